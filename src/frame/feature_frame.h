// Feature frame of a multi-element character (seed 000 §3, docs/algorithms.md §1): feature
// points per contour, sub-frames, sewing lines from the Euclidean minimum spanning tree
// over sub-frames plus the user's edits, and parametric coordinates of every shape vertex.
#pragma once

#include "character/character.h"
#include "character/rig.h"

#include <string>
#include <vector>

namespace mar {

enum class SamplingMode { Features, Uniform };

/// One user edit of the sewing lines, in character coordinates.
struct SewingEdit {
  enum Kind { Add, Delete, Move } kind = Add;
  Vec2 from = Vec2::Zero(), to = Vec2::Zero();          ///< the line (Add) or the line to find
  Vec2 new_from = Vec2::Zero(), new_to = Vec2::Zero();  ///< Move: where it goes
  std::string where;                                    ///< "file:line" for messages
};

/// A hinge from the rig (`[[joint]]`): where it is and, optionally, which two parts it joins
/// (by id; otherwise the two topmost closed parts containing the point).
struct JointSpec {
  bool has_at = true;
  Vec2 at = Vec2::Zero();
  std::string part_a, part_b;
  double stiffness = -1;  ///< rotational spring; < 0: FrameOptions::hinge_stiffness
  bool weld = false;      ///< keep the parts sewn (overrides an automatic hinge)
  std::string where;      ///< "file:line"
};

struct PartStiffness {
  std::string id;
  double stiffness = 1;
  std::string where;
};

struct FrameOptions {
  SamplingMode mode = SamplingMode::Features;
  double interval = 0;                 ///< Uniform: arc-length interval; 0 = diagonal / 24
  double d_min = 0.01, d_max = 0.03;   ///< IPAN99 distances, as fractions of the bbox diagonal
  double alpha_max_deg = 150;          ///< IPAN99 opening angle
  double inflection_window = 0.03;     ///< smoothing window, fraction of the diagonal
  double inflection_hysteresis_deg = 12;
  double max_spacing = 0;              ///< > 0: extra points so no salient feature is longer (fraction of diagonal)
  std::vector<SewingEdit> sewing;
  /// Joints (frame/joints.h): two closed parts whose outlines cross near one end of an
  /// elongated one (an arm over a body) are joined by a pin at the centre of their overlap
  /// instead of a sewing line at a crossing point, so the limb turns about the joint.
  bool auto_joints = true;
  double joint_weight = 8;        ///< pin weight (a feature line's weight is the part's stiffness)
  double hinge_stiffness = 0.3;   ///< rotational spring of a hinge towards its rest angle
  std::vector<JointSpec> joints;
  /// Per-part stiffness scales the rigidity and coupling of a part's lines. Automatic:
  /// sqrt(area / median closed-part area) clamped to [1, 4] (bigger parts stiffer).
  bool auto_stiffness = true;
  std::vector<PartStiffness> stiffness;
};

FrameOptions default_frame_options();

/// Frame options of a rig: sampling mode and interval, sewing edits (with file:line).
FrameOptions frame_options_from_rig(const Rig& rig);

struct FrameVertexOrigin {
  int shape = 0;    ///< index into Character::shapes
  int contour = 0;  ///< index into that shape's contours
  int point = 0;    ///< index into that shape's points
};

struct FrameLine {
  /// Joint: the zero-length pin between the two ends of a hinge. Spoke: ties a hinge end to
  /// its part. Spring: a hinge's rotational spring.
  enum Kind { Feature, Sewing, UserSewing, Joint, Spoke, Spring } kind = Feature;
  int a = 0, b = 0;  ///< frame vertex indices
  double weight = 1; ///< scales the line's rigidity and coupling terms
};

/// A hinge between two parts: a frame vertex in each (`va` moves with `shape_a`), pinned.
struct FrameJoint {
  Vec2 at = Vec2::Zero();
  int shape_a = 0, shape_b = 0;
  int va = 0, vb = 0;
  double stiffness = 0;
  bool automatic = true;
};

/// Shape vertex in the local frame of feature line (a, b): p = v_a + z (v_b - v_a) with
/// complex multiplication (z = u + i s, (x, y)^perp = (-y, x)); a zero-length line keeps
/// the rest offset instead (p = v_a + offset).
struct ShapeParam {
  int a = 0, b = 0;
  double zr = 0, zi = 0;
  bool offset_only = false;
  double ox = 0, oy = 0;
};

struct FeatureFrame {
  Points rest;                             ///< #q frame vertex rest positions
  std::vector<FrameVertexOrigin> origin;   ///< #q
  std::vector<FrameLine> lines;            ///< feature lines first, then sewing lines
  int feature_lines = 0;
  int sewing_lines = 0;                    ///< all sewing lines (automatic + user)
  int user_sewing_lines = 0;
  std::vector<std::vector<ShapeParam>> params;  ///< per shape, per point
  std::vector<std::vector<int>> subframes;      ///< frame vertices of each contour, in order
  size_t shape_vertices = 0;
  double mean_edge_length = 0;
  double diagonal = 0;
  std::vector<FrameJoint> joints;
  std::vector<double> shape_stiffness;     ///< per shape
  std::vector<std::string> warnings;       ///< sewing edits that matched nothing
};

/// Inserts shape vertices where the frame needs points inside segments: where contours of
/// different sub-shapes cross (both get the point), and at user sewing end points (the
/// nearest point of the nearest contour). Nothing is inserted within a quarter of the mean
/// edge length of an existing vertex. Run it once before build_feature_frame and before
/// preparing render meshes. Returns the number of vertices inserted.
size_t refine_for_frame(Character& ch, const FrameOptions& options);

/// Builds the frame. Never fails: degenerate input gives a small or empty frame.
FeatureFrame build_feature_frame(const Character& ch, const FrameOptions& options);

/// Deformed shape points from deformed frame vertices `v` (#q). `out` must already hold
/// one Points per shape with the rest sizes (then nothing is allocated).
void reconstruct_shapes(const FeatureFrame& frame, std::span<const Vec2> v, std::vector<Points>& out);

/// Binds a point to a feature line, as handles are (Eq. 3): of the topmost closed part
/// containing it, else of the nearest contour; the nearest point of that part picks the line.
ShapeParam bind_point(const FeatureFrame& frame, const Character& ch, const Vec2& p);

/// Evaluates a binding for frame vertex positions `v`.
inline Vec2 eval_param(const ShapeParam& s, std::span<const Vec2> v) {
  const Vec2& a = v[static_cast<size_t>(s.a)];
  if (s.offset_only) return {a.x() + s.ox, a.y() + s.oy};
  const Vec2 d = v[static_cast<size_t>(s.b)] - a;
  return {a.x() + s.zr * d.x() - s.zi * d.y(), a.y() + s.zi * d.x() + s.zr * d.y()};
}

}  // namespace mar
