// Reading a file named from outside: a show, a rig, a character, a mask, an image an SVG names,
// a PNG layer, a script, a take, a device profile, a report descriptor, a WAV. Every such path
// is read one way, so a typo, a symlink or a hostile drawing cannot make a loader block or take
// unbounded memory:
//   - opened without blocking (O_NONBLOCK: a FIFO with no writer does not wait for one);
//   - checked with fstat on the opened file to be a regular file ("is a directory", "is a
//     device", "is a FIFO", "is a socket": /dev/zero or /dev/urandom are refused at once);
//   - refused when larger than the format's limit, before a byte is read ("is 5.0 GB; at most
//     64 MB for an SVG character");
//   - read up to that limit and no further (a file that grows while read is cut there and said).
// Messages start with the path.
#pragma once

#include "base/result.h"

#include <cstdint>
#include <string>
#include <string_view>

namespace mar {

/// Limits, in bytes, by format (the loaders' own limits on what the bytes hold come after).
constexpr uint64_t kMaxSvgBytes = 64ull << 20, kMaxPngBytes = 256ull << 20, kMaxTomlBytes = 16ull << 20,
                   kMaxScriptBytes = 64ull << 20, kMaxTakeBytes = 4ull << 30, kMaxDescriptorBytes = 1ull << 20,
                   kMaxWavBytes = 512ull << 20;

/// `path`'s bytes, or a message naming it and what is wrong. `what` names the kind of file for
/// the size message ("an SVG character").
Result<std::string> read_file(const std::string& path, uint64_t max_bytes, const char* what);

/// The same checks without reading (for a library that opens the file itself): empty when
/// `path` is a regular file of at most `max_bytes`, else the message read_file() would give.
std::string file_problem(const std::string& path, uint64_t max_bytes, const char* what);

/// Writes `bytes` to `path` (created or truncated), every write and the close checked: empty on
/// success, else "path: No space left on device" (what failed, from errno). A file cut by a
/// failed write is removed, so nothing claims to be what it is not.
std::string write_file(const std::string& path, std::string_view bytes);

/// Empty when a file can be written at `path` (its folder exists and is writable, and what is
/// there now, if anything, is not a folder), else "path: why". Empty for an empty path.
std::string output_problem(const std::string& path);

/// "5.0 GB", "64 MB", "12 KB", "300 bytes".
std::string byte_size(uint64_t n);

}  // namespace mar
