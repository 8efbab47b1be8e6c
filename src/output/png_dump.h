// `--dump-frames DIR --every K`: every Kth frame as DIR/frame_NNNNNN.png (straight alpha, box-
// filtered down from a supersampled canvas), written by a thread of its own. The frame thread
// copies the canvas into a ring (output/frame_ring.h); on the wall clock a full ring drops the
// frame (counted), on the virtual clock it waits. A file that cannot be written is said once
// with its name; later frames are dropped and counted.
#pragma once

#include "output/frame_ring.h"

#include <atomic>
#include <memory>
#include <string>
#include <thread>

namespace mar {

class PngDump {
 public:
  /// `factor`: supersampling (files are width / factor x height / factor).
  PngDump(std::string dir, int width, int height, int factor, bool lossless, size_t slots = 8);
  ~PngDump();
  PngDump(const PngDump&) = delete;
  PngDump& operator=(const PngDump&) = delete;

  /// The frame thread: frame `seq` (its number names the file).
  void push(const uint8_t* rgba, int stride, uint64_t seq, int64_t t_ns);
  /// Writes what is queued.
  void flush();
  uint64_t written() const { return written_.load(); }
  uint64_t dropped() const { return ring_.full() + dropped_.load(); }
  uint64_t waits() const { return ring_.waits(); }
  double waited_us() const { return ring_.waited_us(); }
  std::string error() const { return failed_ ? error_ : ""; }
  /// Wall time the writer spent on a frame (PNG encoding and the file), µs in all.
  double writer_us() const { return writer_us_.load(); }

 private:
  void run();
  std::string dir_;
  int factor_;
  bool lossless_;
  FrameRing ring_;
  std::thread thread_;
  std::atomic<bool> stop_{false}, failed_{false};
  std::atomic<uint64_t> written_{0}, dropped_{0};
  std::atomic<double> writer_us_{0};
  std::string error_;  ///< set by the writer before failed_
};

}  // namespace mar
