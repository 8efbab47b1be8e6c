// Hot reload on save: watches a show's files (the show file, its rig, its character) with
// inotify. Editors save in place (IN_CLOSE_WRITE) or by writing a new file and renaming it over
// the old (IN_MOVED_TO), so the folders are watched, not the files. A change is reported once
// the files have been quiet for `settle` (an editor writes a file in several steps; a save of
// three files is one reload). Polled between frames: a non-blocking read, never inside a frame.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace mar {

class FileWatch {
 public:
  FileWatch() = default;
  FileWatch(const FileWatch&) = delete;
  FileWatch& operator=(const FileWatch&) = delete;
  ~FileWatch();
  /// Watches `files` (absolute or relative paths; empty entries skipped). Empty on success, else
  /// why not (the show runs without hot reload).
  std::string watch(const std::vector<std::string>& files, int64_t settle_ns = 150'000'000);
  bool active() const { return fd_ >= 0; }
  /// At `now_ns` (CLOCK_MONOTONIC): the names of the watched files saved since the last report,
  /// once they have been quiet for the settle time ("show.toml, figure.toml"); empty otherwise.
  std::string poll(int64_t now_ns);

 private:
  struct Dir {
    int wd;
    std::string path;
  };
  int fd_ = -1;
  std::vector<Dir> dirs_;
  std::vector<std::string> files_;  ///< absolute, normalised
  std::vector<char> changed_;       ///< per file
  int64_t settle_ns_ = 0, last_change_ns_ = -1;
};

}  // namespace mar
