// SVG path data, then its flattening to polylines (arcs become cubics while parsing). The
// loader stops flattening at its point budget, inside a curve too; here the budget is 50,000
// points (without the cap one cubic flattens to as many as 2^18).
#include "character/svg_parse.h"
#include "fuzz_util.h"
#include "geom/flatten.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const mar::svg::PathData p = mar::svg::parse_path(mar::fuzz::text(data, size), 20'000);
  mar::Points out;
  mar::Vec2 at = mar::Vec2::Zero();
  for (const mar::svg::PathCmd& c : p.cmds) {
    if (c.kind == mar::svg::PathCmd::Cubic) mar::flatten_cubic(at, c.c1, c.c2, c.p, 0.25, out, 50'001);
    else out.push_back(c.p);
    at = c.p;
    if (out.size() > 50'000) break;
  }
  return 0;
}
