#include "app/loop/file_watch.h"

#include <sys/inotify.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>

namespace mar {

FileWatch::~FileWatch() {
  if (fd_ >= 0) ::close(fd_);
}

std::string FileWatch::watch(const std::vector<std::string>& files, int64_t settle_ns) {
  namespace fs = std::filesystem;
  settle_ns_ = settle_ns;
  if (fd_ < 0) fd_ = inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
  if (fd_ < 0) return std::string("inotify: ") + std::strerror(errno);
  for (const std::string& f : files) {
    if (f.empty()) continue;
    std::error_code ec;
    const fs::path abs = fs::weakly_canonical(fs::absolute(f, ec), ec);
    const std::string name = abs.lexically_normal().string();
    if (std::find(files_.begin(), files_.end(), name) != files_.end()) continue;
    const std::string dir = abs.parent_path().string();
    if (std::none_of(dirs_.begin(), dirs_.end(), [&](const Dir& d) { return d.path == dir; })) {
      const int wd = inotify_add_watch(fd_, dir.c_str(), IN_CLOSE_WRITE | IN_MOVED_TO);
      if (wd < 0) return dir + ": " + std::strerror(errno);
      dirs_.push_back({wd, dir});
    }
    files_.push_back(name);
    changed_.push_back(0);
  }
  return {};
}

std::string FileWatch::poll(int64_t now_ns) {
  if (fd_ < 0) return {};
  alignas(inotify_event) char buf[4096];
  for (;;) {
    const ssize_t n = ::read(fd_, buf, sizeof buf);
    if (n <= 0) break;  // EAGAIN: nothing more now
    for (ssize_t at = 0; at + ssize_t(sizeof(inotify_event)) <= n;) {
      inotify_event ev;
      std::memcpy(&ev, buf + at, sizeof ev);
      const char* name = buf + at + sizeof(inotify_event);
      at += ssize_t(sizeof(inotify_event) + ev.len);
      if (ev.len == 0) continue;
      for (const Dir& d : dirs_) {
        if (d.wd != ev.wd) continue;
        const std::string path = d.path + "/" + std::string(name, strnlen(name, ev.len));
        for (size_t i = 0; i < files_.size(); ++i)
          if (files_[i] == path) {
            changed_[i] = 1;
            last_change_ns_ = now_ns;
          }
      }
    }
  }
  if (last_change_ns_ < 0 || now_ns - last_change_ns_ < settle_ns_) return {};
  std::string what;
  for (size_t i = 0; i < files_.size(); ++i) {
    if (!changed_[i]) continue;
    if (!what.empty()) what += ", ";
    what += std::filesystem::path(files_[i]).filename().string();
    changed_[i] = 0;
  }
  last_change_ns_ = -1;
  return what;
}

}  // namespace mar
