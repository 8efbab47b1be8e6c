#include "character/css.h"

#include "character/color.h"

#include <algorithm>
#include <cctype>

namespace mar::css {
namespace {

std::string strip_comments(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '/' && i + 1 < text.size() && text[i + 1] == '*') {
      const size_t end = text.find("*/", i + 2);
      if (end == std::string_view::npos) break;
      i = end + 1;
      out.push_back(' ');
    } else {
      out.push_back(text[i]);
    }
  }
  return out;
}

bool ident_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_'; }

// One compound selector without combinators; false when unsupported.
bool parse_selector(std::string_view s, Selector& out) {
  s = trim_space(s);
  if (s.empty()) return false;
  size_t i = 0;
  auto ident = [&]() {
    const size_t b = i;
    while (i < s.size() && ident_char(s[i])) ++i;
    return std::string(s.substr(b, i - b));
  };
  int ids = 0, classes = 0, types = 0;
  if (s[0] == '*') {
    ++i;
  } else if (ident_char(s[0])) {
    out.type = ident();
    ++types;
  }
  while (i < s.size()) {
    const char c = s[i++];
    if (c == '.') {
      std::string cls = ident();
      if (cls.empty()) return false;
      out.classes.push_back(std::move(cls));
      ++classes;
    } else if (c == '#') {
      out.id = ident();
      if (out.id.empty()) return false;
      ++ids;
    } else {
      return false;  // combinators, attribute selectors, pseudo-classes
    }
  }
  out.specificity = ids * 10000 + classes * 100 + types;
  return true;
}

}  // namespace

std::vector<std::pair<std::string, std::string>> parse_declarations(
    std::string_view text, std::vector<std::pair<std::string, std::string>>* important) {
  std::vector<std::pair<std::string, std::string>> out;
  const std::string clean = strip_comments(text);  // (a style attribute may hold /* comments */ too)
  std::string_view body = clean;
  while (!body.empty()) {
    const size_t semi = body.find(';');
    std::string_view decl = body.substr(0, semi);
    body = semi == std::string_view::npos ? std::string_view{} : body.substr(semi + 1);
    const size_t colon = decl.find(':');
    if (colon == std::string_view::npos) continue;
    std::string key(trim_space(decl.substr(0, colon)));
    std::string_view val = trim_space(decl.substr(colon + 1));
    bool imp = false;
    if (const size_t p = val.find("!important"); p != std::string_view::npos) {
      val = trim_space(val.substr(0, p));
      imp = true;
    }
    std::transform(key.begin(), key.end(), key.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (key.empty()) continue;
    (imp && important ? *important : out).emplace_back(std::move(key), std::string(val));
  }
  return out;
}

void parse(std::string_view text, Sheet& sheet) {
  const std::string clean = strip_comments(text);
  std::string_view s = clean;
  int order = static_cast<int>(sheet.rules.size());
  while (true) {
    s = trim_space(s);
    if (s.empty()) break;
    if (s[0] == '@') {
      // @import, @media, @font-face ...: skip the statement or its block.
      const size_t semi = s.find(';'), brace = s.find('{');
      if (brace == std::string_view::npos || (semi != std::string_view::npos && semi < brace)) {
        if (semi == std::string_view::npos) break;
        s.remove_prefix(semi + 1);
        continue;
      }
      int depth = 0;
      size_t i = brace;
      for (; i < s.size(); ++i) {
        if (s[i] == '{') ++depth;
        if (s[i] == '}' && --depth == 0) break;
      }
      s.remove_prefix(std::min(s.size(), i + 1));
      continue;
    }
    const size_t open = s.find('{');
    if (open == std::string_view::npos) break;
    const size_t close = s.find('}', open);
    if (close == std::string_view::npos) break;
    const std::string_view selectors = s.substr(0, open);
    const std::string_view body = s.substr(open + 1, close - open - 1);
    s.remove_prefix(close + 1);
    std::vector<std::pair<std::string, std::string>> important;
    const auto decls = parse_declarations(body, &important);
    size_t pos = 0;
    while (pos <= selectors.size()) {
      const size_t comma = selectors.find(',', pos);
      const std::string_view one =
          selectors.substr(pos, comma == std::string_view::npos ? std::string_view::npos : comma - pos);
      Selector sel;
      if (parse_selector(one, sel)) {
        sheet.rules.push_back({std::move(sel), decls, important, order++});
      } else if (!trim_space(one).empty()) {
        sheet.unsupported.emplace_back(trim_space(one));
      }
      if (comma == std::string_view::npos) break;
      pos = comma + 1;
    }
  }
}

bool matches(const Selector& s, std::string_view tag, std::string_view id, std::string_view class_attr) {
  if (!s.type.empty() && s.type != tag) return false;
  if (!s.id.empty() && s.id != id) return false;
  for (const std::string& want : s.classes) {
    bool found = false;
    size_t pos = 0;
    while (pos < class_attr.size() && !found) {
      while (pos < class_attr.size() && std::isspace(static_cast<unsigned char>(class_attr[pos]))) ++pos;
      size_t end = pos;
      while (end < class_attr.size() && !std::isspace(static_cast<unsigned char>(class_attr[end]))) ++end;
      found = class_attr.substr(pos, end - pos) == want;
      pos = end;
    }
    if (!found) return false;
  }
  return true;
}

}  // namespace mar::css
