#include "character/character.h"

namespace mar {

bool SubShape::closed() const {
  bool any = false;
  for (const Contour& c : contours) {
    if (c.count == 1) continue;  // an interior point (a solver's mesh vertex), not a contour
    if (!c.closed) return false;
    any = true;
  }
  return any;
}

Bounds SubShape::bounds() const {
  Bounds b;
  for (const Vec2& p : points) b.add(p);
  return b;
}

std::vector<Ring> SubShape::rings() const {
  std::vector<Ring> r;
  r.reserve(contours.size());
  for (const Contour& c : contours) r.push_back({c.begin, c.count});
  return r;
}

Bounds Character::bounds() const {
  Bounds b;
  for (const SubShape& s : shapes) b.add(s.bounds());
  return b;
}

size_t Character::vertex_count() const {
  size_t n = 0;
  for (const SubShape& s : shapes) n += s.points.size();
  return n;
}

}  // namespace mar
