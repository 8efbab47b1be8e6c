// The solver seam: what every deformation method offers the rest of the program (the live
// loop, the pose and inspect commands, benchmarks). The feature frame (seed 000,
// solve/feature_frame_method.h), the rigid grid (seed 003, solve/rigid_grid.h) and the outline
// ARAP baseline (solve/arap.h) implement it. A rig names its method (`solver =
// "feature_frame"`, the default; solve/make_solver.h); Puppet holds whichever it names.
//
// Shapes: handles are given by rest points on the character (#h); targets are #h points,
// plus one while a temporary grab handle is set. Everything but prepare(), parameters() and
// set_parameters() allocates nothing.
#pragma once

#include "character/rig.h"
#include "solve/feature_frame.h"

#include <memory>
#include <span>
#include <string>
#include <string_view>

namespace mar {

/// A number of the method a performer may turn live (a binding's `solver.NAME` target).
struct SolverParameter {
  std::string name;
  double value = 0;       ///< the rig's value
  double lo = 0, hi = 1;  ///< what the method accepts
};

class Solver {
 public:
  virtual ~Solver() = default;
  virtual std::string_view name() const = 0;

  /// Builds the method's representation of `ch` (it may insert vertices the method needs,
  /// so call it before preparing render meshes) and factorises for handles at `handle_rest`.
  virtual bool prepare(Character& ch, const Rig& rig, std::span<const Vec2> handle_rest, const SolverWeights& w,
                       std::string* error) = 0;
  /// The method's live parameters and their current values (load time).
  virtual std::vector<SolverParameter> parameters() const = 0;
  /// New values for parameters(), in its order, keeping the pose (may re-factorise and
  /// allocate: not a per-frame call).
  virtual bool set_parameters(std::span<const double> values, std::string* error) = 0;

  /// A fixed number of iterations from the current pose toward `targets`.
  virtual void solve(std::span<const Vec2> targets, int iterations) = 0;
  /// The start for a jump (a solve from rest, a pose recall).
  virtual void initial_guess(std::span<const Vec2> targets) = 0;
  virtual void reset_to_rest() = 0;

  /// Deformed points of every sub-shape; `out` holds one Points per shape with the rest sizes.
  virtual void shape_points(std::vector<Points>& out) const = 0;
  /// Where handle h is on the deformed character.
  virtual Vec2 handle_point(size_t h) const = 0;
  virtual size_t handle_count() const = 0;

  /// A temporary extra handle at a rest point of the character (a pen grab); its target is
  /// the last of solve()'s targets until release().
  virtual void grab(const Vec2& rest_point) = 0;
  virtual void release() = 0;
  virtual bool grabbing() const = 0;

  /// The energy the method minimises, of the current pose for `targets` (rigidity and handle
  /// terms, with the best rotations for the pose); for `pose --dump`, tests and benchmarks.
  virtual double energy(std::span<const Vec2> targets) const = 0;
};

/// A mesh solver's pose reset (`motion` absent) or moved by the best rigid motion of the
/// handles' rest points onto their targets (a jump's start): x = motion(rest), and every
/// local rotation (c, s) set to the motion's. No allocation.
void rigid_pose(std::span<const Vec2> handle_rest, std::span<const Vec2> targets, std::span<const Vec2> rest, std::span<Vec2> x,
                std::span<double> c, std::span<double> s);

/// A part no handle reaches (mesh solvers) is pulled toward where it is with this share of
/// its vertices' stiffness: enough to keep the factorisation well conditioned (1e-8 left the
/// part's translation to rounding: it drifted by 0.02 units per iteration), too little to
/// resist the part's own deformation.
constexpr double kFreePull = 1e-4;

}  // namespace mar
