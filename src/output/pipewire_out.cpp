#include "output/pipewire_out.h"

#include <pipewire/pipewire.h>
#include <spa/param/video/format-utils.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <mutex>

namespace mar {

namespace {

int64_t now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return int64_t(ts.tv_sec) * 1000000000 + ts.tv_nsec;
}

constexpr int64_t kRetryNs = 2000000000;  // a daemon that is not there is asked again every 2 s

// Premultiplied RGBA8 to BGRA8, a row.
void rgba_to_bgra(const uint8_t* src, uint8_t* dst, int n) {
  for (int i = 0; i < n; ++i, src += 4, dst += 4) {
    dst[0] = src[2];
    dst[1] = src[1];
    dst[2] = src[0];
    dst[3] = src[3];
  }
}

}  // namespace

struct PipeWireOut::Impl {
  PipeWireOut* self = nullptr;
  pw_thread_loop* loop = nullptr;
  pw_context* context = nullptr;
  pw_core* core = nullptr;
  spa_hook core_listener{};
  pw_stream* stream = nullptr;
  spa_hook stream_listener{};
  spa_source* timer = nullptr;
  // Below: PipeWire's thread, or another holding the loop's lock.
  std::string why = "connecting";
  bool streaming = false, lost = false, said = false;
  int64_t next_try_ns = 0;
  int32_t stride = 0;

  void say(const std::string& what) {
    if (said) return;
    said = true;
    std::fprintf(stderr, "warning: PipeWire video out '%s': %s; frames are dropped until it is there (retried every 2 s)\n",
                 self->o_.node_name.c_str(), what.c_str());
  }

  void drop_queued() { self->dropped_.fetch_add(self->ring_->clear(), std::memory_order_relaxed); }

  void disconnect() {
    if (stream) {
      pw_stream_destroy(stream);
      stream = nullptr;
    }
    if (core) {
      spa_hook_remove(&core_listener);
      pw_core_disconnect(core);
      core = nullptr;
    }
    streaming = false;
  }

