#include "app/loop/hud.h"

#include <SDL.h>

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace mar {

void format_event(const Event& e, char* out, size_t n) {
  if (n == 0) return;
  const int ch = e.channel + 1;
  switch (e.kind) {
    case ControlKind::None: std::snprintf(out, n, "-"); break;
    case ControlKind::MidiNoteOn: std::snprintf(out, n, "note %" PRIu32 " on %" PRId32 " ch %d", e.number, e.value, ch); break;
    case ControlKind::MidiNoteOff: std::snprintf(out, n, "note %" PRIu32 " off ch %d", e.number, ch); break;
    case ControlKind::MidiCC: std::snprintf(out, n, "cc %" PRIu32 " = %" PRId32 " ch %d", e.number, e.value, ch); break;
    case ControlKind::MidiPitchBend: std::snprintf(out, n, "pitch bend %" PRId32 " ch %d", e.value, ch); break;
    case ControlKind::MidiProgram: std::snprintf(out, n, "program %" PRId32 " ch %d", e.value, ch); break;
    case ControlKind::MidiChannelPressure: std::snprintf(out, n, "pressure %" PRId32 " ch %d", e.value, ch); break;
    case ControlKind::MidiPolyPressure:
      std::snprintf(out, n, "poly pressure %" PRIu32 " = %" PRId32 " ch %d", e.number, e.value, ch);
      break;
    case ControlKind::HidValue: std::snprintf(out, n, "usage 0x%" PRIx32 " = %.2f", e.number, normalized(e)); break;
    case ControlKind::EncoderDelta: std::snprintf(out, n, "encoder %" PRIu32 " %+" PRId32, e.number + 1, e.value); break;
    case ControlKind::Button: std::snprintf(out, n, "button %" PRIu32 " %s", e.number + 1, e.value ? "down" : "up"); break;
    case ControlKind::PointerX: std::snprintf(out, n, "pointer x %.2f", normalized(e)); break;
    case ControlKind::PointerY: std::snprintf(out, n, "pointer y %.2f", normalized(e)); break;
    case ControlKind::Pressure: std::snprintf(out, n, "pressure %.2f", normalized(e)); break;
    case ControlKind::ClockPhase:
      if (e.number == kClockTempo) std::snprintf(out, n, "tempo %.1f BPM", double(e.value) * 1e-3);
      else std::snprintf(out, n, "%s %.2f", e.number == kClockBeat ? "beat" : "bar", normalized(e));
      break;
  }
}

std::vector<uint8_t> cover_cells(const Character& ch, const Bounds& box, int n, const Affine2& to_character) {
  std::vector<uint8_t> cells(size_t(n) * size_t(n), 0);
  for (int j = 0; j < n && !box.empty(); ++j)
    for (int i = 0; i < n; ++i) {
      const Vec2 q = to_character.apply(
          Vec2(box.lo.x() + (i + 0.5) * (box.hi.x() - box.lo.x()) / n, box.lo.y() + (j + 0.5) * (box.hi.y() - box.lo.y()) / n));
      for (const SubShape& s : ch.shapes)
        if (s.fill.enabled && !s.hidden && s.contains(q)) {
          cells[size_t(j * n + i)] = 1;
          break;
        }
    }
  return cells;
}

Hud::Hud(const ShowConfig& show) : show_(show), lines_(3 + show.devices.size() + show.bindings.size() * 2) {}

void Hud::set_notice(std::string_view text, bool error) {
  const size_t n = std::min(text.size(), notice_.text.size() - 1);
  std::copy_n(text.data(), n, notice_.text.data());
  notice_.text[n] = 0;
  notice_.color = error ? SDL_Color{240, 90, 90, 255} : SDL_Color{120, 220, 120, 255};
}

std::string Hud::load_font(SDL_Renderer* r) {
  auto f = GlyphAtlas::load(r, default_font_path(), 13);
  if (!f.ok()) return f.error;
  font_ = std::move(*f.value);
  return {};
}

Hud::Line& Hud::next() {
  Line& l = lines_[std::min(n_, lines_.size() - 1)];
  n_ = std::min(n_ + 1, lines_.size());
  l.color = SDL_Color{235, 235, 235, 255};
  return l;
}

void Hud::format(const HudFrame& f, const Mapping& m, bool compact) {
  n_ = 0;
  {
    Line& l = next();
    if (compact)
      std::snprintf(l.text.data(), l.text.size(), "%.2f / %.1f ms  it %d/%d  q %.2f%%", f.used_us * 1e-3, f.budget_us * 1e-3,
                    f.iterations, f.iterations_wanted, f.quality_pct);
    else
      std::snprintf(l.text.data(), l.text.size(), "frame %.2f ms of %.1f ms   iterations %d of %d   quality %.2f %%",
                    f.used_us * 1e-3, f.budget_us * 1e-3, f.iterations, f.iterations_wanted, f.quality_pct);
  }
  if (notice_.text[0]) next() = notice_;  // what the last reload did, or why it was refused
  static constexpr SDL_Color kState[] = {{240, 180, 60, 255},    // waiting
                                         {120, 220, 120, 255},   // connected
                                         {240, 90, 90, 255},     // unplugged
                                         {240, 90, 90, 255},     // permission denied
                                         {170, 170, 170, 255}};  // unavailable
  for (size_t i = 0; i < show_.devices.size(); ++i) {
    const ShowDevice& d = show_.devices[i];
    const DeviceState st = i < f.devices.size() ? f.devices[i] : DeviceState::Connected;
    char last[64] = "-";
    if (i < f.last_events.size()) format_event(f.last_events[i], last, sizeof last);
    Line& l = next();
    const char* state = d.type == "sim" ? "simulated" : device_state_name(st);
    if (compact)
      std::snprintf(l.text.data(), l.text.size(), "%s %s: %s", d.name.c_str(), state, last);
    else
      std::snprintf(l.text.data(), l.text.size(), "%-10.10s %-8.8s %-17.17s last: %s", d.name.c_str(), d.type.c_str(), state, last);
    l.color = kState[std::min(size_t(st), std::size(kState) - 1)];
  }
  const bool one_device = show_.devices.size() <= 1;
  for (size_t i = 0; i < m.binding_count(); ++i) {
    const Binding& b = m.binding(i);
    const char* dev = b.control.device < show_.devices.size() ? show_.devices[b.control.device].name.c_str() : "?";
    const char* ctl = b.control.text.c_str();
    const double v = m.binding_value(i);
    Line& l = next();
    char value[32] = "";
    if (!std::isnan(v)) std::snprintf(value, sizeof value, " = %.1f", v);
    // Under priorities: whether this binding holds its target or waits for its holder to let go.
    const int holds = m.holds(i);
    const char* who = holds < 0 ? "" : holds ? (compact ? " *" : "  [holds]") : (compact ? " ~" : "  [waits]");
    if (compact)
      std::snprintf(l.text.data(), l.text.size(), "%s%s%s > %s%s%s", one_device ? "" : dev, one_device ? "" : " ", ctl,
                    b.target_text.c_str(), value, who);
    else
      std::snprintf(l.text.data(), l.text.size(), "%-10.10s %-14.14s -> %s%s%s", dev, ctl, b.target_text.c_str(), value, who);
    if (holds == 0) l.color = SDL_Color{170, 170, 170, 255};
    if (const double at = m.takeover_at(i); at >= 0) {
      Line& t = next();
      if (compact)
        std::snprintf(t.text.data(), t.text.size(), "  takeover: move to %.0f%% (now %.0f%%)", at * 100,
                      std::clamp(b.last_norm, 0.0, 1.0) * 100);
      else
        std::snprintf(t.text.data(), t.text.size(), "    waiting for soft takeover: move it to %.0f %% to pick up (now %.0f %%)",
                      at * 100, std::clamp(b.last_norm, 0.0, 1.0) * 100);
      t.color = SDL_Color{240, 180, 60, 255};
    }
  }
}

int Hud::widest() const {
  int tw = 0;
  for (size_t i = 0; i < n_; ++i) tw = std::max(tw, font_->width(lines_[i].text.data()));
  return tw;
}

void Hud::draw(SDL_Renderer* r, int w, int h, const HudFrame& f, const Mapping& m, const HudAvoid* avoid) {
  // The text, into the fixed lines: the full columns where they fit, else the compact ones.
  format(f, m, false);
  const int room = std::max(1, w - 20) - 12;  // the panel's inside
  if (font_ && widest() > room) format(f, m, true);
  // A line still too long is cut at the last glyph that fits, with "..".
  if (font_) {
    for (size_t i = 0; i < n_; ++i) {
      char* t = lines_[i].text.data();
      const size_t len = std::strlen(t);
      if (font_->width(t) <= room) continue;
      // The longest prefix that fits with "..", found by halving (a few measures a line).
      char trial[sizeof(Line::text)];
      size_t lo = 0, hi = std::min(len, sizeof trial - 3);
      while (lo < hi) {
        const size_t mid = (lo + hi + 1) / 2;
        std::snprintf(trial, sizeof trial, "%.*s..", int(mid), t);
        if (font_->width(trial) <= room) lo = mid;
        else hi = mid - 1;
      }
      std::snprintf(trial, sizeof trial, "%.*s..", int(lo), t);
      std::snprintf(t, lines_[i].text.size(), "%s", trial);
    }
  }
  // The bar, then the text on a dark panel.
  SDL_SetRenderDrawBlendMode(r, SDL_BLENDMODE_BLEND);
  const int bw = std::max(1, w - 20);
  SDL_SetRenderDrawColor(r, 0, 0, 0, 90);
  SDL_Rect bg{10, 10, bw, 8};
  SDL_RenderFillRect(r, &bg);
  const double share = f.budget_us > 0 ? std::min(1.0, f.used_us / f.budget_us) : 1.0;
  SDL_SetRenderDrawColor(r, share < 0.5 ? 60 : 230, share < 0.8 ? 180 : 60, 60, 220);
  SDL_Rect bar{10, 10, int(bw * share), 8};
  SDL_RenderFillRect(r, &bar);
  if (!font_) return;
  const int lh = font_->line_height();
  const int tw = widest();
  const int rows = std::min(int(n_), std::max(1, (h - 30) / std::max(1, lh)));
  SDL_Rect panel{10, 22, std::min(tw + 12, bw), rows * lh + 8};
  // The corner that covers the least of the character (the first of equals: top left).
  if (avoid) {
    const SDL_Rect corners[] = {{10, 22, panel.w, panel.h},
                                {w - 10 - panel.w, 22, panel.w, panel.h},
                                {10, h - 10 - panel.h, panel.w, panel.h},
                                {w - 10 - panel.w, h - 10 - panel.h, panel.w, panel.h}};
    long best = -1;
    for (const SDL_Rect& c : corners) {
      long covered = 0;  // the drawing's cells under the panel
      for (int j = 0; j < avoid->n && avoid->cells; ++j)
        for (int i = 0; i < avoid->n; ++i) {
          const int cx = avoid->x + (2 * i + 1) * avoid->w / (2 * avoid->n), cy = avoid->y + (2 * j + 1) * avoid->h / (2 * avoid->n);
          covered += avoid->cells[j * avoid->n + i] && cx >= c.x && cx < c.x + c.w && cy >= c.y && cy < c.y + c.h;
        }
      if (best < 0 || covered < best) {
        best = covered;
        panel = c;
      }
    }
  }
  SDL_SetRenderDrawColor(r, 0, 0, 0, 150);
  SDL_RenderFillRect(r, &panel);
  for (int i = 0; i < rows; ++i)
    font_->draw(r, panel.x + 6, panel.y + 4 + i * lh, lines_[size_t(i)].text.data(), lines_[size_t(i)].color);
}

}  // namespace mar
