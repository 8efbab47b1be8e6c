// Recordings (`--record`, `replay`): every source's wire records as read, each connection's
// description (the serialized DecoderConfig, before that connection's first record) and a
// marker per frame with its time and iteration count. Format MARREC02, native byte order:
//   "MARREC02", then records: 1 wire (i64 t_ns, u16 source, u8 kind, u8 size, bytes),
//   2 frame (i64 t_ns, u16 iterations), 3 device (u16 source, u32 length, bytes).
#pragma once

#include "geom/result.h"
#include "input/wire.h"

#include <cstdio>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace mar {

class Recorder {
 public:
  static Result<std::unique_ptr<Recorder>> open(const std::string& path);
  ~Recorder();
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;
  // Frame thread: into a 1 MiB stdio buffer without the FILE lock (only this thread writes);
  // the buffer goes to disk when full, the one place a recorded show touches the disk in a frame.
  void wire(const WireRecord& r);
  void device(uint16_t source, std::span<const uint8_t> description);
  void frame(int64_t t_ns, int iterations);
  void flush();

 private:
  explicit Recorder(std::FILE* f) : f_(f) {}
  std::FILE* f_;
};

class Playback {
 public:
  /// Opens a recording; an error for a file that is not one (or an older format).
  static Result<std::unique_ptr<Playback>> open(const std::string& path);
  ~Playback();
  Playback(const Playback&) = delete;
  Playback& operator=(const Playback&) = delete;
  using OnDevice = std::function<void(uint16_t source, std::span<const uint8_t> description)>;
  /// Limits of a recording: a device description up to 1 MiB, a frame up to 65,536 wire records
  /// (a live frame reads at most 4,096), each up to WireRecord::kMax bytes; past one is damage.
  static constexpr uint32_t kMaxDescriptionBytes = 1u << 20;
  static constexpr size_t kMaxFrameRecords = 65536;
  /// Reads the records of the next frame: wire records into `wires` (cleared first), device
  /// descriptions through `on_device` as they come; the frame's time and iteration count.
  /// False at the end of the recording or at a damaged record (what was read stays played).
  bool next_frame(std::vector<WireRecord>& wires, int64_t& t_ns, int& iterations, const OnDevice& on_device);

 private:
  explicit Playback(std::FILE* f) : f_(f) {}
  std::FILE* f_;
  std::vector<uint8_t> description_;
};

}  // namespace mar
