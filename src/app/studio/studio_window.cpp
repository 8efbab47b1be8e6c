#include "app/studio/studio_window.h"

#include "render/overlay.h"

#include <SDL2/SDL.h>

#include <algorithm>
#include <cmath>
#include <string_view>
#include <cstdio>

namespace mar {

namespace {

constexpr double kPickPx = 12;   // how near (window pixels) a press must be to pick a handle or hinge
constexpr double kClickPx = 5;   // a press that moves less than this is a click
constexpr double kNotch = 1.25;  // stiffness per scroll notch
constexpr int kPanel = 64;       // canvas pixels kept clear of the character at the top, for the status lines

}  // namespace

Result<std::unique_ptr<StudioWindow>> StudioWindow::open(Studio& studio, const WindowOptions& o, int width, int height,
                                                         std::string* note) {
  using R = Result<std::unique_ptr<StudioWindow>>;
  std::unique_ptr<StudioWindow> w(new StudioWindow(studio));
  auto c = Canvas::window(o, width, height, note);
  if (!c.ok()) return R::failure(c.error);
  w->canvas_ = std::move(*c.value);
  auto f = GlyphAtlas::load(w->canvas_->window_renderer(), default_font_path(), 13);
  if (f.ok()) w->font_ = std::move(*f.value);
  else if (note) *note += (note->empty() ? "" : "; ") + ("no labels: " + f.error);
  // Text input stays on: K's keydown and the letters typed right after it can come in one batch
  // of X events, and SDL makes text only from keys it reads while text input is on (a fast
  // typist's first letter was lost). Keys are commands until K asks for a name; the text K
  // itself makes is dropped.
  SDL_StartTextInput();
  w->say(studio.on_disk() ? "editing " + studio.rig_path() : "the automatic rig; S saves it as " + studio.rig_path());
  return R::success(std::move(w));
}

Affine2 StudioWindow::character_view(const Character& ch, int width, int height) {
  return Affine2::translate(0, kPanel) * fit_view(ch.width, ch.height, width, std::max(1, height - kPanel), 24);
}

Affine2 StudioWindow::view() const { return character_view(studio_.puppet().character, canvas_->width(), canvas_->height()); }

// Window event coordinates <-> the canvas's pixels: the canvas shows letterboxed in the
// window's drawable, which a HiDPI screen makes larger than the window's coordinates.
Vec2 StudioWindow::window_point(const Vec2& p) const {
  const Vec2 c = view().apply(p);
  const SDL_Rect r = canvas_->canvas_rect();
  int ww = 0, wh = 0;
  SDL_GetWindowSize(const_cast<Canvas&>(*canvas_).sdl_window(), &ww, &wh);
  const double sx = ww > 0 ? double(canvas_->window_width()) / ww : 1, sy = wh > 0 ? double(canvas_->window_height()) / wh : 1;
  const double kx = r.w > 0 ? double(r.w) / canvas_->width() : 1, ky = r.h > 0 ? double(r.h) / canvas_->height() : 1;
  return {(r.x + c.x() * kx) / sx, (r.y + c.y() * ky) / sy};
}

Vec2 StudioWindow::character_point(double x, double y) const {
  const SDL_Rect r = canvas_->canvas_rect();
  int ww = 0, wh = 0;
  SDL_GetWindowSize(const_cast<Canvas&>(*canvas_).sdl_window(), &ww, &wh);
  const double sx = ww > 0 ? double(canvas_->window_width()) / ww : 1, sy = wh > 0 ? double(canvas_->window_height()) / wh : 1;
  const double kx = r.w > 0 ? double(r.w) / canvas_->width() : 1, ky = r.h > 0 ? double(r.h) / canvas_->height() : 1;
  return view().inverse().apply(Vec2((x * sx - r.x) / kx, (y * sy - r.y) / ky));
}

void StudioWindow::say(const std::string& what, const std::string& error) {
  status_ = error.empty() ? what : error;
  quit_armed_ = false;
}

void StudioWindow::press(double x, double y) {
  const Vec2 c = character_point(x, y);
  if (studio_.tool() != Studio::Tool::Pose) {  // the brush or the curve
    down_ = Vec2(x, y);
    pointer_ = c;
    drag_ = Drag::Sculpt;
    studio_.pen(c, true, pressure_);
    return;
  }
  const double unit = (window_point(c + Vec2(1, 0)) - window_point(c)).norm();
  const double r = kPickPx / std::max(unit, 1e-9);
  down_ = Vec2(x, y);
  pointer_ = c;
  if (const int h = studio_.handle_at(c, r); h >= 0) {
    drag_ = Drag::Handle;
    dragged_ = selected_ = h;
    grab_ = studio_.targets()[size_t(h)] - c;
  } else if (const int j = studio_.hinge_at(c, r); j >= 0) {
    drag_ = Drag::Hinge;
    dragged_ = j;
    hinge_to_ = studio_.hinges()[size_t(j)].at;
  } else {
    drag_ = Drag::Click;
  }
}

void StudioWindow::motion(double x, double y) {
  pointer_ = character_point(x, y);
  if (drag_ == Drag::Handle) studio_.set_target(size_t(dragged_), pointer_ + grab_);
  if (drag_ == Drag::Hinge) hinge_to_ = pointer_;
  if (drag_ == Drag::Sculpt) studio_.pen(pointer_, true, pressure_);
}

void StudioWindow::release(double x, double y) {
  motion(x, y);
  const bool moved = (Vec2(x, y) - down_).norm() >= kClickPx;
  const Drag d = drag_;
  drag_ = Drag::None;
  if (d == Drag::Sculpt) {
    studio_.pen(pointer_, false, 0);
    studio_.step();  // (the pen's lift: the stroke holds)
    if (studio_.tool() == Studio::Tool::Brush) {
      say(studio_.brush().points().empty() ? "no outline under the brush" : "brushed (K saves the sculpt as a key; R lets it go)");
    } else if (studio_.tool() == Studio::Tool::Line) {
      say(studio_.line().active() ? "redrew the outline (K saves it as a key; R lets it go)" : "start the stroke on an outline and draw along it");
    } else {
      const std::vector<std::string> chain = studio_.curve_chain();
      std::string names;
      for (size_t i = 1; i < chain.size(); ++i) names += (i > 1 ? ", " : "") + chain[i];
      say(chain.size() < 2 ? "start on the part a chain hangs from and draw through its parts"
                           : "the curve took " + names + " (hanging from " + chain[0] + "; K saves it as a key)");
    }
  } else if (d == Drag::Handle) {
    studio_.commit_pose();
    say("posed " + studio_.puppet().rig.handles[size_t(dragged_)].name + " (K saves the pose as a key)");
  } else if (d == Drag::Hinge && moved) {
    const std::string label = studio_.hinges()[size_t(dragged_)].label;
    const std::string err = studio_.move_hinge(size_t(dragged_), hinge_to_);
    say("moved the hinge " + label, err);
  } else if (d == Drag::Click && !moved) {
    const size_t before = studio_.puppet().rig.handles.size();
    const std::string err = studio_.add_handle(pointer_);
    if (err.empty() && studio_.puppet().rig.handles.size() > before) {
      selected_ = int(before);
      say("added the handle " + studio_.puppet().rig.handles[before].name + " (Delete removes it)");
    } else {
      say("", err);
    }
  }
}

void StudioWindow::key(const SDL_KeyboardEvent& k) {
  const SDL_Keycode sym = k.keysym.sym;
  if (naming_) {
    if (sym == SDLK_RETURN || sym == SDLK_KP_ENTER) {
      naming_ = false;
      const std::string err = studio_.save_key(name_);
      say("saved the key " + name_ + " (S writes the rig)", err);
    } else if (sym == SDLK_ESCAPE) {
      naming_ = false;
      say("no key saved");
    } else if (sym == SDLK_BACKSPACE && !name_.empty()) {
      name_.pop_back();
    }
    return;
  }
  const bool ctrl = (k.keysym.mod & KMOD_CTRL) != 0, shift = (k.keysym.mod & KMOD_SHIFT) != 0;
  if (ctrl && (sym == SDLK_z || sym == SDLK_y)) {
    const bool redo = sym == SDLK_y || shift;
    const bool done = redo ? studio_.redo() : studio_.undo();
    say(done ? (redo ? "redone" : "undone") : (redo ? "nothing to redo" : "nothing to undo"));
    selected_ = -1;
    return;
  }
  switch (sym) {
    case SDLK_s: {
      const std::string err = studio_.save();
      say("saved " + studio_.rig_path(), err);
      break;
    }
    case SDLK_f:
      overlay_ = !overlay_;
      say(overlay_ ? "frame shown (F hides it)" : "frame hidden (F shows it)");
      break;
    case SDLK_r:
      studio_.reset_pose();
      say("every handle at rest");
      break;
    case SDLK_b:
    case SDLK_c:
    case SDLK_l: {
      const Studio::Tool t = sym == SDLK_b ? Studio::Tool::Brush : sym == SDLK_c ? Studio::Tool::Curve : Studio::Tool::Line;
      const Studio::Tool want = studio_.tool() == t ? Studio::Tool::Pose : t;
      const std::string err = studio_.set_tool(want);
      say(want == Studio::Tool::Brush   ? "the brush: drag an outline (pressure or [ ] size it; B again: handles)"
          : want == Studio::Tool::Curve ? "the curve: draw from the part a chain hangs from through its parts (C again: handles)"
          : want == Studio::Tool::Line  ? "the line: draw along an outline and it takes the stroke's course (L again: handles)"
                                        : "posing handles",
          err);
      break;
    }
    case SDLK_LEFTBRACKET:
    case SDLK_RIGHTBRACKET:
      studio_.scale_brush(sym == SDLK_RIGHTBRACKET ? 1.25 : 0.8);
      say("brush size x" + std::to_string(studio_.brush_scale()).substr(0, 4));
      break;
    case SDLK_k:
      naming_ = true;
      name_.clear();
      skip_k_text_ = true;
      say("name the key, then Enter (Esc: none)");
      break;
    case SDLK_DELETE:
    case SDLK_BACKSPACE: {
      const double unit = (window_point(pointer_ + Vec2(1, 0)) - window_point(pointer_)).norm();
      int h = studio_.handle_at(pointer_, kPickPx / std::max(unit, 1e-9));
      if (h < 0) h = selected_;
      if (h < 0 || size_t(h) >= studio_.puppet().rig.handles.size()) {
        say("point at a handle to remove it");
        break;
      }
      const std::string name = studio_.puppet().rig.handles[size_t(h)].name;
      const std::string err = studio_.remove_handle(size_t(h));
      if (err.empty()) selected_ = -1;
      say("removed the handle " + name, err);
      break;
    }
    case SDLK_ESCAPE:
    case SDLK_q:
      if (studio_.dirty() && !quit_armed_) {
        say("unsaved changes: S saves them; " + std::string(sym == SDLK_q ? "Q" : "Esc") + " again quits without saving");
        quit_armed_ = true;
      } else {
        quit_ = true;
      }
      break;
    default: break;
  }
}

void StudioWindow::handle(const SDL_Event& e) {
  int ww = 1, wh = 1;
  SDL_GetWindowSize(canvas_->sdl_window(), &ww, &wh);
  switch (e.type) {
    case SDL_QUIT:
      if (studio_.dirty() && !quit_armed_) {
        say("unsaved changes: S saves them; close again to quit without saving");
        quit_armed_ = true;
      } else {
        quit_ = true;
      }
      break;
    // A pen or a finger on a tablet the window system reports as touch: the same gestures.
    // SDL also makes mouse events of them (SDL_TOUCH_MOUSEID), which are skipped.
    case SDL_FINGERDOWN:
      pressure_ = std::clamp(double(e.tfinger.pressure), 0.0, 1.0);
      press(e.tfinger.x * ww, e.tfinger.y * wh);
      break;
    case SDL_FINGERMOTION:
      pressure_ = std::clamp(double(e.tfinger.pressure), 0.0, 1.0);
      motion(e.tfinger.x * ww, e.tfinger.y * wh);
      break;
    case SDL_FINGERUP: release(e.tfinger.x * ww, e.tfinger.y * wh); break;
    case SDL_MOUSEBUTTONDOWN:
      if (e.button.which != SDL_TOUCH_MOUSEID && e.button.button == SDL_BUTTON_LEFT) {
        pressure_ = 0.5;  // (a mouse has none: half way)
        press(e.button.x, e.button.y);
      }
      break;
    case SDL_MOUSEMOTION:
      if (e.motion.which != SDL_TOUCH_MOUSEID) motion(e.motion.x, e.motion.y);
      break;
    case SDL_MOUSEBUTTONUP:
      if (e.button.which != SDL_TOUCH_MOUSEID && e.button.button == SDL_BUTTON_LEFT) release(e.button.x, e.button.y);
      break;
    case SDL_MOUSEWHEEL: {
      if (e.wheel.which == SDL_TOUCH_MOUSEID || e.wheel.y == 0) break;
      const int notches = e.wheel.direction == SDL_MOUSEWHEEL_FLIPPED ? -e.wheel.y : e.wheel.y;
      const int part = studio_.part_at(pointer_);
      const std::string err = studio_.scale_stiffness(part, std::pow(kNotch, notches));
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.2f", studio_.stiffness(part));
      say(studio_.part_name(part) + " stiffness " + buf, err);
      break;
    }
    case SDL_TEXTINPUT:
      if (naming_ && !(skip_k_text_ && (std::string_view(e.text.text) == "k" || std::string_view(e.text.text) == "K"))) name_ += e.text.text;
      skip_k_text_ = false;
      break;
    case SDL_KEYDOWN: key(e.key); break;
    default: break;
  }
}

bool StudioWindow::frame() {
  SDL_Event e;
  while (SDL_PollEvent(&e)) handle(e);
  if (quit_) return false;
  studio_.step();
  draw();
  return true;
}

void StudioWindow::draw() {
  const Puppet& p = studio_.puppet();
  const Affine2 v = view();
  canvas_->clear(Rgba{0.95, 0.95, 0.94, 1});
  list_.clear();
  list_.fringe = canvas_->wants_fringe();
  build_draw_list(p.character, p.mesh, p.shapes, v, 0.25, list_, p.shown);
  std::vector<Vec2> handles(p.rig.handles.size());
  for (size_t h = 0; h < handles.size(); ++h) handles[h] = studio_.handle_point(h);
  const std::vector<StudioHinge> hinges = studio_.hinges();
  std::vector<Vec2> hinge_points;
  for (size_t j = 0; j < hinges.size(); ++j)
    hinge_points.push_back(drag_ == Drag::Hinge && int(j) == dragged_ ? hinge_to_ : hinges[j].at);
  if (overlay_) append_solver_overlay(p, {}, v, list_);
  append_markers(handles, hinge_points, selected_, v, list_);
  if (studio_.tool() == Studio::Tool::Brush)
    append_pen_marks(pointer_, drag_ == Drag::Sculpt && studio_.brush().down() ? studio_.brush().radius() : studio_.brush_radius(pressure_),
                     {}, v, list_);
  if ((studio_.tool() == Studio::Tool::Curve || studio_.tool() == Studio::Tool::Line) && drag_ == Drag::Sculpt)
    append_pen_marks(pointer_, 0, studio_.stroke(), v, list_);
  if (std::string err = canvas_->draw(list_); !err.empty()) say("", err);
  canvas_->compose();

  // The text: status lines on a panel along the top, then a label beside each marker.
  text_.clear();
  const int hovered = studio_.part_at(pointer_);
  const double unit = (window_point(pointer_ + Vec2(1, 0)) - window_point(pointer_)).norm();
  const int hovered_hinge = studio_.hinge_at(pointer_, kPickPx / std::max(unit, 1e-9));
  char buf[256];
  const char* tool = studio_.tool() == Studio::Tool::Brush   ? "   [brush]"
                     : studio_.tool() == Studio::Tool::Curve ? "   [curve]"
                     : studio_.tool() == Studio::Tool::Line  ? "   [line]"
                                                             : "";
  std::snprintf(buf, sizeof buf, "%s%s   %zu handles, %zu hinges%s%s", studio_.rig_path().c_str(),
                studio_.dirty() ? " (unsaved)" : "", handles.size(), hinges.size(), overlay_ ? ", frame" : "", tool);
  text_.push_back(buf);
  if (naming_) {
    text_.push_back("key name: " + name_ + "_");
  } else if (hovered_hinge >= 0) {
    text_.push_back("hinge " + hinges[size_t(hovered_hinge)].label + " (drag to move)   " + status_);
  } else if (hovered >= 0) {
    std::snprintf(buf, sizeof buf, "%s: stiffness %.2f (scroll to change)   %s", studio_.part_name(hovered).c_str(),
                  studio_.stiffness(hovered), status_.c_str());
    text_.push_back(buf);
  } else {
    text_.push_back(status_);
  }
  text_.push_back("drag handles and hinges  click: add  Del: remove  B: brush  C: curve  L: line  K: key  Ctrl+Z/Y: undo/redo  F: frame  R: rest  S: save");
  const size_t status_lines = text_.size();
  for (size_t h = 0; h < handles.size(); ++h) text_.push_back(p.rig.handles[h].name);
  for (const StudioHinge& j : hinges) text_.push_back(j.label);
  if (!font_) return;
  SDL_Renderer* r = canvas_->window_renderer();
  const int lh = font_->line_height();
  int ww = 1, wh = 1;
  SDL_GetWindowSize(canvas_->sdl_window(), &ww, &wh);
  const double sx = double(canvas_->window_width()) / std::max(ww, 1), sy = double(canvas_->window_height()) / std::max(wh, 1);
  SDL_SetRenderDrawBlendMode(r, SDL_BLENDMODE_BLEND);
  SDL_SetRenderDrawColor(r, 20, 20, 24, 190);
  const SDL_Rect panel{0, 0, canvas_->window_width(), int(status_lines) * lh + 12};
  SDL_RenderFillRect(r, &panel);
  for (size_t i = 0; i < status_lines; ++i)
    font_->draw(r, 10, 6 + int(i) * lh, text_[i], i == 1 && !status_.empty() ? SDL_Color{255, 214, 120, 255} : SDL_Color{235, 235, 235, 255});
  // Each label beside its marker where it covers no label placed before it (right, then left,
  // above, then below), else where it overlaps least.
  std::vector<SDL_Rect> placed;
  auto label = [&](const Vec2& at, const std::string& s, SDL_Color fg) {
    const Vec2 w = window_point(at);
    const int mx = int(w.x() * sx), my = int(w.y() * sy), tw = font_->width(s) + 4, th = lh + 2;
    const SDL_Rect tries[] = {{mx + 9, my - th - 3, tw, th}, {mx + 9, my + 3, tw, th}, {mx - 9 - tw, my - th - 3, tw, th},
                              {mx - 9 - tw, my + 3, tw, th}, {mx - tw / 2, my + 10, tw, th}, {mx - tw / 2, my - th - 10, tw, th}};
    SDL_Rect best = tries[0];
    int least = -1;
    for (const SDL_Rect& t : tries) {
      int overlap = 0;
      for (const SDL_Rect& o : placed) {
        SDL_Rect x;
        if (SDL_IntersectRect(&t, &o, &x)) overlap += x.w * x.h;
      }
      if (least < 0 || overlap < least) {
        least = overlap;
        best = t;
      }
      if (overlap == 0) break;
    }
    placed.push_back(best);
    SDL_SetRenderDrawColor(r, 255, 255, 255, 210);
    SDL_RenderFillRect(r, &best);
    font_->draw(r, best.x + 2, best.y + 1, s, fg);
  };
  for (size_t h = 0; h < handles.size(); ++h) label(handles[h], p.rig.handles[h].name, SDL_Color{0, 100, 45, 255});
  // Hinges are named with the frame shown, or under the pointer (their names are long).
  for (size_t j = 0; j < hinges.size(); ++j)
    if (overlay_ || int(j) == hovered_hinge || (drag_ == Drag::Hinge && int(j) == dragged_))
      label(hinge_points[j], hinges[j].label, SDL_Color{110, 20, 160, 255});
}

}  // namespace mar
