#include "output/video_out.h"

#include "render/image.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

#include <chrono>
#include <cmath>

namespace mar {

namespace {

std::string av_error(int e) {
  char buf[AV_ERROR_MAX_STRING_SIZE] = {};
  av_strerror(e, buf, sizeof buf);
  return buf;
}

struct CodecChoice {
  const char* name;     ///< as a take names it
  const char* encoder;  ///< libavcodec's
  AVPixelFormat pix;
};
const CodecChoice kCodecs[] = {
    {"ffv1", "ffv1", AV_PIX_FMT_BGRA},
    {"prores4444", "prores_ks", AV_PIX_FMT_YUVA444P10LE},
    {"h264", "libx264", AV_PIX_FMT_YUV420P},
};

const CodecChoice* find_codec(const std::string& name) {
  for (const CodecChoice& c : kCodecs)
    if (name == c.name) return &c;
  return nullptr;
}

}  // namespace

const char* video_codecs() { return "ffv1, prores4444, h264"; }
bool video_codec_known(const std::string& codec) { return find_codec(codec) != nullptr; }

struct VideoOut::Codec {
  AVFormatContext* fmt = nullptr;
  AVCodecContext* enc = nullptr;
  AVStream* st = nullptr;
  AVFrame* frame = nullptr;
  AVPacket* pkt = nullptr;
  SwsContext* sws = nullptr;
  int w = 0, h = 0;
  ~Codec() {
    sws_freeContext(sws);
    av_packet_free(&pkt);
    av_frame_free(&frame);
    avcodec_free_context(&enc);
    if (fmt && fmt->pb) avio_closep(&fmt->pb);
    avformat_free_context(fmt);
  }
};

Result<std::unique_ptr<VideoOut>> VideoOut::open(const VideoOptions& o) {
  using R = Result<std::unique_ptr<VideoOut>>;
  const CodecChoice* choice = find_codec(o.codec);
  if (!choice) return R::failure("unknown codec '" + o.codec + "'; a video take is one of " + video_codecs());
  std::unique_ptr<VideoOut> v(new VideoOut());
  v->o_ = o;
  v->o_.factor = std::max(1, o.factor);
  auto c = std::make_unique<Codec>();
  c->w = o.width / v->o_.factor;
  c->h = o.height / v->o_.factor;
  if (o.codec == "h264" && (c->w % 2 || c->h % 2))
    return R::failure("h264 needs an even width and height; the canvas is " + std::to_string(c->w) + "x" + std::to_string(c->h) + " (--size)");
  if (avformat_alloc_output_context2(&c->fmt, nullptr, nullptr, o.path.c_str()) < 0 || !c->fmt)
    return R::failure(o.path + ": no container for this file name; end it in .mkv, .mov, .mp4 or .nut");
  const AVCodec* codec = avcodec_find_encoder_by_name(choice->encoder);
  if (!codec) return R::failure(std::string("this libavcodec has no ") + choice->encoder + " encoder for " + o.codec);
  if (avformat_query_codec(c->fmt->oformat, codec->id, FF_COMPLIANCE_NORMAL) != 1)
    return R::failure(o.path + ": a " + c->fmt->oformat->name + " file cannot hold " + o.codec + "; use .mkv");
  c->st = avformat_new_stream(c->fmt, nullptr);
  c->enc = avcodec_alloc_context3(codec);
  if (!c->st || !c->enc) return R::failure(o.path + ": out of memory for the encoder");
  c->enc->width = c->w;
  c->enc->height = c->h;
  c->enc->time_base = AVRational{1, 1000};  // frames at their show times, to the millisecond
  c->enc->pix_fmt = choice->pix;
  if (o.codec == "prores4444") av_opt_set(c->enc->priv_data, "profile", "4444", 0);
  if (o.codec == "h264") {
    av_opt_set(c->enc->priv_data, "crf", "18", 0);
    av_opt_set(c->enc->priv_data, "preset", "veryfast", 0);
  }
  if (c->fmt->oformat->flags & AVFMT_GLOBALHEADER) c->enc->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
  if (int e = avcodec_open2(c->enc, codec, nullptr); e < 0) return R::failure(o.path + ": the " + o.codec + " encoder refused: " + av_error(e));
  if (avcodec_parameters_from_context(c->st->codecpar, c->enc) < 0) return R::failure(o.path + ": the encoder's parameters");
  c->st->time_base = c->enc->time_base;
  if (int e = avio_open(&c->fmt->pb, o.path.c_str(), AVIO_FLAG_WRITE); e < 0) return R::failure(o.path + ": cannot write the video (" + av_error(e) + ")");
  // Matroska holds a cluster in memory until it closes: a cluster a second, so that a disk that
  // fills is noticed within a second (other muxers ignore the option).
  AVDictionary* opts = nullptr;
  av_dict_set(&opts, "cluster_time_limit", "1000", 0);
  const int header = avformat_write_header(c->fmt, &opts);
  av_dict_free(&opts);
  if (header < 0) return R::failure(o.path + ": cannot write the video's header (" + av_error(header) + ")");
  c->frame = av_frame_alloc();
  c->pkt = av_packet_alloc();
  if (!c->frame || !c->pkt) return R::failure(o.path + ": out of memory for the encoder");
  c->frame->format = choice->pix;
  c->frame->width = c->w;
  c->frame->height = c->h;
  if (av_frame_get_buffer(c->frame, 0) < 0) return R::failure(o.path + ": out of memory for a frame");
  // RGBA to BGRA is a shuffle (exact); to YUV, full chroma and accurate rounding.
  const int flags = choice->pix == AV_PIX_FMT_BGRA ? SWS_POINT : SWS_BICUBIC | SWS_ACCURATE_RND | SWS_FULL_CHR_H_INT;
  c->sws = sws_getContext(c->w, c->h, AV_PIX_FMT_RGBA, c->w, c->h, choice->pix, flags, nullptr, nullptr, nullptr);
  if (!c->sws) return R::failure(o.path + ": no conversion from RGBA to the encoder's pixels");
  v->c_ = std::move(c);
  v->ring_ = std::make_unique<FrameRing>(o.width, o.height, o.slots);
  v->thread_ = std::thread([p = v.get()] { p->run(); });
  return R::success(std::move(v));
}

VideoOut::~VideoOut() { finish(); }

void VideoOut::push(const uint8_t* rgba, int stride, uint64_t seq, int64_t t_ns) {
  ++pushed_;
  if (failed_.load(std::memory_order_relaxed)) {
    dropped_.fetch_add(1);
    return;
  }
  ring_->push(rgba, stride, seq, t_ns, o_.lossless, &failed_);
}

void VideoOut::run() {
  while (true) {
    if (ring_->queued()) {
      if (failed_) dropped_.fetch_add(1);
      else encode(&ring_->front());
      ring_->pop();
      continue;
    }
    if (stop_) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

bool VideoOut::encode(const FrameRing::Frame* f) {
  Codec& c = *c_;
  AVFrame* in = nullptr;
  if (f) {
    // Straight alpha, box-filtered down from a supersampled canvas: what --dump-frames writes.
    const Image img = downsample_premultiplied(f->rgba.data(), c.w, c.h, o_.factor);
    if (av_frame_make_writable(c.frame) < 0) return false;
    const uint8_t* src[1] = {img.rgba.data()};
    const int src_stride[1] = {c.w * 4};
    sws_scale(c.sws, src, src_stride, 0, c.h, c.frame->data, c.frame->linesize);
    int64_t pts = std::llround(double(f->t_ns) * 1e-6);
    if (pts <= last_pts_) pts = last_pts_ + 1;  // (two frames within a millisecond)
    last_pts_ = pts;
    c.frame->pts = pts;
    in = c.frame;
  }
  int e = avcodec_send_frame(c.enc, in);
  while (e >= 0) {
    e = avcodec_receive_packet(c.enc, c.pkt);
    if (e == AVERROR(EAGAIN) || e == AVERROR_EOF) break;
    if (e < 0) break;
    if (c.pkt->duration <= 0) c.pkt->duration = std::max<int64_t>(1, std::llround(1000.0 / std::max(1, o_.rate)));  // (ms)
    av_packet_rescale_ts(c.pkt, c.enc->time_base, c.st->time_base);
    c.pkt->stream_index = c.st->index;
    e = av_interleaved_write_frame(c.fmt, c.pkt);
    if (e >= 0 && c.fmt->pb->error < 0) e = c.fmt->pb->error;
  }
  if (e < 0 && e != AVERROR(EAGAIN) && e != AVERROR_EOF) {
    error_ = o_.path + ": writing the video failed (" + av_error(e) + "; a full disk?); later frames are dropped";
    failed_ = true;
    if (f) dropped_.fetch_add(1);
    return false;
  }
  if (f) written_.fetch_add(1);
  return true;
}

bool VideoOut::finish() {
  if (finished_.exchange(true)) return !failed_;
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  if (!c_) return false;
  if (!failed_) encode(nullptr);
  if (!failed_) {
    const int e = av_write_trailer(c_->fmt);
    if (e < 0 || c_->fmt->pb->error < 0) {
      error_ = o_.path + ": writing the video's end failed (" + av_error(e < 0 ? e : c_->fmt->pb->error) + "; a full disk?)";
      failed_ = true;
    }
  }
  avio_flush(c_->fmt->pb);
  if (!failed_ && c_->fmt->pb->error < 0) {
    error_ = o_.path + ": writing the video failed (" + av_error(c_->fmt->pb->error) + "; a full disk?)";
    failed_ = true;
  }
  if (int e = avio_closep(&c_->fmt->pb); e < 0 && !failed_) {
    error_ = o_.path + ": closing the video failed (" + av_error(e) + ")";
    failed_ = true;
  }
  return !failed_;
}

std::string VideoOut::error() const { return failed_ ? error_ : ""; }

}  // namespace mar
