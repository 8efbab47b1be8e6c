// The frame's motion stage: the rig's [[physics]] chains (motion/chain.h) follow the parts they
// hang from and write their link ends as the targets of their handles (Puppet::chains): soft
// targets (RigPhysics::weight), so the solver keeps the dangling parts' shape and their joints
// attached. Each chain's parent is read from the puppet's last pose (chain_parent_pose), carried
// on as it went for this frame.
//
// Live settings (a show's bindings): physics.NAME.strength (0..2, how much it feels the
// parent's motion), physics.NAME.mix (0..1, the simulation against following rigidly),
// physics.wind (its x, units/s²), physics.gravity (0..2, a scale) and physics.reset (a button).
// No allocation after prepare().
#pragma once

#include "app/puppet.h"
#include "app/show.h"
#include "motion/chain.h"

#include <span>
#include <string>
#include <vector>

namespace mar {

/// Where chain `c`'s parent holds it in `p`'s current shapes: the point it hangs from, and the
/// parent's rotation from the drawing (the best rigid motion of the parent's points, weighted
/// toward that point). No allocation.
void chain_parent_pose(const Puppet& p, const PuppetChain& c, Vec2& anchor, double& rotation);

class PhysicsStage {
 public:
  /// The puppet's chains under the show's [physics] (allocates).
  void prepare(const Puppet& p, const ShowPhysics& world);
  bool empty() const { return chains_.empty(); }
  size_t size() const { return chains_.size(); }
  /// The settings a binding may drive, in the order set() takes them: per chain strength and
  /// mix, then wind, gravity and reset. Each with its default and range.
  struct SettingInfo {
    std::string name;
    double value, lo, hi;
  };
  std::vector<SettingInfo> settings() const;
  /// The same names and ranges for a puppet's chains before a stage is prepared (a show's
  /// names resolve against them).
  static std::vector<SettingInfo> setting_names(const Puppet& p);
  size_t setting_count() const { return chains_.empty() ? 0 : 2 * chains_.size() + 3; }
  /// Setting k (settings() order) has value v.
  void set(size_t k, double v);
  /// One frame of `dt` seconds: each chain follows its parent in `p`'s current shapes and
  /// writes its link ends into `targets` (the puppet's handles).
  void step(double dt, const Puppet& p, std::span<Vec2> targets);
  /// The music time (motion/beat_clock.h) for [physics] sync = "beat".
  void set_beats(double beats) { beats_ = beats; }
  /// The next step starts every chain at rest relative to its parent, still (a jump).
  void reset() { reset_ = true; }
  /// A reload: each chain that `old` has too (same name, same links) goes on from where it
  /// swung, with this show's parameters; the others start at rest. (Allocates: not in a frame.)
  void carry_from(const PhysicsStage& old);
  long steps() const;
  long resets() const;
  long reverts() const;

 private:
  struct Item {
    std::string name;
    Chain chain;
    ChainParams base;  ///< the rig's values (strength scales inertia)
    bool own_gravity = false;
    Vec2 gravity = Vec2::Zero(), wind = Vec2::Zero();
    double gust = 0;
    double rotation = 0;  ///< the parent's, unwrapped
    Vec2 last_seen = Vec2::Zero();  ///< where the parent held the chain in the pose before
    double last_rotation = 0;
    bool seen_before = false;
  };
  std::vector<Item> chains_;
  ShowPhysics world_;
  double h_ = 1.0 / 120;
  double t_ = 0;           ///< show time the chains have seen (gusts)
  double beats_ = 0;       ///< the music time (sync)
  double gravity_scale_ = 1;
  double reset_level_ = 0;
  bool reset_ = true;
};

}  // namespace mar
