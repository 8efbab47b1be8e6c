// The window's heads-up display, for the performer only: it is drawn on the window over the
// canvas, never into the canvas that dumps and outputs use. A bar shows the share of the frame
// budget the last frame used (green below half, amber, red above 80%); text lines say the frame
// time against the budget, the iterations and the pose quality; each device with its status and
// its last control; each binding's target and value, and where a control waiting for soft
// takeover must go to pick its target up. Glyphs are prepared at load (render/text.h) and the
// lines are fixed buffers: a frame with the HUD allocates nothing.
#pragma once

#include "app/show.h"
#include "character/character.h"
#include "devices/device.h"
#include "input/event.h"
#include "input/mapping.h"
#include "render/text.h"

#include <array>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

struct SDL_Renderer;

namespace mar {

/// One control event as the HUD names it ("cc 7 = 64 ch 1", "usage 0x10030 = 0.52", "button 2
/// down"), into `out` (always terminated).
void format_event(const Event& e, char* out, size_t n);

/// Where the character is on the window, for the HUD to keep off: its box, split into n x n
/// cells, each 1 where the drawing covers the cell's centre.
struct HudAvoid {
  int x = 0, y = 0, w = 0, h = 0;
  int n = 0;
  const uint8_t* cells = nullptr;  ///< n * n, row by row
};

/// Which of the n x n cells of `box` the character's filled shapes cover at rest (their centres
/// inside a shown, filled shape), row by row: HudAvoid's cells. `to_character`: box space to
/// the character's units (a cast's box is on the canvas). At load, not in a frame.
std::vector<uint8_t> cover_cells(const Character& ch, const Bounds& box, int n, const Affine2& to_character = Affine2::identity());

/// What one frame's HUD reports.
struct HudFrame {
  double used_us = 0, budget_us = 0;  ///< the last frame's work and the frame period
  int iterations = 0, iterations_wanted = 0;
  double quality_pct = 0;             ///< the worst part's distortion, % of the character's height
  std::span<const DeviceState> devices;
  std::span<const Event> last_events; ///< per device (kind None: nothing yet)
};

class Hud {
 public:
  /// The text lines' room for a show: a header, a line per device and per binding.
  explicit Hud(const ShowConfig& show);
  /// Glyphs for renderer `r` (the window's). Without a font the HUD draws its bar only and the
  /// returned message says why.
  std::string load_font(SDL_Renderer* r);
  /// Draws the HUD on `r` over a window of w x h pixels. Its lines fit the window: narrower than
  /// the full lines, it drops the padded columns (and the device column of bindings), and a line
  /// still too long is cut at a glyph with "..". The panel goes in the corner that covers the
  /// least of `avoid` (the character on the window), top left among equals.
  void draw(SDL_Renderer* r, int w, int h, const HudFrame& f, const Mapping& m, const HudAvoid* avoid = nullptr);
  /// A line under the header until replaced: what a reload did (green) or why an edit was
  /// refused, with its file:line (red, `error`). Empty: none. Between frames (it copies).
  void set_notice(std::string_view text, bool error);
  /// The text of the last draw, a line each (tests).
  size_t line_count() const { return n_; }
  const char* line(size_t i) const { return lines_[i].text.data(); }

 private:
  struct Line {
    std::array<char, 160> text{};
    SDL_Color color{235, 235, 235, 255};
  };
  Line& next();
  void format(const HudFrame& f, const Mapping& m, bool compact);
  int widest() const;
  Line notice_;
  const ShowConfig& show_;
  std::vector<Line> lines_;
  size_t n_ = 0;
  std::unique_ptr<GlyphAtlas> font_;
};

}  // namespace mar
