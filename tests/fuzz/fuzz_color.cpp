// CSS/SVG colours: names, #rgb, #rrggbb(aa), rgb()/rgba() with numbers and percentages.
#include "character/color.h"
#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  (void)mar::parse_color(mar::fuzz::text(data, size));
  return 0;
}
