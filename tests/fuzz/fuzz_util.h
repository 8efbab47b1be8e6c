// Helpers shared by the libFuzzer harnesses: the input as text, split in two, or written to
// a file for the parsers that read one (one file per process, reused every run).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <unistd.h>

namespace mar::fuzz {

inline std::string_view text(const uint8_t* data, size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

/// Splits at the first NUL byte (the second part empty when there is none).
inline std::pair<std::string_view, std::string_view> split(std::string_view s) {
  const size_t k = s.find('\0');
  if (k == std::string_view::npos) return {s, {}};
  return {s.substr(0, k), s.substr(k + 1)};
}

/// Memory-backed when it can be (/dev/shm): a write to disk can stall past the 1 s timeout on
/// a busy machine (a fuzz_show_toml "timeout" once was fopen waiting for the disk).
inline const char* scratch_dir() { return access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp"; }

/// Writes the bytes to this process's scratch file `DIR/marionette-fuzz-PID-NAME` and returns its path.
inline std::string scratch_file(const char* name, std::string_view bytes) {
  std::string path = std::string(scratch_dir()) + "/marionette-fuzz-" + std::to_string(getpid()) + "-" + name;
  if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
    if (!bytes.empty()) std::fwrite(bytes.data(), 1, bytes.size(), f);
    std::fclose(f);
  }
  return path;
}

}  // namespace mar::fuzz
