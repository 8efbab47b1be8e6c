#include "rig/chains.h"

#include "frame/joints.h"
#include "geom/polygon.h"

#include <algorithm>
#include <cmath>

namespace mar {

namespace {

// A shape's outline: its largest closed contour, else all its points (a stroke).
std::vector<Vec2> outline(const SubShape& s) {
  Points r = s.largest_ring();
  if (r.empty()) r.assign(s.points.begin(), s.points.end());
  return r;
}

// Where `child` hangs from `parent`: a stated or drawn hinge between them, the middle of their
// overlap, or the child's point nearest the parent.
Vec2 hang_point(const Character& ch, const Rig& rig, int parent, int child) {
  const std::string& a = ch.shapes[size_t(parent)].id;
  const std::string& b = ch.shapes[size_t(child)].id;
  for (const RigJoint& j : rig.joints)
    if (j.has_at && !j.weld && ((j.part_a == a && j.part_b == b) || (j.part_a == b && j.part_b == a))) return j.at;
  const std::vector<Vec2> pa = outline(ch.shapes[size_t(parent)]), pb = outline(ch.shapes[size_t(child)]);
  Vec2 c;
  if (ch.shapes[size_t(parent)].closed() && ch.shapes[size_t(child)].closed() && overlap_centre(pa, pb, c)) return c;
  double best = INFINITY;
  Vec2 at = pb.empty() ? Vec2::Zero() : pb[0];
  for (const Vec2& q : pb)
    for (const Vec2& p : pa)
      if (const double d = (p - q).squaredNorm(); d < best) {
        best = d;
        at = q;
      }
  return at;
}

}  // namespace

Result<ChainGeometry> chain_geometry(const Character& ch, const Rig& rig, const RigPhysics& ph) {
  using R = Result<ChainGeometry>;
  const std::string where = rig.path + ":" + std::to_string(ph.line) + ": physics chain '" + ph.name + "'";
  auto shape = [&](const std::string& id) {
    for (size_t k = 0; k < ch.shapes.size(); ++k)
      if (ch.shapes[k].id == id) return int(k);
    return -1;
  };
  ChainGeometry g;
  for (const std::string& id : ph.parts) {
    const int k = shape(id);
    if (k < 0) return R::failure(where + " names part '" + id + "', which is not a sub-shape of " + ch.source + " (inspect lists them)");
    if (std::find(g.shapes.begin(), g.shapes.end(), k) != g.shapes.end()) return R::failure(where + " names part '" + id + "' twice");
    if (ch.shapes[size_t(k)].points.size() < 2) return R::failure(where + ": part '" + id + "' has too few points to swing");
    g.shapes.push_back(k);
  }
  g.parent = shape(ph.from);
  if (g.parent < 0) {  // a handle: the topmost closed part under it, not one of the chain's
    const int h = rig.find_handle(ph.from);
    if (h < 0) return R::failure(where + " hangs from '" + ph.from + "', which is neither a sub-shape nor a handle");
    const Vec2 at = rig.handles[size_t(h)].rest;
    for (size_t k = ch.shapes.size(); k-- > 0 && g.parent < 0;)
      if (ch.shapes[k].closed() && ch.shapes[k].contains(at) && std::find(g.shapes.begin(), g.shapes.end(), int(k)) == g.shapes.end())
        g.parent = int(k);
    if (g.parent < 0) return R::failure(where + " hangs from handle '" + ph.from + "', which is on no part");
  }
  if (std::find(g.shapes.begin(), g.shapes.end(), g.parent) != g.shapes.end())
    return R::failure(where + " hangs from '" + ph.from + "', one of its own parts");
  int up = g.parent;
  for (int k : g.shapes) {
    g.rest.push_back(hang_point(ch, rig, up, k));
    up = k;
  }
  // The free end: the last part's point farthest from where it hangs.
  const Vec2 last = g.rest.back();
  Vec2 tip = last;
  for (const Vec2& p : ch.shapes[size_t(g.shapes.back())].points)
    if ((p - last).squaredNorm() > (tip - last).squaredNorm()) tip = p;
  if (ph.length > 0 && (tip - last).norm() > 0) tip = last + (tip - last).normalized() * ph.length;
  g.rest.push_back(tip);
  for (size_t i = 1; i < g.rest.size(); ++i)
    if ((g.rest[i] - g.rest[i - 1]).norm() < 1e-6)
      return R::failure(where + ": link " + std::to_string(i) + " has no length (its part hangs where it ends)");
  return R::success(std::move(g));
}

}  // namespace mar
