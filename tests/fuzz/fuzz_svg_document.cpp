// An SVG document as a character: XML, styles, shapes, <use>, transforms, flattening and the
// sub-shape outlines (load_svg_string). Limits are lowered so one run stays fast; the
// limits themselves are what is tested.
#include "character/svg_loader.h"
#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  mar::SvgOptions o;
  o.max_points = 200'000;
  o.max_bytes = 1 << 20;
  (void)mar::load_svg_string(mar::fuzz::text(data, size), "fuzz.svg", o);
  return 0;
}
