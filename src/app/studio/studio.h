// The rig studio's model (`marionette rig CHARACTER` without -o): a live puppet and the rig's
// text, changed by the performer's actions. Dragging a handle poses the character with the
// solver running as in a show; adding or removing a handle, moving a hinge and changing a
// part's stiffness edit the rig's text (rig/rig_text.h: every other line stays as written) and
// load the puppet again, keeping the pose. Every action is an undo step; save() writes the text
// atomically. No window here: studio_window.h draws it and turns events into these calls, and
// tests call them directly.
//
// Points are in character units on the posed character, as the performer sees it.
#pragma once

#include "app/loop/brush.h"
#include "app/loop/contour.h"
#include "app/loop/curve.h"
#include "app/puppet.h"
#include "rig/rig_text.h"

#include <memory>
#include <string>
#include <vector>

namespace mar {

/// A hinge as the studio shows it.
struct StudioHinge {
  Vec2 at = Vec2::Zero();    ///< where it is on the posed character
  Vec2 rest = Vec2::Zero();  ///< where it is on the drawing
  int shape_a = -1, shape_b = -1;
  std::string label;         ///< "arm-left / body"
};

class Studio {
 public:
  /// Opens `character` with the rig at `rig_path`: the rig is read from that file when it
  /// exists, else it is the automatic rig (rig/auto_rig.h), which save() then writes there.
  /// `mask`: a PNG character's mask. Errors name the file.
  static Result<std::unique_ptr<Studio>> open(const std::string& character, const std::string& rig_path, const std::string& mask = "");

  Puppet& puppet() { return *puppet_; }
  const Puppet& puppet() const { return *puppet_; }
  const std::string& rig_path() const { return rig_path_; }
  const std::string& text() const { return text_.text(); }
  /// Whether the text differs from the file's.
  bool dirty() const { return text_.text() != saved_; }
  /// Whether the rig file exists (false: the automatic rig, not saved yet).
  bool on_disk() const { return on_disk_; }

  // ---- the pose ----
  const std::vector<Vec2>& targets() const { return targets_; }
  /// Where handle h is on the posed character.
  Vec2 handle_point(size_t h) const { return puppet_->solver->handle_point(h); }
  /// Moves handle h's target (a drag); the pose follows at step().
  void set_target(size_t h, const Vec2& p);
  /// One frame: the rig's iterations toward the targets, as a show solves.
  void step();
  /// A drag ended: the pose becomes an undo step.
  void commit_pose();
  /// Every handle back at rest (an undo step).
  void reset_pose();

  // ---- picking, on the posed character ----
  int handle_at(const Vec2& p, double radius) const;
  int hinge_at(const Vec2& p, double radius) const;
  /// The topmost shown closed part containing p (-1: none).
  int part_at(const Vec2& p) const;
  std::vector<StudioHinge> hinges() const;
  /// A part's stiffness as the solver has it (the rig's [[part]], else automatic).
  double stiffness(int part) const;
  /// A part's name as a person reads it (its label, else its id).
  std::string part_name(int part) const;

  // ---- edits: each is an undo step; each returns "" or why it did nothing ----
  /// A new handle where p is, named after the part under it.
  std::string add_handle(const Vec2& p);
  std::string remove_handle(size_t h);
  /// Moves hinge j (of hinges()) to p: the rig's [[joint]] for its two parts changes, or one is
  /// written (a hinge the rig found in the drawing).
  std::string move_hinge(size_t j, const Vec2& p);
  /// Multiplies a part's stiffness by `factor` (a [[part]] table; clamped to [0.05, 50]).
  std::string scale_stiffness(int part, double factor);
  /// The pose as a key pose `name` ([[key]]): its moved handles; or, when a brush or a curve
  /// holds a shape (sculpted()), every shape's points in a file beside the rig
  /// (RigKey::shapes, written at once) that the key names.
  std::string save_key(const std::string& name);
  bool undo();
  bool redo();
  bool can_undo() const { return at_ > 0; }
  bool can_redo() const { return at_ + 1 < history_.size(); }
  /// Writes the text to the rig file atomically; "" or the error.
  std::string save();

