// `[output] pipewire = true`: the canvas published as a PipeWire video source (libpipewire-0.3),
// a `Video/Source` node any PipeWire client can read — OBS's "Screen Capture (PipeWire)"/video
// capture source, GStreamer's pipewiresrc, a browser. BGRA with premultiplied alpha, the canvas's
// size, at the show's rate; each buffer's header carries the show's frame number (seq) and show
// time (pts, ns).
//
// The frame thread only copies the canvas into a slot of a ring made at open (no allocation, no
// lock, no system call). A thread of PipeWire's own (pw_thread_loop) drives the stream on a timer
// at the show's rate and sends the newest frame it has; older ones it skips and counts. A reader
// that is slow or absent drops frames (counted), never the show. A daemon that is not there, or
// dies, is said once and retried every two seconds; frames meanwhile are dropped and counted.
#pragma once

#include "output/frame_ring.h"

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace mar {

struct PipeWireOptions {
  std::string node_name;    ///< node.name (what pipewiresrc's target-object names)
  std::string description;  ///< node.description (what OBS lists)
  int width = 0, height = 0;
  int rate = 60;            ///< frames a second
  size_t slots = 3;
};

class PipeWireOut {
 public:
  /// Starts PipeWire's thread and asks the daemon for the stream (it connects in the
  /// background: a daemon that is not there is not an error here, see state()).
  static std::unique_ptr<PipeWireOut> open(const PipeWireOptions& o);
  ~PipeWireOut();
  PipeWireOut(const PipeWireOut&) = delete;
  PipeWireOut& operator=(const PipeWireOut&) = delete;

  /// The frame thread: one canvas frame, premultiplied RGBA8 rows `stride` bytes apart (the
  /// options' size), with its frame number and show time. A full ring drops it (counted).
  void push(const uint8_t* rgba, int stride, uint64_t seq, int64_t t_ns);

  uint64_t pushed() const { return pushed_.load(std::memory_order_relaxed); }
  /// Frames a reader received.
  uint64_t sent() const { return sent_.load(std::memory_order_relaxed); }
  /// Frames no reader took: the ring full, skipped for a newer one, or nobody streaming.
  uint64_t dropped() const { return dropped_.load(std::memory_order_relaxed) + (ring_ ? ring_->full() : 0); }
  /// "connecting", "paused" (published, no reader), "streaming", "unconnected: WHY".
  std::string state() const;
  const std::string& node_name() const { return o_.node_name; }

  struct Impl;

 private:
  PipeWireOut() = default;
  friend struct Impl;
  PipeWireOptions o_;
  std::unique_ptr<FrameRing> ring_;
  std::atomic<uint64_t> pushed_{0}, sent_{0}, dropped_{0};
  std::unique_ptr<Impl> impl_;
};

}  // namespace mar
