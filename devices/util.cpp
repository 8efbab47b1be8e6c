#include "devices/util.h"

#include "devices/device.h"

#include <algorithm>
#include <cstdio>
#include <dirent.h>
#include <fstream>
#include <iterator>
#include <unistd.h>

namespace mar::devutil {

std::vector<uint8_t> read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::string read_line(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  if (!in || !std::getline(in, line)) return {};
  while (!line.empty() && (line.back() == '\n' || line.back() == ' ' || line.back() == '\r')) line.pop_back();
  return line;
}

bool exists(const std::string& path) { return access(path.c_str(), F_OK) == 0; }

std::string vid_pid(int vid, int pid) {
  char b[16];
  std::snprintf(b, sizeof b, "%04x:%04x", vid & 0xFFFF, pid & 0xFFFF);
  return b;
}

std::string narrow(const wchar_t* w) {
  std::string s;
  for (; w && *w; ++w) s += (*w > 0 && *w < 128) ? char(*w) : '?';
  return s;
}

std::vector<std::string> list_dir(const std::string& path) {
  // opendir rather than std::filesystem: umockdev's preload redirects these calls.
  std::vector<std::string> out;
  if (DIR* d = opendir(path.c_str())) {
    while (dirent* e = readdir(d))
      if (e->d_name[0] != '.') out.emplace_back(e->d_name);
    closedir(d);
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::string profile_of(const std::vector<ProfileId>& profiles, int vid, int pid) {
  for (const auto& p : profiles)
    if (p.vid == vid)
      for (int q : p.pids)
        if (q == pid) return p.name;
  return {};
}

void access_status(FoundDevice& f) {
  if (access(f.node.c_str(), R_OK | W_OK) == 0) {
    f.status = "available";
  } else {
    f.status = "permission denied";
    f.problem = "install " + std::string(kUdevRule) + " and join the 'marionette' group";
  }
}

}  // namespace mar::devutil
