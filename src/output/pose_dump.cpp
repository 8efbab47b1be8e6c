#include "output/pose_dump.h"

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>

namespace mar {

namespace {

std::string json_string(const std::string& s) {
  std::string o = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      o += '\\';
      o += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", unsigned(static_cast<unsigned char>(c)));
      o += buf;
    } else {
      o += c;
    }
  }
  return o + "\"";
}

}  // namespace

Result<std::unique_ptr<PoseDump>> PoseDump::open(const std::string& path, const Character& ch, bool lossless, size_t slots) {
  using R = Result<std::unique_ptr<PoseDump>>;
  std::unique_ptr<PoseDump> d(new PoseDump());
  d->path_ = path;
  d->file_ = std::fopen(path.c_str(), "wb");
  if (!d->file_) return R::failure(path + ": cannot write the pose dump (" + std::strerror(errno) + ")");
  size_t total = 0;
  for (const SubShape& s : ch.shapes) {
    d->ids_.push_back(json_string(s.id));
    d->counts_.push_back(s.points.size());
    total += s.points.size();
  }
  d->slots_.resize(std::max<size_t>(2, slots));
  for (Slot& s : d->slots_) {
    s.points.resize(total);
    s.shown.resize(ch.shapes.size(), 1);
  }
  d->lossless_ = lossless;
  d->writer_ = std::thread([p = d.get()] { p->run(); });
  return R::success(std::move(d));
}

PoseDump::~PoseDump() {
  stop_ = true;
  if (writer_.joinable()) writer_.join();
  if (file_) std::fclose(file_);
}

void PoseDump::push(double t, std::span<const Points> shapes, std::span<const char> shown) {
  const uint64_t h = head_.load(std::memory_order_relaxed);
  if (h - tail_.load(std::memory_order_acquire) >= slots_.size()) {
    if (!lossless_ || failed_) {
      ++dropped_;
      return;
    }
    ++waits_;
    while (h - tail_.load(std::memory_order_acquire) >= slots_.size() && !failed_) std::this_thread::yield();
    if (failed_) {
      ++dropped_;
      return;
    }
  }
  Slot& s = slots_[h % slots_.size()];
  s.t = t;
  size_t at = 0;
  for (size_t k = 0; k < counts_.size(); ++k)
    for (size_t i = 0; i < counts_[k]; ++i, ++at) s.points[at] = k < shapes.size() && i < shapes[k].size() ? shapes[k][i] : Vec2(NAN, NAN);
  for (size_t k = 0; k < s.shown.size(); ++k) s.shown[k] = k < shown.size() ? shown[k] : 1;
  head_.store(h + 1, std::memory_order_release);
}

void PoseDump::flush() {
  while (tail_.load(std::memory_order_acquire) != head_.load(std::memory_order_acquire) && !failed_)
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  if (file_ && std::fflush(file_) != 0 && !failed_) {
    errno_ = errno;
    failed_ = true;
  }
}

std::string PoseDump::error() const {
  return failed_ ? path_ + ": " + (errno_ ? std::strerror(errno_) : "write failed") + "; later frames are dropped" : "";
}

void PoseDump::run() {
  // A coordinate is written in full: %.3f of 1e308 is 313 characters, two of them a point.
  char num[800];
  while (true) {
    const uint64_t t = tail_.load(std::memory_order_relaxed);
    if (t == head_.load(std::memory_order_acquire)) {
      if (stop_) break;
      std::this_thread::sleep_for(std::chrono::microseconds(500));
      continue;
    }
    const Slot& s = slots_[t % slots_.size()];
    bool ok = true;
    std::snprintf(num, sizeof num, "%.6f", s.t);
    ok = ok && std::fputs("{\"t\": ", file_) >= 0 && std::fputs(num, file_) >= 0 && std::fputs(", \"subshapes\": [", file_) >= 0;
    size_t at = 0;
    for (size_t k = 0; k < counts_.size() && ok; ++k) {
      ok = std::fputs(k ? ", {\"id\": " : "{\"id\": ", file_) >= 0 && std::fputs(ids_[k].c_str(), file_) >= 0 &&
           std::fputs(", \"points\": [", file_) >= 0;
      for (size_t i = 0; i < counts_[k] && ok; ++i, ++at) {
        const Vec2& p = s.points[at];
        if (p.allFinite()) std::snprintf(num, sizeof num, "%s[%.3f, %.3f]", i ? ", " : "", p.x(), p.y());
        else std::snprintf(num, sizeof num, "%s[null, null]", i ? ", " : "");
        ok = std::fputs(num, file_) >= 0;
      }
      ok = ok && std::fputs(s.shown[k] ? "]}" : "], \"shown\": false}", file_) >= 0;
    }
    ok = ok && std::fputs("]}\n", file_) >= 0;
    if (!ok) {
      errno_ = errno;
      failed_ = true;
      tail_.store(head_.load(std::memory_order_acquire), std::memory_order_release);
      break;
    }
    written_.fetch_add(1);
    tail_.store(t + 1, std::memory_order_release);
  }
  if (std::fflush(file_) != 0 && !failed_) {
    errno_ = errno;
    failed_ = true;
  }
}

}  // namespace mar
