// Secondary motion (docs/algorithms.md §8): chains of dangling links — hair, a ponytail, ears, a
// tail, antennae, a flame — that swing, bounce and settle when what they hang from moves.
//
// A chain hangs from an anchor on its parent (a point and the parent's rotation, given each
// frame). Each link is a pendulum from the end of the one before: its angle θ (world) and
// angular velocity ω, and for the spring model its length r as well. In the anchor's
// accelerating frame the link end feels F = g + wind / mass − inertia · a (a: the acceleration
// of the point it hangs from), and
//     θ'' = (u × F) / r − ω₀² · sin(θ − θ_rest) − 2ζ·ωn·(ω − ρ')
//     r''  = −ω₀² (r − L) − 2ζ·ω₀·r' + u · F + r ω²                     (spring model only)
// with u = (cos θ, sin θ), θ_rest the drawn direction turned with the parent (ρ: its rotation),
// ω₀ = 2π · frequency (0: no spring; the pendulum hangs by gravity alone), ωn the undamped
// natural frequency √(ω₀² + |g|/L) and ζ the damping ratio. With a spring, θ_rest leans
// against gravity's pull on the drawn link (asin((u_drawn × g) / (L ω₀²))), so the drawing is
// where the chain settles while its parent is as drawn; turn the parent and gravity pulls anew.
//
// Steps are fixed (1/rate s, semi-implicit Euler) with an accumulator: each frame adds its
// time, steps while a whole step is left, and outputs the state interpolated between the last
// two steps — the motion is the same at 30, 60, 144 or 240 Hz frames. The anchor moves
// linearly through the steps of one frame (it is known once a frame). A frame longer than 0.25
// s, or reset(), puts the chain at rest relative to its parent, still. A link end's speed is
// clamped to `limit`; a step that gives a non-finite state is undone and the link stopped.
// Nothing here allocates after construction.
#pragma once

#include "geom/types.h"

#include <span>
#include <vector>

namespace mar {

struct ChainParams {
  enum Model { Pendulum, Spring } model = Pendulum;
  double frequency = 0;  ///< Hz: a spring toward the drawn direction (and, spring model, length)
  double damping = 0.1;  ///< ζ, a fraction of critical
  double inertia = 1;    ///< how much of the parent's acceleration the links feel
  double mass = 1;       ///< wind is a force: its acceleration is wind / mass
  Vec2 gravity{0, 0};    ///< this chain's own, added to the world's (character units / s²)
  Vec2 wind{0, 0};       ///< added to the world's
  double mix = 1;        ///< 0: the links follow the parent rigidly; 1: the simulation
  double limit = 0;      ///< top speed of a link end, character units / s (0: none)
};

/// What every chain feels.
struct MotionWorld {
  Vec2 gravity{0, 0};
  Vec2 wind{0, 0};
  double strength = 1;  ///< scales every chain's mix (a performer's master control)
};

class Chain {
 public:
  /// `rest`: the anchor, then each link's end, on the drawing (#links + 1 points).
  Chain(std::span<const Vec2> rest, const ChainParams& p);

  ChainParams& params() { return p_; }
  const ChainParams& params() const { return p_; }
  size_t links() const { return len_.size(); }
  double length(size_t i) const { return len_[i]; }

  /// Puts the chain at rest relative to a parent at `anchor`, turned by `rotation` (radians
  /// from the drawing), still.
  void reset(const Vec2& anchor, double rotation);
  /// One frame of `dt` seconds, at steps of `h` seconds, the parent at `anchor` and turned by
  /// `rotation` at the frame's end.
  void advance(double dt, double h, const Vec2& anchor, double rotation, const MotionWorld& w);
  /// The link ends this frame (interpolated between steps, mixed with the rigid pose).
  std::span<const Vec2> ends() const { return out_; }
  /// The link ends of the simulation alone, at the last step.
  Vec2 simulated_end(size_t i) const { return end_of(i, state_); }
  long steps() const { return steps_; }
  long resets() const { return resets_; }
  long reverts() const { return reverts_; }

 private:
  struct Link {
    double theta = 0, omega = 0, r = 0, rdot = 0;
  };
  Vec2 end_of(size_t i, const std::vector<Link>& s) const;
  void step(double h, const Vec2& anchor, double rotation, double spin, const MotionWorld& w);

  ChainParams p_;
  std::vector<double> len_, rest_angle_;  ///< per link: drawn length and direction
  std::vector<Vec2> rest_offset_;         ///< per link end: rest point − anchor (rigid follow)
  std::vector<Link> state_, prev_, good_;
  std::vector<Vec2> out_;
  std::vector<Vec2> root_, root1_, root2_;  ///< per link: where it hangs, now and the two steps before
  Vec2 anchor_ = Vec2::Zero(), anchor0_ = Vec2::Zero();  ///< the frame's end, the frame's start
  double rotation_ = 0, rotation0_ = 0;
  double acc_ = 0;       ///< time not yet stepped
  bool started_ = false;
  int history_ = 0;      ///< steps with root positions behind them (0..2): acceleration needs two
  long steps_ = 0, resets_ = 0, reverts_ = 0;
};

/// Deterministic smooth noise in [-1, 1] (a sum of incommensurate sines), for wind gusts.
double smooth_noise(double t, double seed);

}  // namespace mar