  // ---- the pen's sculpting tools: a show's brush and drawn curve (app/loop/brush.h, curve.h)
  // on the studio's puppet (studio_tools.cpp). A sculpt is held until R, another tool's
  // stroke, or an edit of the rig (which loads the puppet again): K saves it as a key.
  enum class Tool { Pose, Brush, Curve, Line };  ///< Line: the curve redrawing an outline (fit = "contour")
  /// Chooses the pen's tool; the first sculpting tool loads the finer frame a brush needs
  /// (kSculptSpacing), keeping the pose. "" or why not.
  std::string set_tool(Tool t);
  Tool tool() const { return tool_; }
  /// The pen on the posed character (`down`, `pressure` 0..1), for the brush or the curve:
  /// the brush's radius is brush_radius(pressure); the curve's chain is the parts its stroke
  /// crosses after the one it starts on (that one it hangs from). Takes effect at step().
  void pen(const Vec2& p, bool down, double pressure);
  /// The brush's radius at a pressure, character units ([2 %, 8 %] of the diagonal, by
  /// brush_scale()).
  double brush_radius(double pressure) const;
  void scale_brush(double factor);
  double brush_scale() const { return brush_scale_; }
  /// Whether a brush or a curve holds a shape now.
  bool sculpted() const;
  /// Lets every sculpt go (the chosen tool's stage made again: "" or why not).
  std::string clear_sculpt();
  const BrushStage& brush() const { return brush_; }
  const CurveStage& curve() const { return curve_; }
  const ContourStage& line() const { return line_; }
  /// The curve's chain: the part it hangs from, then its parts (names as part_name gives).
  std::vector<std::string> curve_chain() const;
  /// The stroke being drawn (the curve and line tools), as drawn.
  const std::vector<Vec2>& stroke() const { return stroke_; }

  /// The rest point under p on the posed character (the fill triangle it is in, mapped back;
  /// near an outline, the nearest point's). false when p is on no part.
  bool to_rest(const Vec2& p, Vec2& rest) const;

 private:
  Studio() = default;
  struct State {
    std::string text;
    std::vector<std::pair<std::string, Vec2>> targets;  ///< by handle name
  };
  State state() const;
  /// Makes `text` the rig (parse, load, keep the pose as `targets` names it); "" or why not.
  std::string load(const std::string& text, const std::vector<std::pair<std::string, Vec2>>& targets);
  void restore(const State& s);
  std::string edit(const RigText& changed, std::vector<std::pair<std::string, Vec2>> targets);
  void push();

  std::string character_, rig_path_, mask_;
  RigText text_;
  std::string saved_;
  bool on_disk_ = false;
  Rig file_rig_;  ///< the text as parsed (its tables in file order, without drawn joints)
  std::unique_ptr<Puppet> puppet_;
  std::vector<std::string> roles_;  ///< per shape: a handle name after what the automatic rig sees it as
  std::vector<Vec2> targets_;
  std::vector<State> history_;
  size_t at_ = 0;
  // The sculpting tools.
  std::string prepare_tools();  ///< after a load: the stages on the new puppet (a sculpt is let go)
  void pen_curve(const Vec2& p);  ///< a stroke's point: the chain grows by the part under it
  std::string save_sculpt(const RigText& base, const std::string& name, RigText& out);
  Tool tool_ = Tool::Pose;
  double spacing_ = 0;  ///< the frame's (kSculptSpacing once a sculpting tool is chosen)
  double brush_scale_ = 1;
  BrushStage brush_;
  CurveStage curve_;
  ContourStage line_;
  ShowBrush brush_spec_;
  ShowCurve curve_spec_, line_spec_;
  Mapping::Pen pen_;
  bool pen_was_down_ = false;
  int from_ = -1;                 ///< the curve's: the part it hangs from
  std::vector<int> chain_;        ///< its parts
  std::vector<Vec2> stroke_;      ///< its stroke as drawn
  int leaves_ = -1;               ///< its first point off the part it hangs from (-1: none yet)
  std::vector<Vec2> solve_targets_;
};

}  // namespace mar
