// Recordings (`--record`, `replay`): every source's wire records as read, each connection's
// description (the serialized DecoderConfig, before that connection's first record) and a
// marker per frame with its time and iteration count. Format MARREC03, native byte order:
//   header: "MARREC03", u64 the show's identity (show_identity()), u32 CRC-32 of those 16 bytes;
//   then blocks: u32 length, u32 CRC-32 of the payload, payload (whole frames of records):
//   1 wire (i64 t_ns, u16 source, u8 kind, u8 size, bytes), 2 frame (i64 t_ns, u16 iterations),
//   3 device (u16 source, u32 length, bytes).
// A damaged take (a cut file, a flipped bit, a count no show may ask for) is found at the block
// that holds the damage; what came before it plays, and the damage is said.
#pragma once

#include "base/result.h"
#include "input/wire.h"

#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace mar {

struct ShowConfig;

/// A show's identity in its takes: its devices' names and kinds, in order. A take drives the
/// devices by their position, so a take of a show with other devices is another show's take;
/// an edit of bindings, poses or the rig keeps the identity (a take recorded before stays good).
uint64_t show_identity(const ShowConfig& show);

/// CRC-32 (IEEE 802.3, as zlib's crc32) of `bytes`, continuing from `crc`.
uint32_t crc32(std::span<const uint8_t> bytes, uint32_t crc = 0);

class Recorder {
 public:
  static Result<std::unique_ptr<Recorder>> open(const std::string& path, uint64_t identity);
  ~Recorder();
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;
  // Frame thread: records go into a block buffer reserved at open; every 64 frames (or 64 KiB)
  // the block goes into a 1 MiB stdio buffer, which goes to disk when full: the one place a
  // recorded show touches the disk in a frame.
  void wire(const WireRecord& r);
  void device(uint16_t source, std::span<const uint8_t> description);
  void frame(int64_t t_ns, int iterations);
  /// Writes what is buffered and flushes the file; false (and error()) when any write failed.
  bool flush();
  /// Empty while every write succeeded, else the first failure ("take.mrec: No space left on device").
  const std::string& error() const { return error_; }

 private:
  Recorder(std::FILE* f, std::string path) : f_(f), path_(std::move(path)) {}
  void put(const void* p, size_t n);
  void write_block();
  std::FILE* f_;
  std::string path_;
  std::vector<uint8_t> block_;
  int block_frames_ = 0;
  std::string error_;
};

class Playback {
 public:
  /// Opens a recording; an error for a file that is not one (or an older format, or a
  /// damaged header).
  static Result<std::unique_ptr<Playback>> open(const std::string& path);
  ~Playback();
  Playback(const Playback&) = delete;
  Playback& operator=(const Playback&) = delete;
  using OnDevice = std::function<void(uint16_t source, std::span<const uint8_t> description)>;
  /// Limits of a recording: a device description up to 1 MiB, a frame up to 65,536 wire records
  /// (a live frame reads at most 4,096), each up to WireRecord::kMax bytes, a block up to 64 MiB,
  /// a frame's iterations 1..kMaxIterations (what a show may ask); past one is damage.
  static constexpr uint32_t kMaxDescriptionBytes = 1u << 20;
  static constexpr size_t kMaxFrameRecords = 65536;
  static constexpr uint32_t kMaxBlockBytes = 64u << 20;
  static constexpr int kMaxIterations = 200;
  /// Reads the records of the next frame: wire records into `wires` (cleared first), device
  /// descriptions through `on_device` as they come; the frame's time and iteration count.
  /// False at the end of the recording or at damage (what was read stays played; damage()).
  bool next_frame(std::vector<WireRecord>& wires, int64_t& t_ns, int& iterations, const OnDevice& on_device);
  /// The identity of the show it was recorded with (show_identity()).
  uint64_t identity() const { return identity_; }
  /// Empty at a clean end, else what is damaged and where ("take.mrec: damaged at byte 4096
  /// (checksum); played to frame 82").
  const std::string& damage() const { return damage_; }

 private:
  Playback(std::FILE* f, std::string path, uint64_t identity) : f_(f), path_(std::move(path)), identity_(identity) {}
  bool next_block();
  bool damaged(const std::string& what);
  template <class T>
  bool get(T& v);
  bool get_bytes(void* out, size_t n);
  std::FILE* f_;
  std::string path_;
  uint64_t identity_;
  std::vector<uint8_t> block_;
  size_t at_ = 0;          // read position in block_
  uint64_t block_start_ = 0;  // the block's offset in the file
  long frames_ = 0;
  std::vector<uint8_t> description_;
  std::string damage_;
};

}  // namespace mar
