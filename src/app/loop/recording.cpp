#include "app/loop/recording.h"

#include "app/show.h"
#include "base/read_file.h"

#include <array>
#include <cerrno>
#include <cstring>

namespace mar {
namespace {

constexpr char kMagic[8] = {'M', 'A', 'R', 'R', 'E', 'C', '0', '3'};
constexpr uint8_t kWire = 1, kFrame = 2, kDevice = 3;
// A block is written once it holds 64 frames or 64 KiB: a damaged or cut take loses at most
// about a second at 60 Hz (the file's stdio buffer batches the disk writes).
constexpr size_t kBlockTarget = 64u << 10;
constexpr int kBlockFrames = 64;

std::array<uint32_t, 256> crc_table() {
  std::array<uint32_t, 256> t{};
  for (uint32_t i = 0; i < 256; ++i) {
    uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    t[i] = c;
  }
  return t;
}

}  // namespace

uint32_t crc32(std::span<const uint8_t> bytes, uint32_t crc) {
  static const std::array<uint32_t, 256> table = crc_table();
  crc = ~crc;
  for (uint8_t b : bytes) crc = table[(crc ^ b) & 0xFF] ^ (crc >> 8);
  return ~crc;
}

uint64_t show_identity(const ShowConfig& show) {
  uint64_t h = 1469598103934665603ull;  // FNV-1a over each device's name, type and simulator
  const auto mix = [&h](const std::string& s) {
    for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
    h = (h ^ 0xFF) * 1099511628211ull;  // a separator no name holds
  };
  for (const ShowDevice& d : show.devices) {
    mix(d.name);
    mix(d.type);
    mix(d.sim);
  }
  return h;
}

// ---- Recorder ------------------------------------------------------------------------

Result<std::unique_ptr<Recorder>> Recorder::open(const std::string& path, uint64_t identity) {
  using R = Result<std::unique_ptr<Recorder>>;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return R::failure(path + ": cannot write the recording (" + std::strerror(errno) + ")");
  std::setvbuf(f, nullptr, _IOFBF, 1 << 20);
  std::unique_ptr<Recorder> r(new Recorder(f, path));
  r->block_.reserve(2 * kBlockTarget + (1u << 20));
  uint8_t header[20];
  std::memcpy(header, kMagic, 8);
  std::memcpy(header + 8, &identity, 8);
  const uint32_t crc = crc32(std::span<const uint8_t>(header, 16));
  std::memcpy(header + 16, &crc, 4);
  if (std::fwrite(header, 1, sizeof header, f) != sizeof header || std::fflush(f) != 0)
    return R::failure(path + ": cannot write the recording (" + std::strerror(errno) + ")");
  return R::success(std::move(r));
}

Recorder::~Recorder() {
  flush();
  std::fclose(f_);
}

void Recorder::put(const void* p, size_t n) {
  const auto* b = static_cast<const uint8_t*>(p);
  block_.insert(block_.end(), b, b + n);
}

void Recorder::wire(const WireRecord& r) {
  put(&kWire, 1);
  put(&r.t_ns, 8);
  put(&r.source, 2);
  put(&r.kind, 1);
  put(&r.size, 1);
  put(r.data, r.size);
}

void Recorder::device(uint16_t source, std::span<const uint8_t> d) {
  const uint32_t n = uint32_t(d.size());
  put(&kDevice, 1);
  put(&source, 2);
  put(&n, 4);
  put(d.data(), n);
}

void Recorder::frame(int64_t t_ns, int iterations) {
  const uint16_t it = uint16_t(iterations);
  put(&kFrame, 1);
  put(&t_ns, 8);
  put(&it, 2);
  if (++block_frames_ >= kBlockFrames || block_.size() >= kBlockTarget) write_block();
}

void Recorder::write_block() {
  if (block_.empty()) return;
  const uint32_t head[2] = {uint32_t(block_.size()), crc32(block_)};
  // After a failed write nothing more is written: a take with a hole would play wrong.
  if (error_.empty() && (fwrite_unlocked(head, 1, sizeof head, f_) != sizeof head ||
                         fwrite_unlocked(block_.data(), 1, block_.size(), f_) != block_.size()))
    error_ = path_ + ": " + std::strerror(errno);
  block_.clear();
  block_frames_ = 0;
}

bool Recorder::flush() {
  write_block();
  if (error_.empty() && std::fflush(f_) != 0) error_ = path_ + ": " + std::strerror(errno);
  return error_.empty();
}

// ---- Playback ------------------------------------------------------------------------

Result<std::unique_ptr<Playback>> Playback::open(const std::string& path) {
  using R = Result<std::unique_ptr<Playback>>;
  // A take is read as it plays: checked first as every outside file is, so a FIFO or a device
  // named as a take is refused rather than waited on.
  if (std::string why = file_problem(path, kMaxTakeBytes, "a take"); !why.empty()) return R::failure(why);
  std::FILE* f = std::fopen(path.c_str(), "rb");
  uint8_t header[20] = {};
  const size_t got = f ? std::fread(header, 1, sizeof header, f) : 0;
  const auto fail = [&](const std::string& why) {
    if (f) std::fclose(f);
    return R::failure(path + ": " + why);
  };
  if (got < 8 || std::memcmp(header, kMagic, 6) != 0) return fail("not a marionette recording");
  if (std::memcmp(header, kMagic, 8) != 0)
    return fail("a recording of an older marionette (" + std::string(reinterpret_cast<char*>(header), 8) +
                "); record it again with this one");
  uint32_t crc = 0;
  std::memcpy(&crc, header + 16, 4);
  if (got < sizeof header || crc != crc32(std::span<const uint8_t>(header, 16))) return fail("damaged header (checksum)");
  uint64_t identity = 0;
  std::memcpy(&identity, header + 8, 8);
  std::unique_ptr<Playback> p(new Playback(f, path, identity));
  p->block_start_ = sizeof header;
  // A frame of a live show holds at most 4,096 records (about 440 KB) and a block 64 frames or
  // 64 KiB past a frame: reserved once, so a replayed frame allocates nothing (a larger block
  // in a take, up to kMaxBlockBytes, grows it).
  p->block_.reserve(2u << 20);
  return R::success(std::move(p));
}

Playback::~Playback() { std::fclose(f_); }

bool Playback::damaged(const std::string& what) {
  if (damage_.empty())
    damage_ = path_ + ": damaged at byte " + std::to_string(block_start_) + " (" + what + "); played to frame " +
              std::to_string(frames_);
  block_.clear();
  at_ = 0;
  return false;
}

bool Playback::next_block() {
  if (!damage_.empty()) return false;
  block_start_ += block_.empty() ? 0 : block_.size() + 8;
  block_.clear();
  at_ = 0;
  uint32_t head[2];
  const size_t got = std::fread(head, 1, sizeof head, f_);
  if (got == 0 && std::feof(f_)) return false;  // the clean end
  if (got != sizeof head) return damaged("cut short");
  if (head[0] == 0 || head[0] > kMaxBlockBytes) return damaged("block length " + std::to_string(head[0]));
  block_.resize(head[0]);
  if (std::fread(block_.data(), 1, head[0], f_) != head[0]) return damaged("cut short");
  if (crc32(block_) != head[1]) return damaged("checksum");
  return true;
}

bool Playback::get_bytes(void* out, size_t n) {
  if (n == 0) return true;  // (an empty description: its buffer may be null, which memcpy may not take)
  if (block_.size() - at_ < n) return false;
  std::memcpy(out, block_.data() + at_, n);
  at_ += n;
  return true;
}

template <class T>
bool Playback::get(T& v) {
  return get_bytes(&v, sizeof(T));
}

bool Playback::next_frame(std::vector<WireRecord>& wires, int64_t& t_ns, int& iterations, const OnDevice& on_device) {
  wires.clear();
  // A block holds whole frames: a frame is never split across two.
  if (at_ == block_.size() && !next_block()) return false;
  for (;;) {
    uint8_t type = 0;
    if (!get(type)) return damaged("a frame runs past its block");
    if (type == kFrame) {
      uint16_t it = 0;
      if (!get(t_ns) || !get(it)) return damaged("a frame runs past its block");
      if (it < 1 || it > kMaxIterations)
        return damaged(std::to_string(it) + " solver iterations in a frame; a show asks for 1 to " +
                       std::to_string(kMaxIterations));
      iterations = it;
      ++frames_;
      return true;
    }
    if (type == kDevice) {
      uint16_t src = 0;
      uint32_t n = 0;
      if (!get(src) || !get(n) || n > kMaxDescriptionBytes) return damaged("a device description");
      description_.resize(n);
      if (!get_bytes(description_.data(), n)) return damaged("a device description");
      on_device(src, description_);
      continue;
    }
    WireRecord r;
    if (type != kWire) return damaged("record type " + std::to_string(type));
    if (!get(r.t_ns) || !get(r.source) || !get(r.kind) || !get(r.size) || r.size > WireRecord::kMax ||
        !get_bytes(r.data, r.size))
      return damaged("a wire record");
    if (wires.size() == kMaxFrameRecords) return damaged("more than 65,536 records in a frame");
    wires.push_back(r);
  }
}

}  // namespace mar