  void connect() {
    next_try_ns = now_ns() + kRetryNs;
    core = pw_context_connect(context, nullptr, 0);
    if (!core) {
      const char* dir = std::getenv("XDG_RUNTIME_DIR");
      why = std::string("unconnected: no PipeWire daemon (") + std::strerror(errno) + "; XDG_RUNTIME_DIR " + (dir ? dir : "is not set") + ")";
      say(why.substr(std::strlen("unconnected: ")));
      return;
    }
    static const pw_core_events core_events = [] {
      pw_core_events e{};
      e.version = PW_VERSION_CORE_EVENTS;
      e.error = [](void* data, uint32_t id, int, int res, const char* message) {
        auto* im = static_cast<Impl*>(data);
        if (id == PW_ID_CORE) {  // the daemon went away (or refused us)
          im->lost = true;
          im->why = std::string("unconnected: ") + (message ? message : std::strerror(-res));
        }
      };
      return e;
    }();
    spa_zero(core_listener);
    pw_core_add_listener(core, &core_listener, &core_events, this);

    const PipeWireOptions& o = self->o_;
    pw_properties* props = pw_properties_new(PW_KEY_MEDIA_CLASS, "Video/Source", PW_KEY_NODE_NAME, o.node_name.c_str(),
                                             PW_KEY_NODE_DESCRIPTION, o.description.c_str(), PW_KEY_MEDIA_ROLE, "Camera", nullptr);
    stream = pw_stream_new(core, o.node_name.c_str(), props);
    static const pw_stream_events stream_events = [] {
      pw_stream_events e{};
      e.version = PW_VERSION_STREAM_EVENTS;
      e.state_changed = [](void* data, pw_stream_state, pw_stream_state state, const char* error) {
        auto* im = static_cast<Impl*>(data);
        im->streaming = state == PW_STREAM_STATE_STREAMING;
        if (state == PW_STREAM_STATE_ERROR) {
          im->lost = true;
          im->why = std::string("unconnected: ") + (error ? error : "stream error");
        } else if (state == PW_STREAM_STATE_PAUSED) {
          im->why = "paused";
        } else if (state == PW_STREAM_STATE_STREAMING) {
          im->why = "streaming";
          if (im->said) std::fprintf(stderr, "PipeWire video out '%s': streaming\n", im->self->o_.node_name.c_str());
          im->said = false;
        }
      };
      e.param_changed = [](void* data, uint32_t id, const spa_pod* param) {
        auto* im = static_cast<Impl*>(data);
        if (!param || id != SPA_PARAM_Format) return;
        spa_video_info_raw info{};
        if (spa_format_video_raw_parse(param, &info) < 0) return;
        im->stride = int32_t(info.size.width) * 4;
        uint8_t buf[1024];
        spa_pod_builder b = SPA_POD_BUILDER_INIT(buf, sizeof buf);
        const spa_pod* params[2];
        params[0] = static_cast<const spa_pod*>(spa_pod_builder_add_object(
            &b, SPA_TYPE_OBJECT_ParamBuffers, SPA_PARAM_Buffers, SPA_PARAM_BUFFERS_buffers, SPA_POD_CHOICE_RANGE_Int(4, 2, 16),
            SPA_PARAM_BUFFERS_blocks, SPA_POD_Int(1), SPA_PARAM_BUFFERS_size, SPA_POD_Int(im->stride * int32_t(info.size.height)),
            SPA_PARAM_BUFFERS_stride, SPA_POD_Int(im->stride), SPA_PARAM_BUFFERS_dataType,
            SPA_POD_CHOICE_FLAGS_Int((1 << SPA_DATA_MemPtr) | (1 << SPA_DATA_MemFd))));
        params[1] = static_cast<const spa_pod*>(spa_pod_builder_add_object(&b, SPA_TYPE_OBJECT_ParamMeta, SPA_PARAM_Meta, SPA_PARAM_META_type,
                                                                           SPA_POD_Id(SPA_META_Header), SPA_PARAM_META_size,
                                                                           SPA_POD_Int(sizeof(spa_meta_header))));
        pw_stream_update_params(im->stream, params, 2);
      };
      e.process = [](void* data) { static_cast<Impl*>(data)->process(); };
      return e;
    }();
    spa_zero(stream_listener);
    pw_stream_add_listener(stream, &stream_listener, &stream_events, this);

    uint8_t buf[1024];
    spa_pod_builder b = SPA_POD_BUILDER_INIT(buf, sizeof buf);
    spa_rectangle size = SPA_RECTANGLE(uint32_t(o.width), uint32_t(o.height));
    spa_fraction rate = SPA_FRACTION(uint32_t(o.rate), 1);
    const spa_pod* params[1];
    params[0] = static_cast<const spa_pod*>(spa_pod_builder_add_object(
        &b, SPA_TYPE_OBJECT_Format, SPA_PARAM_EnumFormat, SPA_FORMAT_mediaType, SPA_POD_Id(SPA_MEDIA_TYPE_video),
        SPA_FORMAT_mediaSubtype, SPA_POD_Id(SPA_MEDIA_SUBTYPE_raw), SPA_FORMAT_VIDEO_format, SPA_POD_Id(SPA_VIDEO_FORMAT_BGRA),
        SPA_FORMAT_VIDEO_size, SPA_POD_Rectangle(&size), SPA_FORMAT_VIDEO_framerate, SPA_POD_Fraction(&rate)));
    if (pw_stream_connect(stream, PW_DIRECTION_OUTPUT, PW_ID_ANY, pw_stream_flags(PW_STREAM_FLAG_DRIVER | PW_STREAM_FLAG_MAP_BUFFERS),
                          params, 1) < 0) {
      why = "unconnected: the stream could not connect";
      say("the stream could not connect");
      disconnect();
      return;
    }
    why = "paused";
  }

