// TOML helpers shared by the show-file readers (show.cpp, show_devices.cpp). Errors are
// thrown as ShowError with file:line and caught at the loader's edge.
#pragma once

#include <toml++/toml.h>

#include <cmath>
#include <filesystem>
#include <cstdlib>
#include <string>

namespace mar::showtoml {

namespace fs = std::filesystem;

struct ShowError {
  std::string message;
};

inline std::string at(const std::string& path, const toml::node& n) {
  return path + ":" + std::to_string(n.source().begin.line);
}

inline double number(const std::string& path, const toml::node& n, const char* what) {
  if (auto v = n.value<double>(); v && std::isfinite(*v)) return *v;
  throw ShowError{at(path, n) + ": " + what + " must be a finite number"};
}

inline std::string text(const std::string& path, const toml::node& n, const char* what) {
  if (auto v = n.value<std::string>()) return *v;
  throw ShowError{at(path, n) + ": " + what + " must be a string"};
}

inline bool boolean(const std::string& path, const toml::node& n, const char* what) {
  if (auto v = n.value<bool>()) return *v;
  throw ShowError{at(path, n) + ": " + what + " must be true or false"};
}

inline void check_keys(const std::string& path, const toml::table& t, std::initializer_list<std::string_view> known,
                const char* where) {
  for (const auto& [k, v] : t) {
    bool ok = false;
    for (std::string_view n : known) ok = ok || k.str() == n;
    if (!ok) throw ShowError{at(path, v) + ": unknown key '" + std::string(k.str()) + "' in " + where};
  }
}

inline std::string resolve(const std::string& show_path, const std::string& p) {
  if (p.empty() || fs::path(p).is_absolute()) return p;
  // "corpus:" paths name files in the shared test corpus (MARIONETTE_CORPUS_DIR or the
  // build's default), so shows can use real devices' descriptors without copying them.
  if (p.rfind("corpus:", 0) == 0) {
    const char* env = std::getenv("MARIONETTE_CORPUS_DIR");
    return (fs::path(env && *env ? env : MARIONETTE_DEFAULT_CORPUS_DIR) / p.substr(7)).string();
  }
  return (fs::path(show_path).parent_path() / p).lexically_normal().string();
}

}  // namespace mar::showtoml

namespace mar {
struct ShowDevice;
/// [[device]] keys (sim and hardware).
void check_device_keys(const std::string& path, const toml::table& t);
/// Reads a hardware device's keys (and its profile) into `d.hw` / `d.controls`.
void read_hardware(const std::string& path, const toml::table& t, ShowDevice& d);
}  // namespace mar
