#include "rig/rig_text.h"

#include <cmath>
#include <cstdio>

namespace mar {
namespace {

bool space(char c) { return c == ' ' || c == '\t' || c == '\r'; }

// Walks one line's value text from `i` to `end`, tracking bracket depth outside strings and
// stopping at a comment. Returns where the value stops (a '#' or the line's end).
size_t walk(const std::string& s, size_t i, size_t end, int& depth) {
  while (i < end) {
    const char c = s[i];
    if (c == '#') return i;
    if (c == '"' || c == '\'') {  // a string on this line
      for (++i; i < end && s[i] != c; ++i)
        if (c == '"' && s[i] == '\\') ++i;
    } else if (c == '[' || c == '{') {
      ++depth;
    } else if (c == ']' || c == '}') {
      --depth;
    }
    ++i;
  }
  return end;
}

}  // namespace

RigText::RigText(std::string text) : text_(std::move(text)) { scan(); }

void RigText::scan() {
  lines_.clear();
  int depth = 0, open_key = -1;  // inside a value spanning lines: the key line it began on
  for (size_t b = 0; b < text_.size();) {
    size_t e = text_.find('\n', b);
    e = e == std::string::npos ? text_.size() : e + 1;
    Line l;
    l.begin = b;
    l.end = e;
    size_t i = b;
    while (i < e && space(text_[i])) ++i;
    const size_t stop = text_[e - 1] == '\n' ? e - 1 : e;
    if (open_key >= 0) {
      l.kind = Line::Continued;
      walk(text_, i, stop, depth);
      if (depth <= 0) {
        depth = 0;
        lines_[size_t(open_key)].last = int(lines_.size());
        open_key = -1;
      }
    } else if (i >= stop) {
      l.kind = Line::Blank;
    } else if (text_[i] == '#') {
      l.kind = Line::Comment;
    } else if (text_[i] == '[') {
      const bool array = i + 1 < stop && text_[i + 1] == '[';
      l.kind = array ? Line::ArrayHeader : Line::Header;
      const size_t nb = i + (array ? 2 : 1);
      const size_t ne = text_.find(']', nb);
      std::string name = text_.substr(nb, ne == std::string::npos || ne > stop ? 0 : ne - nb);
      while (!name.empty() && space(name.back())) name.pop_back();
      while (!name.empty() && space(name.front())) name.erase(name.begin());
      l.name = name;
    } else {
      l.kind = Line::Key;
      size_t k = i;
      while (k < stop && text_[k] != '=' && !space(text_[k])) ++k;
      l.name = text_.substr(i, k - i);
      if (l.name.size() >= 2 && (l.name.front() == '"' || l.name.front() == '\'')) l.name = l.name.substr(1, l.name.size() - 2);
      const size_t eq = text_.find('=', k);
      size_t v = eq == std::string::npos || eq >= stop ? stop : eq + 1;
      while (v < stop && space(text_[v])) ++v;
      l.value_begin = v;
      l.value_end = walk(text_, v, stop, depth);
      while (l.value_end > v && space(text_[l.value_end - 1])) --l.value_end;
      l.last = int(lines_.size());
      if (depth > 0) open_key = int(lines_.size());
      else depth = 0;
    }
    lines_.push_back(std::move(l));
    b = e;
  }
}

size_t RigText::count(std::string_view name) const {
  size_t n = 0;
  for (const Line& l : lines_) n += l.kind == Line::ArrayHeader && l.name == name;
  return n;
}

bool RigText::find(std::string_view name, size_t n, Table& t) const {
  size_t seen = 0;
  for (size_t i = 0; i < lines_.size(); ++i) {
    if (lines_[i].kind != Line::ArrayHeader || lines_[i].name != name || seen++ != n) continue;
    t.header = int(i);
    t.last_key = int(i);
    size_t j = i + 1;
    for (; j < lines_.size(); ++j) {
      const Line::Kind k = lines_[j].kind;
      if (k == Line::Header || k == Line::ArrayHeader) break;
      if (k == Line::Key) t.last_key = lines_[j].last;
    }
    t.next = int(j);
    return true;
  }
  return false;
}

int RigText::header_line(std::string_view name, size_t n) const {
  Table t;
  return find(name, n, t) ? t.header + 1 : 0;
}

std::string RigText::get(std::string_view name, size_t n, std::string_view key) const {
  Table t;
  if (!find(name, n, t)) return "";
  for (int j = t.header + 1; j < t.next; ++j) {
    const Line& l = lines_[size_t(j)];
    if (l.kind != Line::Key || l.name != key) continue;
    if (l.last == j) return text_.substr(l.value_begin, l.value_end - l.value_begin);
    const Line& end = lines_[size_t(l.last)];
    return text_.substr(l.value_begin, end.end - l.value_begin);
  }
  return "";
}

bool RigText::set(std::string_view name, size_t n, std::string_view key, std::string_view value) {
  Table t;
  if (!find(name, n, t)) return false;
  for (int j = t.header + 1; j < t.next; ++j) {
    const Line& l = lines_[size_t(j)];
    if (l.kind != Line::Key || l.name != key) continue;
    if (l.last == j) {  // one line: the value alone changes, a comment after it stays
      text_.replace(l.value_begin, l.value_end - l.value_begin, value);
    } else {  // a value over several lines becomes one line
      const size_t end = lines_[size_t(l.last)].end;
      const bool newline = end > 0 && text_[end - 1] == '\n';
      text_.replace(l.value_begin, end - l.value_begin, std::string(value) + (newline ? "\n" : ""));
    }
    scan();
    return true;
  }
  const Line& after = lines_[size_t(t.last_key)];
  std::string add = std::string(key) + " = " + std::string(value) + "\n";
  if (after.end > 0 && text_[after.end - 1] != '\n') add = "\n" + add;
  text_.insert(after.end, add);
  scan();
  return true;
}

void RigText::append(std::string_view name, std::string_view body) {
  const std::string table = "[[" + std::string(name) + "]]\n" + std::string(body);
  const size_t n = count(name);
  if (n > 0) {
    Table t;
    find(name, n - 1, t);
    const size_t at = lines_[size_t(t.last_key)].end;
    std::string add = "\n" + table;
    if (at > 0 && text_[at - 1] != '\n') add = "\n" + add;
    text_.insert(at, add);
  } else {
    std::string add;
    if (!text_.empty() && text_.back() != '\n') add += "\n";
    if (!text_.empty()) add += "\n";
    text_ += add + table;
  }
  scan();
}

bool RigText::remove(std::string_view name, size_t n) {
  Table t;
  if (!find(name, n, t)) return false;
  int first = t.header;
  while (first > 0 && lines_[size_t(first - 1)].kind == Line::Comment) --first;  // its own comments
  // Its lines after the last key (blank lines, comments that introduce what follows) stay,
  // but one blank line that separated it from the table before goes with it.
  if (first > 0 && lines_[size_t(first - 1)].kind == Line::Blank) --first;
  else if (t.last_key + 1 < int(lines_.size()) && lines_[size_t(t.last_key + 1)].kind == Line::Blank) ++t.last_key;
  const size_t b = lines_[size_t(first)].begin, e = lines_[size_t(t.last_key)].end;
  text_.erase(b, e - b);
  scan();
  return true;
}

std::string toml_string(std::string_view s) {
  std::string o = "\"";
  for (const char c : s) {
    switch (c) {
      case '"': o += "\\\""; break;
      case '\\': o += "\\\\"; break;
      case '\n': o += "\\n"; break;
      case '\t': o += "\\t"; break;
      case '\r': o += "\\r"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", unsigned(static_cast<unsigned char>(c)));
          o += buf;
        } else {
          o += c;
        }
    }
  }
  return o + "\"";
}

std::string toml_number(double v) {
  if (!std::isfinite(v)) v = 0;
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.3f", v);
  std::string s = buf;
  while (s.size() > 1 && s.back() == '0' && s[s.size() - 2] != '.') s.pop_back();
  if (s == "-0.0") s = "0.0";
  return s;
}

std::string toml_point(double x, double y) {
  auto one = [](double v) {
    if (!std::isfinite(v)) v = 0;
    char buf[48];
    std::snprintf(buf, sizeof buf, "%.1f", v);
    std::string s = buf;
    return s == "-0.0" ? std::string("0.0") : s;
  };
  return "[" + one(x) + ", " + one(y) + "]";
}

}  // namespace mar
