// TOML helpers shared by every config file reader — rigs, show files, device profiles. A
// problem is thrown as ConfigError with "file:line: what" and caught at the reader's edge,
// which returns it as a failed Result.
#pragma once

#include "base/result.h"
#include "geom/types.h"

#include <toml++/toml.h>

#include <cmath>
#include <optional>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

namespace mar::cfg {

struct ConfigError {
  std::string message;
};

/// Every TOML file is parsed here (toml_parse.cpp): the text's nesting is checked first, then
/// toml++ parses it. A problem is "path:line: what".
Result<toml::table> parse_toml(std::string_view text, const std::string& path);

/// Empty when no key, table header, inline table or array nests deeper than `max_depth`
/// (counting a dotted key's segments), else the message naming the line. toml++ recurses once a
/// level, so a 100 KB key of 50,000 segments would overflow the stack; no config file of ours
/// nests past 10.
std::string toml_nesting_problem(std::string_view text, const std::string& path, int max_depth = 64);

inline std::string at(const std::string& path, const toml::node& n) {
  return path + ":" + std::to_string(n.source().begin.line);
}

inline double number(const std::string& path, const toml::node& n, const char* what) {
  if (auto v = n.value<double>(); v && std::isfinite(*v)) return *v;
  throw ConfigError{at(path, n) + ": " + what + " must be a finite number"};
}

/// A whole number: an integer, or a float with no fraction within ±2^53. toml++'s own
/// value<int64_t>() converts any float, which is undefined past int64's range (found by
/// fuzz_show_toml: `height = 4e048`).
inline std::optional<int64_t> whole(const toml::node& n) {
  if (const auto* i = n.as_integer()) return i->get();
  if (const auto* f = n.as_floating_point()) {
    const double v = f->get();
    if (std::isfinite(v) && v == std::trunc(v) && std::fabs(v) <= 9007199254740992.0) return int64_t(v);
  }
  return std::nullopt;
}

inline int integer(const std::string& path, const toml::node& n, const char* what, int lo, int hi) {
  if (auto v = whole(n); v && *v >= lo && *v <= hi) return int(*v);
  throw ConfigError{at(path, n) + ": " + what + " must be an integer " + std::to_string(lo) + ".." + std::to_string(hi)};
}

inline std::string text(const std::string& path, const toml::node& n, const char* what) {
  if (auto v = n.value<std::string>()) return *v;
  throw ConfigError{at(path, n) + ": " + what + " must be a string"};
}

inline bool boolean(const std::string& path, const toml::node& n, const char* what) {
  if (auto v = n.value<bool>()) return *v;
  throw ConfigError{at(path, n) + ": " + what + " must be true or false"};
}

inline Vec2 point(const std::string& path, const toml::node& n, const char* what) {
  const toml::array* a = n.as_array();
  if (!a || a->size() != 2) throw ConfigError{at(path, n) + ": " + what + " must be [x, y]"};
  return {number(path, *a->get(0), what), number(path, *a->get(1), what)};
}

inline std::vector<std::string> strings(const std::string& path, const toml::node& n, const char* what) {
  std::vector<std::string> out;
  const toml::array* a = n.as_array();
  if (!a) throw ConfigError{at(path, n) + ": " + what + " must be a list of strings"};
  for (const toml::node& e : *a) out.push_back(text(path, e, what));
  return out;
}

inline void check_keys(const std::string& path, const toml::table& t, std::initializer_list<std::string_view> known,
                       const char* where) {
  for (const auto& [k, v] : t) {
    bool ok = false;
    for (std::string_view n : known) ok = ok || k.str() == n;
    if (!ok) throw ConfigError{at(path, v) + ": unknown key '" + std::string(k.str()) + "' in " + where};
  }
}

}  // namespace mar::cfg
