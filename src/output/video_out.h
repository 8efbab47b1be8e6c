// Video takes (libavcodec, libavformat): `run --video OUT.mkv` and `replay TAKE --video OUT.mkv`
// write the show's canvas to a file, each frame at its show time. Codecs:
//   ffv1        lossless, BGRA with alpha (the default): decoded, each frame is byte-identical to
//               the show's --dump-frames PNG of it
//   prores4444  ProRes 4444 (prores_ks), 10-bit 4:4:4 with alpha, for editors
//   h264        H.264 (libx264, CRF 18, yuv420p): small, no alpha
// The container follows the file's extension (.mkv, .mov, .mp4, .nut). Alpha is stored straight
// (not premultiplied), as video files expect; the frame at N x supersampling is box-filtered down
// first, as dumps are.
//
// The frame thread only copies the canvas into a ring (output/frame_ring.h); a thread of its own
// converts and encodes. On the wall clock a full ring drops the frame (counted: the show never
// waits on an encoder); on the virtual clock (headless, replays) nothing is dropped. A write that
// fails (a full disk) is said once with the file's name; later frames are dropped and counted.
#pragma once

#include "base/result.h"
#include "output/frame_ring.h"

#include <atomic>
#include <memory>
#include <string>
#include <thread>

namespace mar {

struct VideoOptions {
  std::string path;
  std::string codec = "ffv1";
  int width = 0, height = 0;  ///< the canvas's
  int factor = 1;             ///< supersampling: the file is width / factor x height / factor
  int rate = 60;              ///< the show's: a frame's duration (the last one's too)
  bool lossless = false;      ///< wait for the encoder rather than drop (the virtual clock)
  size_t slots = 8;
};

/// The codecs a take may name, for messages: "ffv1, prores4444, h264".
const char* video_codecs();
bool video_codec_known(const std::string& codec);

class VideoOut {
 public:
  /// Opens the file and the encoder. Errors name the file or the codec.
  static Result<std::unique_ptr<VideoOut>> open(const VideoOptions& o);
  /// Finishes (finish()) if not done.
  ~VideoOut();
  VideoOut(const VideoOut&) = delete;
  VideoOut& operator=(const VideoOut&) = delete;

  /// The frame thread: one canvas frame (premultiplied RGBA8, rows `stride` bytes apart).
  void push(const uint8_t* rgba, int stride, uint64_t seq, int64_t t_ns);
  /// Encodes what is queued, flushes the encoder and writes the file's end. Returns false when
  /// the file could not be written (error() says why).
  bool finish();

  uint64_t pushed() const { return pushed_; }
  uint64_t written() const { return written_.load(); }
  uint64_t dropped() const { return ring_->full() + dropped_.load(); }
  uint64_t waits() const { return ring_->waits(); }
  double waited_us() const { return ring_->waited_us(); }
  std::string error() const;
  const VideoOptions& options() const { return o_; }

  struct Codec;

 private:
  VideoOut() = default;
  void run();
  bool encode(const FrameRing::Frame* f);  ///< nullptr: flush
  VideoOptions o_;
  std::unique_ptr<FrameRing> ring_;
  std::unique_ptr<Codec> c_;
  std::thread thread_;
  std::atomic<bool> stop_{false}, failed_{false}, finished_{false};
  std::atomic<uint64_t> written_{0}, dropped_{0};
  uint64_t pushed_ = 0;
  std::string error_;  ///< set by the encoder's thread before failed_
  int64_t last_pts_ = -1;
};

}  // namespace mar
