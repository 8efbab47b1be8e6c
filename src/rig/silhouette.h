// Limbs from a silhouette: where a drawing's parts do not give its limbs (a black silhouette
// under colour pieces, a body and its legs drawn as one shape, one flat picture), the region
// the drawing covers does. Its outline's medial axis (the straight skeleton, geom/skeleton.h),
// pruned of the twigs a bumpy outline grows, is a tree about its widest point (the core); each
// branch out to a free end is a limb. A limb's joint is where the branch narrows to the limb's
// own width on its way out of what it hangs from (a hip, a shoulder, a neck); an elbow or knee
// is where its axis bends.
#pragma once

#include "character/character.h"

#include <span>
#include <string>
#include <vector>

namespace mar {

struct SilhouetteLimb {
  std::vector<Vec2> axis;  ///< its medial axis, from the free end to the joint
  std::vector<double> radius;  ///< its half-width at each point of `axis`
  Vec2 tip{0, 0};          ///< inside its free end: where its handle goes
  Vec2 joint{0, 0};        ///< where it leaves what it hangs from
  std::vector<Vec2> bends; ///< where its axis bends along the way (an elbow, a knee)
  double width = 0;        ///< its typical width
  double length = 0;       ///< from the free end to the joint
  double end_radius = 0;   ///< the widest it is in its outer 40% (a head is wider there than at its neck)
  Vec2 end_centre{0, 0};   ///< where it is that wide
  double narrowest = 0;    ///< the least radius between there and its joint (a neck)
};

struct Silhouette {
  Points outline;          ///< the region's outer outline (character units)
  std::vector<Points> holes;
  Vec2 core{0, 0};         ///< the centre of its widest part
  double core_radius = 0;
  std::vector<SilhouetteLimb> limbs;
  std::string error;       ///< why there is none
};

/// The limbs of the region inside `outline` (with `holes`), in its own units.
Silhouette silhouette_limbs(const Points& outline, std::span<const Points> holes = {});

/// The outer outline of everything one shape fills and strokes (its sub-paths together: an
/// outline drawn as many small filled pieces), traced at `long_side` pixels over its bounds;
/// empty when it draws nothing.
Points union_outline(const SubShape& shape, int long_side = 160);
/// The same of several shapes together: the outline of the largest region they cover.
Points union_outline(std::span<const SubShape* const> shapes, int long_side = 160);

/// The silhouette of the given shapes of `ch` together (fills and strokes, drawn opaque, then
/// traced: their union), its largest region, limbs found; drawn `long_side` pixels long.
Silhouette silhouette_of(const Character& ch, std::span<const int> shapes, int long_side = 400);

}  // namespace mar
