// Joints and per-part stiffness of a feature frame (docs/algorithms.md §7).
//
// A hinge joins two closed parts at one point: a new frame vertex in each part, tied to
// its part's nearest frame vertices by spokes (coupling only, so the vertex moves with the
// part) and to the other by a zero-length pin. Unlike a sewing line between the parts'
// vertices, a pin carries no rotation: the limb turns about the joint while the body keeps
// its shape. An optional weak spring line from one end to the other part pulls the hinge
// towards its rest angle, so a part with no handle of its own still follows its parent.
//
// Automatic hinges replace the sewing line between two closed parts whose outlines cross
// (a near-zero-length sewing line) when the overlap covers less than 40% of the smaller
// part, or less than 60% when its centre lies near one end of an elongated part (an arm
// over a body, a leg under shorts, a wing on a body). Other crossings (hair over a head, a
// sleeve on an arm, a drip on a candle, and open strokes) are welds: the crossing line plus
// a second line that keeps the parts' relative orientation.
#pragma once

#include "frame/feature_frame.h"

namespace mar {

/// Per-shape stiffness: the rig's [[part]] values, else automatic or 1 (see FrameOptions).
std::vector<double> part_stiffness(const Character& ch, const FrameOptions& o, std::vector<std::string>* warnings);

/// Replaces crossing sewing lines by hinges (automatic and the rig's), then weights every
/// line by its parts' stiffness. Run by build_feature_frame after the sewing lines exist.
void add_joints_and_stiffness(const Character& ch, const FrameOptions& o, FeatureFrame& f);

/// The principal axis of a ring's points: the centre of their extent, the unit major axis,
/// and the half extents along the major and minor axes.
struct Axis {
  Vec2 centre{0, 0}, major{1, 0};
  double half_major = 0, half_minor = 0;
};
Axis principal_axis(std::span<const Vec2> r);

/// Centre (and area, when asked) of the region inside both closed rings, sampled on a
/// 48 x 48 grid over their common bounds; false when they do not overlap.
bool overlap_centre(std::span<const Vec2> a, std::span<const Vec2> b, Vec2& centre, double* area = nullptr);

}  // namespace mar