  // PipeWire's thread, a reader wants a buffer: the newest frame, older ones skipped.
  void process() {
    pw_buffer* pb = pw_stream_dequeue_buffer(stream);
    if (!pb) return;  // the reader holds them all: the frame stays queued
    spa_buffer* sb = pb->buffer;
    FrameRing& ring = *self->ring_;
    auto* dst = static_cast<uint8_t*>(sb->datas[0].data);
    const PipeWireOptions& o = self->o_;
    const int32_t dstride = stride > 0 ? stride : o.width * 4;
    if (ring.queued() == 0 || !dst || sb->datas[0].maxsize < uint32_t(dstride) * uint32_t(o.height)) {
      sb->datas[0].chunk->size = 0;  // nothing new (a follower's cycle): an empty buffer
      pw_stream_queue_buffer(stream, pb);
      return;
    }
    self->dropped_.fetch_add(ring.skip_to_newest(), std::memory_order_relaxed);
    const FrameRing::Frame& s = ring.front();
    for (int y = 0; y < o.height; ++y) rgba_to_bgra(s.rgba.data() + size_t(y) * size_t(o.width) * 4, dst + size_t(y) * size_t(dstride), o.width);
    if (auto* hd = static_cast<spa_meta_header*>(spa_buffer_find_meta_data(sb, SPA_META_Header, sizeof(spa_meta_header)))) {
      hd->pts = s.t_ns;
      hd->flags = 0;
      hd->seq = s.seq;
      hd->dts_offset = 0;
    }
    ring.pop();
    sb->datas[0].chunk->offset = 0;
    sb->datas[0].chunk->size = uint32_t(dstride) * uint32_t(o.height);
    sb->datas[0].chunk->stride = dstride;
    pw_stream_queue_buffer(stream, pb);
    self->sent_.fetch_add(1, std::memory_order_relaxed);
  }

  // PipeWire's thread, at the show's rate: drive the stream when a frame waits; reconnect.
  void tick() {
    if (lost) {
      lost = false;
      say(why.substr(why.find(": ") == std::string::npos ? 0 : why.find(": ") + 2));
      disconnect();
      next_try_ns = now_ns() + kRetryNs;
    }
    if (!stream) {
      drop_queued();
      if (now_ns() >= next_try_ns) connect();
      return;
    }
    if (!streaming) {
      drop_queued();
      return;
    }
    if (self->ring_->queued() && pw_stream_is_driving(stream))
      pw_stream_trigger_process(stream);
  }
};

std::unique_ptr<PipeWireOut> PipeWireOut::open(const PipeWireOptions& o) {
  static std::once_flag once;
  std::call_once(once, [] { pw_init(nullptr, nullptr); });
  std::unique_ptr<PipeWireOut> p(new PipeWireOut());
  p->o_ = o;
  p->o_.rate = std::max(1, o.rate);
  p->ring_ = std::make_unique<FrameRing>(o.width, o.height, o.slots);
  p->impl_ = std::make_unique<Impl>();
  Impl& im = *p->impl_;
  im.self = p.get();
  im.loop = pw_thread_loop_new("marionette-pipewire", nullptr);
  im.context = pw_context_new(pw_thread_loop_get_loop(im.loop), nullptr, 0);
  im.timer = pw_loop_add_timer(pw_thread_loop_get_loop(im.loop), [](void* data, uint64_t) { static_cast<Impl*>(data)->tick(); }, &im);
  pw_thread_loop_start(im.loop);
  pw_thread_loop_lock(im.loop);
  im.connect();
  const long period = 1000000000L / p->o_.rate;
  timespec first{0, 1}, every{period / 1000000000L, period % 1000000000L};
  pw_loop_update_timer(pw_thread_loop_get_loop(im.loop), im.timer, &first, &every, false);
  pw_thread_loop_unlock(im.loop);
  return p;
}

PipeWireOut::~PipeWireOut() {
  if (!impl_) return;
  Impl& im = *impl_;
  pw_thread_loop_lock(im.loop);
  pw_loop_destroy_source(pw_thread_loop_get_loop(im.loop), im.timer);
  im.disconnect();
  pw_thread_loop_unlock(im.loop);
  pw_thread_loop_stop(im.loop);
  pw_context_destroy(im.context);
  pw_thread_loop_destroy(im.loop);
}

void PipeWireOut::push(const uint8_t* rgba, int stride, uint64_t seq, int64_t t_ns) {
  pushed_.fetch_add(1, std::memory_order_relaxed);
  ring_->push(rgba, stride, seq, t_ns);  // a full ring drops it (counted)
}

std::string PipeWireOut::state() const {
  if (!impl_) return "unconnected";
  pw_thread_loop_lock(impl_->loop);
  std::string s = impl_->why;
  pw_thread_loop_unlock(impl_->loop);
  return s;
}

}  // namespace mar
