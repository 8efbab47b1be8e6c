// `run --dump-poses FILE.jsonl`: every frame's deformed shapes, one JSON line a frame —
//   {"t": seconds, "subshapes": [{"id": "...", "points": [[x, y], ...]}, ...]}
// in the loader's order; a shape not drawn that frame (a swap member not chosen, a trigger's
// shape while it is off, a hidden alternative) carries "shown": false — for tests, benchmarks and other tools that read motion. The frame
// thread copies the points into a slot of a ring made at open (no allocation, no lock) and a
// writer thread of its own formats and writes them. On the wall clock a full ring drops the
// frame (counted: the show never waits on a disk); on the virtual clock (headless, replays)
// nothing is dropped: the frame waits for a free slot, which costs wall time only.
#pragma once

#include "character/character.h"
#include "base/result.h"

#include <atomic>
#include <cstdio>
#include <memory>
#include <span>
#include <string>
#include <thread>
#include <vector>

namespace mar {

class PoseDump {
 public:
  /// Opens (truncates) `path` for the shapes of `ch` (their point counts are fixed from here).
  /// `lossless`: wait for room rather than drop. Errors name the file.
  static Result<std::unique_ptr<PoseDump>> open(const std::string& path, const Character& ch, bool lossless, size_t slots = 64);
  /// Writes what is queued, then closes the file.
  ~PoseDump();
  PoseDump(const PoseDump&) = delete;
  PoseDump& operator=(const PoseDump&) = delete;

  /// Queues one frame at show time `t` seconds (shapes in the character's order, each the size
  /// it had at open) and, when given, whether each shows (0: not drawn this frame). No
  /// allocation, no lock.
  void push(double t, std::span<const Points> shapes, std::span<const char> shown = {});
  /// Finishes writing what is queued (the writer keeps running).
  void flush();
  uint64_t written() const { return written_.load(); }
  uint64_t dropped() const { return dropped_; }
  /// Frames that waited for a free slot (lossless only).
  uint64_t waits() const { return waits_; }
  /// A write error (the disk is full...), naming the file; empty when none.
  std::string error() const;

 private:
  PoseDump() = default;
  void run();
  struct Slot {
    double t = 0;
    std::vector<Vec2> points;  ///< every shape's, concatenated
    std::vector<char> shown;   ///< per shape
  };
  std::string path_;
  std::FILE* file_ = nullptr;
  std::vector<std::string> ids_;  ///< JSON-escaped
  std::vector<size_t> counts_;
  std::vector<Slot> slots_;
  std::atomic<uint64_t> head_{0}, tail_{0};  ///< written by the frame thread / the writer
  std::atomic<uint64_t> written_{0};
  std::atomic<bool> stop_{false}, failed_{false};
  bool lossless_ = false;
  int errno_ = 0;  ///< the failed write's, set by the writer before failed_
  uint64_t dropped_ = 0, waits_ = 0;
  std::thread writer_;
};

}  // namespace mar
