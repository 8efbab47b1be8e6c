// A rigged character ready to pose: the character (refined for its solver), the rig, the
// solver the rig names (behind the seam in solve/solver.h), render meshes and the deformed
// shape points.
#pragma once

#include "character/rig.h"
#include "render/tessellate.h"
#include "rig/chains.h"
#include "solve/feature_frame_method.h"

#include <array>
#include <memory>
#include <span>
#include <string>

namespace mar {

/// A [[physics]] chain of a show's puppet: its links on the drawing and its handles.
struct PuppetChain {
  const RigPhysics* spec = nullptr;  ///< in Puppet::rig
  ChainGeometry geo;
  /// Per link end, its handle: a new one (`physics.NAME[.k]`), or for the last end a handle of
  /// the rig's on the last part, which the chain then drives in a show.
  std::vector<size_t> handles;
  /// How far around where it hangs the parent's points count for its motion (their weight
  /// halves at this distance): a third of the parent's size.
  double reach = 1;
};

struct Puppet {
  Character character;
  Rig rig;
  std::unique_ptr<Solver> solver;
  CharacterMesh mesh;
  std::vector<Points> shapes;        ///< deformed shape points (rest after load)
  /// Per sub-shape: whether it shows (swap sets show one member, trigger shapes only while
  /// their trigger is on); all of them deform.
  std::vector<char> shown;
  std::vector<std::vector<int>> swap_shapes;     ///< per rig swap set: its members' shape indices
  std::vector<std::vector<int>> trigger_shapes;  ///< per rig trigger: its shape indices
  /// A show's secondary motion: the rig's [[physics]] chains, each link end a handle after the
  /// rig's own (load_puppet with `physics`; empty otherwise).
  std::vector<PuppetChain> chains;
  /// Sets `shown` from each swap set's member and each trigger's state (one per rig swap set
  /// and trigger). No allocation.
  void show(std::span<const int> members, std::span<const char> triggers_on);
  double prefactor_ms = 0;           ///< time of Solver::prepare
  // What a reload that keeps this puppet (its files unchanged) reads of it while a running show
  // poses it on another thread: only what posing never writes (app/live_reload.cpp).
  std::vector<SolverParameter> loaded_parameters;  ///< the solver's, as the rig set them
  /// Its key poses, solved once (app/keys.h) by the first show that drove them; null until then.
  std::shared_ptr<const std::vector<Points>> solved_keys;
  /// Per key, its sculpted detail (app/keys.h solve_keys; empty for a key of handle targets).
  std::shared_ptr<const std::vector<Points>> key_details;
  /// The files it was made from with a hash of each one's bytes (puppet_stamp()).
  std::string stamp;
  double diagonal = 1;               ///< of the character's bounds
  std::vector<Vec2> rest_targets() const;
  SolverWeights weights() const;     ///< the rig's
  /// Rebuilds `shapes` from the solver's current pose.
  void reconstruct() { solver->shape_points(shapes); }
  /// The feature frame behind the seam, when the rig's method is the feature frame.
  const FeatureFrameMethod* feature_frame() const { return dynamic_cast<const FeatureFrameMethod*>(solver.get()); }
  FeatureFrameMethod* feature_frame() { return dynamic_cast<FeatureFrameMethod*>(solver.get()); }
};

/// Each file `p` was made from (its rig, its drawing, its mask, its keys' frames) with a hash of
/// its bytes as they are now; empty when one cannot be read. Equal stamps: the same puppet.
std::string puppet_stamp(const Puppet& p);

/// Appends the solver's structure over the character (the feature frame, the ARAP mesh or the
/// rigid grid) with handles at `handle_points`, mapped by `view`.
void append_solver_overlay(const Puppet& p, std::span<const Vec2> handle_points, const Affine2& view, DrawList& list);

/// The margin a show keeps around its character on the canvas (px at the canvas's size).
inline constexpr double kShowMargin = 16.0;

/// Loads the rig, then the character (`character_path`, or the rig's own when empty).
/// Errors are bad input (file:line).
/// `mask_path`: a PNG character's mask (non-black = figure); empty: the rig's `mask` when the
/// character is the rig's own file, else the PNG's alpha.
/// `physics`: the rig's [[physics]] chains get their handles (a show's motion stage drives them).
/// `images_anywhere`: an SVG character may name images outside its folder ([show] images).
/// `canvas`: the canvas it is drawn on (width, height in px; 0: not known), where an SVG's curves
/// are flattened to within 0.1 px (LoadOptions::pixels_per_unit).
Result<std::unique_ptr<Puppet>> load_puppet(const std::string& character_path, const std::string& rig_path,
                                            const std::string& mask_path = "", bool physics = false, bool images_anywhere = false,
                                            std::array<int, 2> canvas = {0, 0});
/// The same with a rig already read (a bench or tool that changes its solver first).
Result<std::unique_ptr<Puppet>> load_puppet(const std::string& character_path, Rig rig, const std::string& mask_path = "",
                                            bool physics = false, bool images_anywhere = false,
                                            std::array<int, 2> canvas = {0, 0});

}  // namespace mar
