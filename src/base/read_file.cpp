#include "base/read_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace mar {
namespace {

/// The open, non-blocking descriptor of a regular file of at most max_bytes, or -1 and `why`.
int open_regular(const std::string& path, uint64_t max_bytes, const char* what, std::string& why, uint64_t& size) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) {
    why = path + ": cannot open: " + std::strerror(errno);
    return -1;
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    why = path + ": cannot read: " + std::strerror(errno);
  } else if (S_ISDIR(st.st_mode)) {
    why = path + ": is a directory, not a file";
  } else if (S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode)) {
    why = path + ": is a device, not a file";
  } else if (S_ISFIFO(st.st_mode)) {
    why = path + ": is a FIFO, not a file";
  } else if (S_ISSOCK(st.st_mode)) {
    why = path + ": is a socket, not a file";
  } else if (!S_ISREG(st.st_mode)) {
    why = path + ": is not a regular file";
  } else if (uint64_t(st.st_size) > max_bytes) {
    why = path + ": is " + byte_size(uint64_t(st.st_size)) + "; at most " + byte_size(max_bytes) + " for " + what;
  } else {
    size = uint64_t(st.st_size);
    return fd;
  }
  ::close(fd);
  return -1;
}

}  // namespace

std::string byte_size(uint64_t n) {
  char s[48];
  if (n >= (1ull << 30)) std::snprintf(s, sizeof s, "%.1f GB", double(n) / double(1ull << 30));
  else if (n >= (1ull << 20)) std::snprintf(s, sizeof s, "%.0f MB", double(n) / double(1ull << 20));
  else if (n >= (1ull << 10)) std::snprintf(s, sizeof s, "%.0f KB", double(n) / double(1ull << 10));
  else std::snprintf(s, sizeof s, "%llu bytes", static_cast<unsigned long long>(n));
  return s;
}

std::string file_problem(const std::string& path, uint64_t max_bytes, const char* what) {
  std::string why;
  uint64_t size = 0;
  const int fd = open_regular(path, max_bytes, what, why, size);
  if (fd >= 0) ::close(fd);
  return why;
}

Result<std::string> read_file(const std::string& path, uint64_t max_bytes, const char* what) {
  std::string why;
  uint64_t size = 0;
  const int fd = open_regular(path, max_bytes, what, why, size);
  if (fd < 0) return Result<std::string>::failure(why);
  // A regular file does not block; its size may still change while it is read: at most the
  // limit is read, and one byte more tells that it grew past it.
  std::string out;
  out.resize(size_t(size));
  size_t got = 0;
  for (;;) {
    if (got == out.size()) {
      if (out.size() > max_bytes) break;
      out.resize(std::min<uint64_t>(max_bytes + 1, out.size() + (out.size() < 4096 ? 4096 : out.size())));
    }
    const ssize_t n = ::read(fd, out.data() + got, out.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      why = path + ": cannot read: " + std::strerror(errno);
      ::close(fd);
      return Result<std::string>::failure(why);
    }
    if (n == 0) break;
    got += size_t(n);
  }
  ::close(fd);
  if (got > max_bytes)
    return Result<std::string>::failure(path + ": grew past " + byte_size(max_bytes) + " while it was read; at most " +
                                        byte_size(max_bytes) + " for " + what);
  out.resize(got);
  return Result<std::string>::success(std::move(out));
}

std::string write_file(const std::string& path, std::string_view bytes) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC | O_NOCTTY, 0644);
  if (fd < 0) return path + ": cannot write: " + std::strerror(errno);
  struct stat st {};
  const bool regular = ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode);
  size_t done = 0;
  std::string why;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      why = path + ": " + (n < 0 ? std::strerror(errno) : "nothing written");
      break;
    }
    done += size_t(n);
  }
  if (::close(fd) != 0 && why.empty()) why = path + ": " + std::strerror(errno);
  if (!why.empty() && regular) ::unlink(path.c_str());
  return why;
}

std::string output_problem(const std::string& path) {
  if (path.empty()) return {};
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) return path + ": is a directory, not a file";
    if (::access(path.c_str(), W_OK) != 0) return path + ": cannot write: " + std::strerror(errno);
    return {};
  }
  const size_t slash = path.find_last_of('/');
  const std::string dir = slash == std::string::npos ? "." : slash == 0 ? "/" : path.substr(0, slash);
  if (::stat(dir.c_str(), &st) != 0) return path + ": cannot write: its folder " + dir + ": " + std::strerror(errno);
  if (!S_ISDIR(st.st_mode)) return path + ": cannot write: " + dir + " is not a folder";
  if (::access(dir.c_str(), W_OK | X_OK) != 0) return path + ": cannot write in " + dir + ": " + std::strerror(errno);
  return {};
}

}  // namespace mar
