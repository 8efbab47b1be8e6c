#include "output/png_dump.h"

#include "render/image.h"

#include <chrono>
#include <cstdio>
#include <filesystem>

namespace mar {

PngDump::PngDump(std::string dir, int width, int height, int factor, bool lossless, size_t slots)
    : dir_(std::move(dir)), factor_(std::max(1, factor)), lossless_(lossless), ring_(width, height, slots) {
  thread_ = std::thread([this] { run(); });
}

PngDump::~PngDump() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

void PngDump::push(const uint8_t* rgba, int stride, uint64_t seq, int64_t t_ns) {
  if (failed_.load(std::memory_order_relaxed)) {
    dropped_.fetch_add(1);
    return;
  }
  ring_.push(rgba, stride, seq, t_ns, lossless_, &failed_);
}

void PngDump::flush() {
  while (ring_.queued()) std::this_thread::sleep_for(std::chrono::milliseconds(1));  // (after a failure it drains them, counted)
}

void PngDump::run() {
  while (true) {
    if (ring_.queued()) {
      const FrameRing::Frame& f = ring_.front();
      if (failed_) {
        dropped_.fetch_add(1);
      } else {
        const auto start = std::chrono::steady_clock::now();
        char name[64];
        std::snprintf(name, sizeof name, "frame_%06llu.png", static_cast<unsigned long long>(f.seq));
        const std::string path = (std::filesystem::path(dir_) / name).string();
        const std::string e = write_png(path, downsample_premultiplied(f.rgba.data(), ring_.width() / factor_, ring_.height() / factor_, factor_));
        if (!e.empty()) {
          error_ = e + " (frames from here on are dropped)";
          failed_ = true;
          dropped_.fetch_add(1);
        } else {
          written_.fetch_add(1);
        }
        writer_us_.store(writer_us_.load() + std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count());
      }
      ring_.pop();
      continue;
    }
    if (stop_) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

}  // namespace mar
