// A small CSS subset for SVG <style> sheets, as Illustrator and Inkscape write them:
// rules of simple selectors (type, .class, #id, *, and compounds such as rect.st0),
// comma-separated groups, comments, !important, @-rules skipped.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace mar::css {

struct Selector {
  std::string type;                  ///< empty = any
  std::string id;                    ///< empty = any
  std::vector<std::string> classes;  ///< all must be present
  int specificity = 0;               ///< ids * 10000 + classes * 100 + types
};

struct Rule {
  Selector selector;
  std::vector<std::pair<std::string, std::string>> declarations;  ///< lower-case names
  std::vector<std::pair<std::string, std::string>> important;     ///< !important ones
  int order = 0;
};

struct Sheet {
  std::vector<Rule> rules;
  std::vector<std::string> unsupported;  ///< selectors that were skipped
};

/// Parses style sheet text, appending to `sheet` (rule order continues).
void parse(std::string_view text, Sheet& sheet);

/// Parses "name: value; ..." declarations (a style attribute or a rule body).
std::vector<std::pair<std::string, std::string>> parse_declarations(std::string_view body,
                                                                    std::vector<std::pair<std::string, std::string>>* important = nullptr);

/// True when the element (tag name, id, class attribute) matches the selector.
bool matches(const Selector& s, std::string_view tag, std::string_view id, std::string_view class_attr);

}  // namespace mar::css
