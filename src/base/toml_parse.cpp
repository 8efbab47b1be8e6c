// Reading TOML text (base/config_toml.h): a nesting check before toml++ sees the text,
// then toml++ itself.
#include "base/config_toml.h"

namespace mar::cfg {
namespace {

// What the scanner is inside of at the current character.
enum class In { Code, Comment, Basic, Literal, MultiBasic, MultiLiteral };

}  // namespace

std::string toml_nesting_problem(std::string_view s, const std::string& path, int max_depth) {
  // toml++ recurses once per dotted-key segment, table header segment, inline table and array;
  // a key 50,000 segments deep overflows the stack. One pass counts what it would recurse into:
  // the open brackets of values, plus the segments of the key being read. Strings and comments
  // are skipped; dots count only in key position (a float's dot is in a value).
  std::vector<char> open;  // '[' or '{' of values (and of a table header while it is read)
  In in = In::Code;
  bool key = true;  // reading a key: at a line's start, after '{' or ',' in an inline table
  int segments = 1;
  int line = 1;
  const auto too_deep = [&] {
    return path + ":" + std::to_string(line) + ": keys, tables or arrays nest deeper than " +
           std::to_string(max_depth) + " levels (the limit); file refused";
  };
  for (size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    if (c == '\n') ++line;
    switch (in) {
      case In::Comment:
        if (c == '\n') in = In::Code;
        else continue;
        break;
      case In::Basic:
        if (c == '\\') ++i;
        else if (c == '"' || c == '\n') in = In::Code;
        continue;
      case In::Literal:
        if (c == '\'' || c == '\n') in = In::Code;
        continue;
      case In::MultiBasic:
        if (c == '\\') ++i;
        else if (s.compare(i, 3, "\"\"\"") == 0) in = In::Code, i += 2;
        continue;
      case In::MultiLiteral:
        if (s.compare(i, 3, "'''") == 0) in = In::Code, i += 2;
        continue;
      case In::Code:
        break;
    }
    if (c == '\n') {
      if (open.empty() || open.back() == '{') key = open.empty(), segments = 1;
      continue;
    }
    switch (c) {
      case '#': in = In::Comment; break;
      case '"': in = s.compare(i, 3, "\"\"\"") == 0 ? (i += 2, In::MultiBasic) : In::Basic; break;
      case '\'': in = s.compare(i, 3, "'''") == 0 ? (i += 2, In::MultiLiteral) : In::Literal; break;
      case '.':
        if (key && int(open.size()) + ++segments > max_depth) return too_deep();
        break;
      case '=': key = false, segments = 1; break;
      case '[':
      case '{':
        open.push_back(c);
        if (int(open.size()) + segments > max_depth) return too_deep();
        key = c == '{' || (key && open.size() <= 2);  // an inline table's keys; a [header] or [[header]]
        segments = 1;
        break;
      case ']':
      case '}':
        if (!open.empty()) open.pop_back();
        key = false, segments = 1;
        break;
      case ',':
        if (!open.empty() && open.back() == '{') key = true, segments = 1;
        break;
      default: break;
    }
  }
  return {};
}

Result<toml::table> parse_toml(std::string_view text, const std::string& path) {
  if (std::string why = toml_nesting_problem(text, path); !why.empty()) return Result<toml::table>::failure(why);
  try {
    return Result<toml::table>::success(toml::parse(text, path));
  } catch (const toml::parse_error& e) {
    return Result<toml::table>::failure(path + ":" + std::to_string(e.source().begin.line) + ": " +
                                        std::string(e.description()));
  }
}

}  // namespace mar::cfg
