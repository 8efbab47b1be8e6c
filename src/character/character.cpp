#include "character/character.h"

#include "geom/polygon.h"

#include <cmath>

namespace mar {

bool SubShape::contains(const Vec2& q, std::span<const Vec2> at) const {
  bool in = false;
  for (const Contour& c : contours)
    if (c.closed && c.count >= 3 && size_t(c.begin + c.count) <= at.size() &&
        winding_number(at.subspan(size_t(c.begin), size_t(c.count)), q) % 2 != 0)
      in = !in;
  return in;
}

Points SubShape::largest_ring() const {
  Points best;
  double area = -1;
  for (const Contour& c : contours) {
    if (!c.closed || c.count < 3) continue;
    const std::span<const Vec2> r(points.data() + c.begin, size_t(c.count));
    if (const double a = std::abs(signed_area(r)); a > area) {
      area = a;
      best.assign(r.begin(), r.end());
    }
  }
  return best;
}

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
