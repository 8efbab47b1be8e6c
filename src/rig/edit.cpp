#include "rig/edit.h"

#include "base/read_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fcntl.h>
#include <unistd.h>

namespace mar {

namespace fs = std::filesystem;

std::string write_atomically(const std::string& path, const std::string& text) {
  std::error_code ec;
  // Through a symbolic link: the file it names is the one replaced.
  fs::path target = fs::is_symlink(path, ec) ? fs::weakly_canonical(path, ec) : fs::path(path);
  if (ec) target = path;
  // Only a file is replaced: a device, a folder, a FIFO or a socket (/dev/null, as root) is not.
  if (const fs::file_status st = fs::status(target, ec); fs::exists(st) && !fs::is_regular_file(st))
    return target.string() + ": not a regular file (a device, a folder, a FIFO or a socket); not replaced";
  const std::string tmp = target.string() + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return tmp + ": cannot write (" + std::strerror(errno) + ")";
  size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const std::string why = std::strerror(errno);
      ::close(fd);
      fs::remove(tmp, ec);
      return tmp + ": write failed (" + why + ")";
    }
    done += size_t(n);
  }
  if (::fsync(fd) != 0 || ::close(fd) != 0) {
    const std::string why = std::strerror(errno);
    fs::remove(tmp, ec);
    return tmp + ": write failed (" + why + ")";
  }
  // The file's permissions, as they were.
  if (fs::exists(target, ec)) fs::permissions(tmp, fs::status(target, ec).permissions(), ec);
  fs::rename(tmp, target, ec);
  if (ec) {
    fs::remove(tmp, ec);
    return target.string() + ": cannot replace it (" + ec.message() + ")";
  }
  // The rename itself, on disk.
  const std::string dir = target.has_parent_path() ? target.parent_path().string() : ".";
  if (const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
  return {};
}

std::string append_atomically(const std::string& path, const std::string& text) {
  Result<std::string> read = read_file(path, kMaxTomlBytes, "a rig");
  if (!read.ok()) return read.error;
  std::string now = std::move(*read.value);
  if (!now.empty() && now.back() != '\n') now += '\n';
  return write_atomically(path, now + text);
}

}  // namespace mar
