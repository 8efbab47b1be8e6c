// The drawings on a show's stage besides its character: [[scenery]] that never moves (behind
// it, or in front) and [[prop]]s a part of the character holds (docs/live-shows.md).
//
// Loaded with the show (off a running show's frame thread on a reload), their curves flattened
// against the canvas as the character's are. What lies behind the character is drawn once at
// load into a picture (backdrop()) that the canvas copies under each frame; a prop moves each
// frame by its part's best rigid motion from rest. append_*() allocate nothing.
#pragma once

#include "app/loop/actor.h"
#include "app/puppet.h"
#include "app/show.h"
#include "render/canvas.h"
#include "render/tessellate.h"

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace mar {

class StageDrawings {
 public:
  /// Loads the show's scenery and props for the cast (placed: each actor's view) drawn on a
  /// canvas of `canvas` px, supersampled `ss` times, and draws what lies behind over
  /// `background` (backdrop()). Empty, or the error with the show's file and line. `quiet`: the
  /// drawings' warnings are not printed.
  std::string load(const ShowConfig& sh, const std::vector<std::unique_ptr<Actor>>& cast, std::array<int, 2> canvas, int ss,
                   const Rgba& background, bool quiet);
  /// Each scenery drawing's view on a canvas of w x h px (supersampled `ss` times).
  void place(double w, double h, double ss);
  /// The scenery behind, drawn once at load (premultiplied RGBA8 of the canvas's size; empty
  /// when there is none), handed over once; `copied` says the canvas now puts it under each
  /// frame, so append_behind() leaves the scenery out.
  std::vector<uint8_t> take_backdrop() { return std::move(backdrop_); }
  void set_copied(bool copied) { copied_ = copied; }
  bool copied() const { return copied_; }
  /// Appends the scenery behind the cast (unless copied) or in front of it.
  void append_scenery(bool front, DrawList& list) const;
  /// Appends the props actor `a` holds behind it or in front of it, as it is now posed.
  void append_props(const Actor& a, bool front, DrawList& list) const;

 private:
  struct Scenery {
    Character ch;
    CharacterMesh mesh;
    Affine2 view;
    ShowScenery spec;
  };
  struct Prop {
    Character ch;
    CharacterMesh mesh;
    int who = 0;    ///< the holding actor (its index in the cast)
    int part = -1;  ///< the holding shape
    Affine2 place;  ///< prop -> character units, at rest
    bool front = true;
  };
  std::vector<Scenery> scenery_;
  std::vector<Prop> props_;
  std::vector<uint8_t> backdrop_;
  bool copied_ = false;
};

}  // namespace mar
