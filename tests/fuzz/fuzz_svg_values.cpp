// SVG attribute values: transforms, point lists, numbers, lengths, opacities and view boxes.
#include "character/svg_parse.h"
#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view s = mar::fuzz::text(data, size);
  (void)mar::svg::parse_transform(s);
  bool odd = false;
  (void)mar::svg::parse_points(s, &odd);
  (void)mar::svg::parse_number(s);
  (void)mar::svg::parse_opacity(s, 1.0);
  (void)mar::svg::parse_length(s, 0, 100, 100);
  (void)mar::svg::parse_length(s, 2, 100, 100);
  (void)mar::svg::parse_viewbox(s);
  size_t pos = 0;
  while (pos < s.size() && mar::svg::read_number(s, pos)) {}
  return 0;
}
