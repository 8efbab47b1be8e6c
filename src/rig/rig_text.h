// Editing a rig file's text the way a person would: the rig studio changes one value, adds a
// table or removes one, and every other line — comments, blank lines, the order of tables, a
// value written as the person wrote it — stays as it was. Tables are found by their header and
// their place among the tables of that name (the n-th `[[handle]]`), as parse_rig reads them.
//
// The scanner knows enough TOML for a rig: `[table]` and `[[array]]` headers, `key = value`
// lines, values that span lines inside brackets, basic and literal strings, and comments.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace mar {

class RigText {
 public:
  explicit RigText(std::string text = {});
  const std::string& text() const { return text_; }

  /// How many `[[name]]` tables the text has.
  size_t count(std::string_view name) const;
  /// The 1-based line of the n-th `[[name]]` header (0: none).
  int header_line(std::string_view name, size_t n) const;
  /// Sets `key = value` (value as TOML text) in the n-th `[[name]]` table: the key's line is
  /// replaced (a comment after a one-line value is kept), or a line is added after the
  /// table's last key. false when there is no such table.
  bool set(std::string_view name, size_t n, std::string_view key, std::string_view value);
  /// The value text of `key` in the n-th `[[name]]` table ("" when absent).
  std::string get(std::string_view name, size_t n, std::string_view key) const;
  /// Adds `[[name]]` with `body` (key lines, each ending in '\n') after the last table of that
  /// name, or at the end of the text when there is none.
  void append(std::string_view name, std::string_view body);
  /// Removes the n-th `[[name]]` table and the comment lines right above its header.
  bool remove(std::string_view name, size_t n);

 private:
  struct Line {
    size_t begin = 0, end = 0;  ///< byte range in text_, end after its '\n' (if any)
    enum Kind { Blank, Comment, Header, ArrayHeader, Key, Continued } kind = Blank;
    std::string name;  ///< a header's table name, a key line's key
    size_t value_begin = 0, value_end = 0;  ///< a one-line key's value (before any comment)
    int last = 0;  ///< a key line: the index of the line its value ends on
  };
  struct Table {
    int header = -1;     ///< line index
    int last_key = -1;   ///< the last line of its last value (the header when it has none)
    int next = 0;        ///< the line after it (the next header or the end)
  };
  void scan();
  bool find(std::string_view name, size_t n, Table& t) const;
  std::string text_;
  std::vector<Line> lines_;
};

/// A TOML basic string with the characters TOML needs escaped.
std::string toml_string(std::string_view s);
/// A point as a rig writes one: "[x, y]" with one decimal.
std::string toml_point(double x, double y);
/// A number with up to 3 decimals, trailing zeros dropped but one ("0.25", "4.0").
std::string toml_number(double v);

}  // namespace mar
