// An SVG document as a character: XML, styles, shapes, <use>, transforms, flattening and the
// sub-shape outlines (load_svg_string). The point budget is lowered to 5,000 (4,000,000 in
// the program): the fuzzer favours drawings that flatten toward the budget, and each point is
// flattening and outline work on an accepted drawing (691 inputs a second on one core on a
// grown corpus at 20,000, 1,069 at 5,000). The budget's own checks are what is tested.
// Curves are flattened to 1 unit rather than the program's 0.1. Nothing becomes unreachable: a
// drawing flattened to 1 subdivides as the same drawing scaled down ten times does at 0.1 (up
// to rounding; the tolerance is used only there), so a drawing ten times larger reaches the
// same depth and budget limits (30 s on one core, seed 1, the grown corpus: 656 and 694
// inputs/s at 0.1, 1,016 and 983 at 1).
#include "character/svg_loader.h"
#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  mar::SvgOptions o;
  o.max_points = 5'000;
  o.max_elements = 5'000;  // 200,000 in the program; the bound's own check is what is tested
  o.max_gradient_texels = 1'000'000;  // 16 million in the program: the same evaluation, less of it
  o.tolerance = 1.0;
  o.max_bytes = 1 << 20;
  (void)mar::load_svg_string(mar::fuzz::text(data, size), "fuzz.svg", o);
  return 0;
}
