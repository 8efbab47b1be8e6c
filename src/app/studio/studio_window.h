// The rig studio's window: the character with its handles (green), hinges (purple) and, on F,
// the solver's frame, each labelled in the HUD's text; a status line and the keys along the
// top. Input is SDL's: a mouse, or a pen tablet as the window system gives it (pointer events,
// or touch events with their pressure), each the same gesture:
//   drag a handle        pose the character live (the solver runs every frame, as in a show)
//   click on a part      add a handle there          Delete / Backspace: remove the one under
//   drag a hinge         move it                     the pointer (or the last one touched)
//   scroll over a part   stiffer (up) or softer (down), x1.25 a notch
//   B, C                 the pen's tool: the brush (drag an outline: it moves by the Gaussian
//                        of its distance, radius by pressure, [ and ] size it) or the curve
//                        (draw from the part a chain hangs from through its parts: they take
//                        the stroke's curve); L the line (draw along an outline: it takes the
//                        stroke's course, its detail kept); the same key again: back to handles
//   K                    save the pose as a key (type its name, Enter; a sculpt saves the shape)
//   Ctrl+Z, Ctrl+Y       undo, redo (Ctrl+Shift+Z too)
//   F                    the frame overlay           R: every handle back at rest
//   S                    save the rig (atomically; comments and order kept)
//   Esc or Q             quit (twice when there are unsaved changes)
#pragma once

#include "app/studio/studio.h"
#include "render/canvas.h"
#include "render/text.h"

#include <SDL2/SDL_events.h>

#include <memory>
#include <string>
#include <vector>

namespace mar {

class StudioWindow {
 public:
  /// A window on `studio` (which must outlive it). `note` receives what the window could not
  /// have as asked; a missing font leaves the labels out and says so there.
  static Result<std::unique_ptr<StudioWindow>> open(Studio& studio, const WindowOptions& o, int width, int height,
                                                    std::string* note = nullptr);

  /// Handles every pending SDL event, solves one frame and draws it (the window's pixels are
  /// then readable: Canvas::read_window); present() shows it. false once the performer has quit.
  bool frame();
  void present() { canvas_->present(); }
  /// One event, as frame() handles it (tests may call it with events of their own).
  void handle(const SDL_Event& e);

  /// Where the character shows on a canvas of width x height: fitted below the status lines.
  static Affine2 character_view(const Character& ch, int width, int height);
  /// Where a point of the posed character shows, in the window's event coordinates.
  Vec2 window_point(const Vec2& p) const;
  /// The character point under a window point.
  Vec2 character_point(double x, double y) const;
  /// The text drawn in the last frame: the status lines, then every label.
  const std::vector<std::string>& text() const { return text_; }
  const std::string& status() const { return status_; }
  bool overlay() const { return overlay_; }
  Canvas& canvas() { return *canvas_; }

 private:
  StudioWindow(Studio& s) : studio_(s) {}
  void press(double x, double y);
  void motion(double x, double y);
  void release(double x, double y);
  void key(const SDL_KeyboardEvent& k);
  void say(const std::string& what, const std::string& error = "");
  void draw();
  Affine2 view() const;

  Studio& studio_;
  std::unique_ptr<Canvas> canvas_;
  std::unique_ptr<GlyphAtlas> font_;
  DrawList list_;
  std::vector<std::string> text_;
  std::string status_;
  bool overlay_ = false;
  bool quit_ = false, quit_armed_ = false;
  // A gesture: what the pointer went down on.
  enum class Drag { None, Handle, Hinge, Click, Sculpt } drag_ = Drag::None;
  int dragged_ = -1;                 ///< handle or hinge index
  Vec2 down_ = Vec2::Zero();         ///< where it went down (window)
  Vec2 hinge_to_ = Vec2::Zero();     ///< a hinge being dragged: where it would go (character)
  Vec2 grab_ = Vec2::Zero();         ///< a handle being dragged: its target less the pointer
  Vec2 pointer_ = Vec2(-1e9, -1e9);  ///< the pointer (character)
  int selected_ = -1;                ///< the last handle touched
  bool naming_ = false;              ///< typing a key's name
  bool skip_k_text_ = false;         ///< the text K's own press makes is not the name's
  std::string name_;
  double pressure_ = 0.5;            ///< the pen's (a mouse: half way)
};

}  // namespace mar
