#include "app/loop/hud.h"
#include "hud_show.h"

#include <SDL.h>
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

namespace mar {
namespace {

// A software renderer on a surface: what the HUD draws on a window, without a display.
struct Surface {
  SDL_Surface* s = SDL_CreateRGBSurfaceWithFormat(0, 640, 240, 32, SDL_PIXELFORMAT_ABGR8888);
  SDL_Renderer* r = SDL_CreateSoftwareRenderer(s);
  ~Surface() {
    SDL_DestroyRenderer(r);
    SDL_FreeSurface(s);
  }
  std::array<int, 4> pixel(int x, int y) const {
    const auto* p = static_cast<const uint8_t*>(s->pixels) + y * s->pitch + x * 4;
    return {p[0], p[1], p[2], p[3]};
  }
  void clear() {
    SDL_SetRenderDrawColor(r, 255, 255, 255, 255);
    SDL_RenderClear(r);
  }
};

using ShowSetup = test::HudShow;

Event cc(int number, int value) {
  Event e;
  e.kind = ControlKind::MidiCC;
  e.number = uint32_t(number);
  e.value = value;
  e.lo = 0;
  e.hi = 127;
  return e;
}

bool contains(const Hud& h, const std::string& text) {
  for (size_t i = 0; i < h.line_count(); ++i)
    if (std::strstr(h.line(i), text.c_str())) return true;
  return false;
}

// The HUD speaks: frame time against the budget, iterations, quality; each device's status and
// last control; each binding's target and value; where a waiting control must go.
TEST(Hud, SaysWhatTheShowIsDoing) {
  ShowSetup s;
  Hud hud(s.show);
  Surface out;
  ASSERT_EQ(hud.load_font(out.r), "") << "fonts-dejavu-core is installed by the test command";
  s.m.update(0);
  s.m.apply(cc(7, 127));  // the fader is far from the target (0): soft takeover waits
  const DeviceState states[] = {DeviceState::Connected, DeviceState::Unplugged};
  const Event last[] = {cc(7, 127), Event{}};
  out.clear();
  hud.draw(out.r, 640, 240, HudFrame{9100, 16667, 7, 8, 0.12, states, last}, s.m);
  SDL_RenderFlush(out.r);
  EXPECT_TRUE(contains(hud, "frame 9.10 ms of 16.7 ms")) << hud.line(0);
  EXPECT_TRUE(contains(hud, "iterations 7 of 8"));
  EXPECT_TRUE(contains(hud, "quality 0.12 %"));
  EXPECT_TRUE(contains(hud, "korg")) << hud.line(1);
  EXPECT_TRUE(contains(hud, "connected"));
  EXPECT_TRUE(contains(hud, "last: cc 7 = 127 ch 1"));
  EXPECT_TRUE(contains(hud, "unplugged"));
  EXPECT_TRUE(contains(hud, "cc 7") && contains(hud, "-> handle.head.y = 0.0"));
  EXPECT_TRUE(contains(hud, "move it to 0 % to pick up (now 100 %)"));
  // Text is drawn: light glyph pixels on the dark panel, in the first text row.
  int light = 0;
  for (int y = 26; y < 26 + 14; ++y)
    for (int x = 16; x < 300; ++x) light += out.pixel(x, y)[0] > 150;
  EXPECT_GT(light, 100);
  // The budget bar: 55 % of the budget is amber, drawn to 10 + 0.55 x 620.
  const auto bar = out.pixel(12, 13), rest = out.pixel(600, 13);
  EXPECT_GT(bar[0], 200);
  EXPECT_LT(rest[0], 255);
  // Picked up: the waiting line goes.
  s.m.apply(cc(7, 0));
  hud.draw(out.r, 640, 240, HudFrame{1000, 16667, 8, 8, 0.1, states, last}, s.m);
  EXPECT_FALSE(contains(hud, "pick up"));
  EXPECT_TRUE(contains(hud, "-> handle.head.y = 0.0"));
}

// The HUD in a 360x480 show (the shipped singer on an APC mini): its lines fit the window (the
// compact columns, then cut with ".."), never past its right edge; bindings are named as the
// show names them; the panel goes to the corner that covers the least of the drawing.
TEST(Hud, FitsANarrowWindowAndKeepsOffTheDrawing) {
  ShowSetup s;
  for (int k = 1; k <= 8; ++k) {
    Binding b = s.show.bindings[0];
    b.control.text = "pad_r1c" + std::to_string(k);
    b.target_text = "swap.mouth.mouth-smile-and-a-very-long-member-name-" + std::to_string(k);
    b.tf.takeover = false;
    s.show.bindings.push_back(b);
    s.m.add_binding(b);
  }
  Hud hud(s.show);
  SDL_Surface* surf = SDL_CreateRGBSurfaceWithFormat(0, 360, 480, 32, SDL_PIXELFORMAT_ABGR8888);
  SDL_Renderer* r = SDL_CreateSoftwareRenderer(surf);
  ASSERT_EQ(hud.load_font(r), "");
  auto font = GlyphAtlas::load(r, default_font_path(), 13);
  ASSERT_TRUE(font.ok()) << font.error;
  const DeviceState states[] = {DeviceState::Connected, DeviceState::Connected};
  const Event last[] = {cc(7, 64), Event{}};
  // The drawing covers the top half (a head and shoulders): the panel goes to the bottom.
  std::vector<uint8_t> cells(16 * 16, 0);
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 16; ++i) cells[size_t(j * 16 + i)] = 1;
  const HudAvoid avoid{0, 0, 360, 480, 16, cells.data()};
  SDL_SetRenderDrawColor(r, 255, 255, 255, 255);
  SDL_RenderClear(r);
  hud.draw(r, 360, 480, HudFrame{4720, 16667, 8, 8, 0.19, states, last}, s.m, &avoid);
  SDL_RenderFlush(r);
  ASSERT_GT(hud.line_count(), 9u);
  for (size_t i = 0; i < hud.line_count(); ++i) EXPECT_LE((*font.value)->width(hud.line(i)), 360 - 32) << hud.line(i);
  EXPECT_TRUE(contains(hud, "pad_r1c3")) << "named as the show names it";
  EXPECT_TRUE(contains(hud, "..")) << "a line too long for the window is cut";
  // Nothing drawn in the rightmost column of the window, and the panel's dark pixels in the
  // bottom half, none in the top half below the bar.
  auto px = [&](int x, int y) { return static_cast<const uint8_t*>(surf->pixels)[y * surf->pitch + x * 4]; };
  int right = 0, top = 0, bottom = 0;
  for (int y = 0; y < 480; ++y) right += px(359, y) < 250;
  for (int y = 30; y < 200; ++y) top += px(20, y) < 200;
  for (int y = 280; y < 470; ++y) bottom += px(20, y) < 200;
  EXPECT_EQ(right, 0);
  EXPECT_EQ(top, 0);
  EXPECT_GT(bottom, 100);
  SDL_DestroyRenderer(r);
  SDL_FreeSurface(surf);
}

// A reload's notice: under the header until replaced, red for a refused edit with its file:line.
TEST(Hud, SaysWhatAReloadDidUnderTheHeader) {
  ShowSetup s;
  Hud hud(s.show);
  Surface out;
  ASSERT_EQ(hud.load_font(out.r), "");
  const DeviceState states[] = {DeviceState::Connected, DeviceState::Connected};
  const Event last[] = {Event{}, Event{}};
  const HudFrame f{1000, 16667, 8, 8, 0.1, states, last};
  hud.draw(out.r, 640, 240, f, s.m);
  const size_t plain = hud.line_count();
  hud.set_notice("edit refused: show.toml:12: the rig has no handle 'nose'", true);
  hud.draw(out.r, 640, 240, f, s.m);
  ASSERT_EQ(hud.line_count(), plain + 1);
  EXPECT_STREQ(hud.line(1), "edit refused: show.toml:12: the rig has no handle 'nose'");
  hud.set_notice("reloaded show.toml", false);
  hud.draw(out.r, 640, 240, f, s.m);
  EXPECT_STREQ(hud.line(1), "reloaded show.toml");
  EXPECT_EQ(hud.line_count(), plain + 1);
}

TEST(Hud, WithoutAFontItSaysWhyAndDrawsTheBar) {
  ShowSetup s;
  Hud hud(s.show);
  Surface out;
  setenv("MARIONETTE_FONT", "/nonexistent/font.ttf", 1);
  const std::string err = hud.load_font(out.r);
  unsetenv("MARIONETTE_FONT");
  EXPECT_NE(err.find("/nonexistent/font.ttf"), std::string::npos) << err;
  out.clear();
  hud.draw(out.r, 640, 240, HudFrame{15000, 16667, 8, 8, 0, {}, {}}, s.m);
  SDL_RenderFlush(out.r);
  const auto bar = out.pixel(12, 13);
  EXPECT_GT(bar[0], bar[1] + 60) << "over 80 % is red";
}

TEST(Hud, FormatsEveryKindOfEvent) {
  char buf[64];
  Event e = cc(1, 64);
  e.channel = 9;
  format_event(e, buf, sizeof buf);
  EXPECT_STREQ(buf, "cc 1 = 64 ch 10");
  e.kind = ControlKind::Button;
  e.number = 1;
  e.value = 1;
  format_event(e, buf, sizeof buf);
  EXPECT_STREQ(buf, "button 2 down");
  e.kind = ControlKind::EncoderDelta;
  e.value = -3;
  format_event(e, buf, sizeof buf);
  EXPECT_STREQ(buf, "encoder 2 -3");
  for (int k = 0; k <= int(ControlKind::Pressure); ++k) {
    e.kind = ControlKind(k);
    format_event(e, buf, 8);  // truncated, never overrun
    EXPECT_LT(std::strlen(buf), 8u);
  }
}

// Two performers on one target: the HUD says which binding holds it and which waits.
TEST(Hud, SaysWhoHoldsATargetTwoPerformersDrive) {
  ShowSetup s;
  Binding guest = s.show.bindings[0];
  guest.control.device = 1;
  guest.control.text = "cc 8";
  guest.control.number = 8;
  guest.tf.priority = {10, 1.0, 0.5};
  guest.tf.has_priority = true;
  s.show.bindings.push_back(guest);
  s.m.add_binding(guest);
  Hud hud(s.show);
  Surface out;
  ASSERT_EQ(hud.load_font(out.r), "");
  Event base = cc(7, 20), theirs = cc(8, 100);
  theirs.source = 1;
  s.m.apply(base);
  s.m.apply(theirs);
  s.m.update(1.0 / 60);
  const DeviceState states[] = {DeviceState::Connected, DeviceState::Connected};
  const Event last[] = {base, theirs};
  hud.draw(out.r, 640, 240, HudFrame{9100, 16667, 7, 8, 0.12, states, last}, s.m);
  bool base_waits = false, guest_holds = false;
  for (size_t i = 0; i < hud.line_count(); ++i) {
    const std::string l = hud.line(i);
    base_waits = base_waits || (l.find("cc 7") != std::string::npos && l.find("[waits]") != std::string::npos);
    guest_holds = guest_holds || (l.find("cc 8") != std::string::npos && l.find("[holds]") != std::string::npos);
  }
  EXPECT_TRUE(base_waits);
  EXPECT_TRUE(guest_holds);
}

}  // namespace
}  // namespace mar
