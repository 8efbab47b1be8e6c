#include "solve/solver.h"

#include "geom/polygon.h"

#include <algorithm>

namespace mar {

void rigid_pose(std::span<const Vec2> handle_rest, std::span<const Vec2> targets, std::span<const Vec2> rest, std::span<Vec2> x,
                std::span<double> c, std::span<double> s) {
  const size_t m = std::min(targets.size(), handle_rest.size());
  RigidMotion r = rigid_fit(handle_rest.first(m), targets.first(m));
  if (m == 0 || !r.to_c.allFinite()) r = RigidMotion{};  // identity: back to rest
  for (size_t i = 0; i < rest.size() && i < x.size(); ++i) x[i] = r.apply(rest[i]);
  std::fill(c.begin(), c.end(), r.c);
  std::fill(s.begin(), s.end(), r.s);
}

}  // namespace mar
