#include "app/loop/recording.h"

#include "input/read_file.h"

#include <cstring>

namespace mar {
namespace {

constexpr char kMagic[8] = {'M', 'A', 'R', 'R', 'E', 'C', '0', '2'};
constexpr uint8_t kWire = 1, kFrame = 2, kDevice = 3;

void put(const void* p, size_t n, std::FILE* f) { fwrite_unlocked(p, 1, n, f); }
template <class T>
bool get(T& v, std::FILE* f) {
  return std::fread(&v, sizeof(T), 1, f) == 1;
}

}  // namespace

Result<std::unique_ptr<Recorder>> Recorder::open(const std::string& path) {
  using R = Result<std::unique_ptr<Recorder>>;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return R::failure(path + ": cannot write the recording");
  std::setvbuf(f, nullptr, _IOFBF, 1 << 20);
  std::fwrite(kMagic, 1, 8, f);
  return R::success(std::unique_ptr<Recorder>(new Recorder(f)));
}

Recorder::~Recorder() { std::fclose(f_); }

void Recorder::wire(const WireRecord& r) {
  put(&kWire, 1, f_);
  put(&r.t_ns, 8, f_);
  put(&r.source, 2, f_);
  put(&r.kind, 1, f_);
  put(&r.size, 1, f_);
  put(r.data, r.size, f_);
}

void Recorder::device(uint16_t source, std::span<const uint8_t> d) {
  const uint32_t n = uint32_t(d.size());
  put(&kDevice, 1, f_);
  put(&source, 2, f_);
  put(&n, 4, f_);
  put(d.data(), n, f_);
}

void Recorder::frame(int64_t t_ns, int iterations) {
  const uint16_t it = uint16_t(iterations);
  put(&kFrame, 1, f_);
  put(&t_ns, 8, f_);
  put(&it, 2, f_);
}

void Recorder::flush() { std::fflush(f_); }

Result<std::unique_ptr<Playback>> Playback::open(const std::string& path) {
  using R = Result<std::unique_ptr<Playback>>;
  // A take is read as it plays: checked first as every outside file is, so a FIFO or a device
  // named as a take is refused rather than waited on.
  if (std::string why = file_problem(path, kMaxTakeBytes, "a take"); !why.empty()) return R::failure(why);
  std::FILE* f = std::fopen(path.c_str(), "rb");
  char magic[8] = {};
  if (!f || std::fread(magic, 1, 8, f) != 8 || std::memcmp(magic, kMagic, 6) != 0) {
    if (f) std::fclose(f);
    return R::failure(path + ": not a marionette recording");
  }
  if (std::memcmp(magic, kMagic, 8) != 0) {
    std::fclose(f);
    return R::failure(path + ": a recording of an older marionette (" + std::string(magic, 8) +
                      "); record it again with this one");
  }
  return R::success(std::unique_ptr<Playback>(new Playback(f)));
}

Playback::~Playback() { std::fclose(f_); }

bool Playback::next_frame(std::vector<WireRecord>& wires, int64_t& t_ns, int& iterations, const OnDevice& on_device) {
  wires.clear();
  for (;;) {
    uint8_t type = 0;
    if (!get(type, f_)) return false;
    if (type == kFrame) {
      uint16_t it = 0;
      if (!get(t_ns, f_) || !get(it, f_)) return false;
      iterations = it;
      return true;
    }
    if (type == kDevice) {
      uint16_t src = 0;
      uint32_t n = 0;
      if (!get(src, f_) || !get(n, f_) || n > kMaxDescriptionBytes) return false;
      description_.resize(n);
      if (std::fread(description_.data(), 1, n, f_) != n) return false;
      on_device(src, description_);
      continue;
    }
    WireRecord r;
    if (type != kWire || !get(r.t_ns, f_) || !get(r.source, f_) || !get(r.kind, f_) || !get(r.size, f_) ||
        r.size > WireRecord::kMax || std::fread(r.data, 1, r.size, f_) != r.size || wires.size() == kMaxFrameRecords)
      return false;
    wires.push_back(r);
  }
}

}  // namespace mar
