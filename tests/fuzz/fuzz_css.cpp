// Style sheets (<style>) and declaration lists (style=""), and selector matching on the result.
#include "character/css.h"
#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto [sheet_text, element] = mar::fuzz::split(mar::fuzz::text(data, size));
  mar::css::Sheet sheet;
  mar::css::parse(sheet_text, sheet);
  std::vector<std::pair<std::string, std::string>> important;
  (void)mar::css::parse_declarations(sheet_text, &important);
  for (const auto& r : sheet.rules) (void)mar::css::matches(r.selector, "path", element, element);
  return 0;
}
