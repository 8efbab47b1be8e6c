// The rig studio: each action on the model (drag, add, remove, move a hinge, stiffness, key,
// undo and redo, save), checked in the rig's text and the posed character; then each action
// again in a window under Xvfb, driven by synthesized SDL input events (a mouse and a pen's
// touch events) through SDL's own queue, down to the saved file.
#include "app/studio/studio.h"
#include "app/studio/studio_window.h"
#include "character/rig.h"
#include "render/image.h"
#include "test_util.h"

#include <SDL2/SDL.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace mar {
namespace {

namespace fs = std::filesystem;

std::string read_all(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

size_t count_of(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// Whether every line of `before` is in `after`, in the same order.
bool lines_kept(const std::string& before, const std::string& after) {
  std::istringstream a(before), b(after);
  std::string la, lb;
  while (std::getline(a, la)) {
    bool found = false;
    while (!found && std::getline(b, lb)) found = lb == la;
    if (!found) return false;
  }
  return true;
}

// A folder with the cat and its hand-written rig (comments and all), as a performer has them.
fs::path cat_folder(const std::string& name) {
  const fs::path dir = test::temp_dir("studio_" + name);
  fs::create_directories(dir / "rigs");
  fs::create_directories(dir / "characters");
  fs::copy_file(test::characters_dir() / "cat.svg", dir / "characters" / "cat.svg", fs::copy_options::overwrite_existing);
  fs::copy_file(test::source_dir() / "config/rigs/cat.toml", dir / "rigs" / "cat.toml", fs::copy_options::overwrite_existing);
  return dir;
}

std::unique_ptr<Studio> open_cat(const fs::path& dir, bool automatic = false) {
  const fs::path rig = automatic ? dir / "auto.toml" : dir / "rigs" / "cat.toml";
  auto s = Studio::open((dir / "characters" / "cat.svg").string(), rig.string());
  EXPECT_TRUE(s.ok()) << s.error;
  return s.ok() ? std::move(*s.value) : nullptr;
}

int handle_named(const Studio& s, const std::string& name) { return s.puppet().rig.find_handle(name); }

// Where handle h goes when its limb turns `deg` degrees about the hinge it hangs from: a target
// the limb reaches.
Vec2 swing(const Studio& s, size_t h, double deg) {
  const Vec2 p = s.handle_point(h);
  const int part = s.part_at(p);
  Vec2 pivot = p;
  double best = 1e300;
  for (const StudioHinge& j : s.hinges())
    if ((j.shape_a == part || j.shape_b == part) && (j.at - p).norm() < best) {
      best = (j.at - p).norm();
      pivot = j.at;
    }
  EXPECT_LT(best, 1e300) << "a hinge on the part under handle " << h;
  const double r = deg * M_PI / 180, c = std::cos(r), sn = std::sin(r);
  const Vec2 d = p - pivot;
  return pivot + Vec2(c * d.x() - sn * d.y(), sn * d.x() + c * d.y());
}

TEST(Studio, WithoutARigFileItIsTheAutomaticRigAndSaveWritesIt) {
  const fs::path dir = cat_folder("auto");
  auto s = open_cat(dir, true);
  ASSERT_TRUE(s);
  EXPECT_FALSE(s->on_disk());
  EXPECT_TRUE(s->dirty());
  EXPECT_GE(s->puppet().rig.handles.size(), 5u);
  EXPECT_GE(s->hinges().size(), 4u) << "the legs, tail, ears and head hang from the body";
  ASSERT_EQ(s->save(), "");
  EXPECT_FALSE(s->dirty());
  EXPECT_EQ(read_all(dir / "auto.toml"), s->text());
  EXPECT_FALSE(fs::exists(dir / "auto.toml.tmp"));
  auto p = load_puppet("", (dir / "auto.toml").string());
  ASSERT_TRUE(p.ok()) << p.error << " (the saved rig names its character relative to itself)";
}

TEST(Studio, DraggingAHandlePosesLiveAndUndoRedoTheDrag) {
  auto s = open_cat(cat_folder("drag"));
  ASSERT_TRUE(s);
  const int tail = handle_named(*s, "tail");
  ASSERT_GE(tail, 0);
  const Vec2 rest = s->handle_point(size_t(tail)), to = swing(*s, size_t(tail), 25);
  for (int f = 1; f <= 10; ++f) {  // a drag over ten frames, the solver running each
    s->set_target(size_t(tail), rest + (to - rest) * (f / 10.0));
    s->step();
  }
  for (int f = 0; f < 30; ++f) s->step();
  EXPECT_LT((s->handle_point(size_t(tail)) - to).norm(), 2.0) << "the tail follows the drag";
  s->commit_pose();
  EXPECT_FALSE(s->dirty()) << "a pose is not an edit of the rig";
  ASSERT_TRUE(s->undo());
  EXPECT_LT((s->handle_point(size_t(tail)) - rest).norm(), 0.5);
  ASSERT_TRUE(s->redo());
  EXPECT_LT((s->handle_point(size_t(tail)) - to).norm(), 2.0);
  EXPECT_FALSE(s->redo());
}

TEST(Studio, AddingAHandleOnAPartNamesItAfterThePartAndKeepsTheText) {
  auto s = open_cat(cat_folder("add"));
  ASSERT_TRUE(s);
  const std::string before = s->text();
  const Vec2 p(250, 185);
  const int part = s->part_at(p);
  ASSERT_GE(part, 0);
  const size_t n = s->puppet().rig.handles.size();
  ASSERT_EQ(s->add_handle(p), "");
  ASSERT_EQ(s->puppet().rig.handles.size(), n + 1);
  const RigHandle& h = s->puppet().rig.handles.back();
  EXPECT_LT((h.rest - p).norm(), 1e-6) << "at rest, the handle is where the click was";
  EXPECT_LT((s->handle_point(n) - p).norm(), 0.1);
  EXPECT_TRUE(lines_kept(before, s->text()));
  EXPECT_EQ(count_of(s->text(), "[[handle]]"), n + 1);
  EXPECT_TRUE(s->dirty());
  EXPECT_NE(s->add_handle(Vec2(-500, -500)), "") << "off the character there is nothing to hold";
  ASSERT_TRUE(s->undo());
  EXPECT_EQ(s->text(), before);
  EXPECT_EQ(s->puppet().rig.handles.size(), n);
  EXPECT_FALSE(s->dirty());
  // The cat's parts have its editor's ids (ellipse1042, circle877, rect1187): a new handle is
  // named after what the part is, its body, its head, a leg on its left.
  const auto added = [&](const Vec2& at) {
    EXPECT_EQ(s->add_handle(at), "");
    return s->puppet().rig.handles.back().name;
  };
  EXPECT_EQ(added(Vec2(200, 140)), "body-2");
  EXPECT_EQ(added(Vec2(322, 120)), "head-2");
  EXPECT_EQ(added(Vec2(123, 250)).rfind("limb-left", 0), 0u);
}

TEST(Studio, AddingAHandleOnAPosedCharacterHoldsThePartWhereItIs) {
  auto s = open_cat(cat_folder("add_posed"));
  ASSERT_TRUE(s);
  const int tail = handle_named(*s, "tail");
  s->set_target(size_t(tail), swing(*s, size_t(tail), 20));
  for (int f = 0; f < 40; ++f) s->step();
  s->commit_pose();
  const Vec2 held = s->handle_point(size_t(tail));
  const Vec2 body = s->handle_point(size_t(handle_named(*s, "body"))) + Vec2(40, 10);
  ASSERT_EQ(s->add_handle(body), "");
  EXPECT_LT((s->handle_point(s->puppet().rig.handles.size() - 1) - body).norm(), 1.0) << "the new handle is where it was clicked";
  EXPECT_LT((s->handle_point(size_t(tail)) - held).norm(), 1.0) << "the pose stays as it was";
}

TEST(Studio, RemovingAHandleTakesItsTableOnlyAndUndoBringsItBack) {
  auto s = open_cat(cat_folder("remove"));
  ASSERT_TRUE(s);
  const std::string before = s->text();
  const int ear = handle_named(*s, "ear-left");
  ASSERT_GE(ear, 0);
  ASSERT_EQ(s->remove_handle(size_t(ear)), "");
  EXPECT_LT(handle_named(*s, "ear-left"), 0);
  EXPECT_EQ(s->text().find("ear-left"), std::string::npos);
  EXPECT_TRUE(lines_kept(s->text(), before)) << "nothing else changed";
  EXPECT_EQ(count_of(s->text(), "[[handle]]"), count_of(before, "[[handle]]") - 1);
  ASSERT_TRUE(s->undo());
  EXPECT_EQ(s->text(), before);
}

TEST(Studio, AHandleInAKeyIsNotRemovedAndWhyIsSaid) {
  auto s = open_cat(cat_folder("remove_key"));
  ASSERT_TRUE(s);
  const int tail = handle_named(*s, "tail");
  s->set_target(size_t(tail), s->handle_point(size_t(tail)) + Vec2(10, 0));
  ASSERT_EQ(s->save_key("flick"), "");
  const std::string err = s->remove_handle(size_t(tail));
  EXPECT_NE(err.find("key 'flick'"), std::string::npos) << err;
  EXPECT_GE(handle_named(*s, "tail"), 0);
}

TEST(Studio, MovingADrawnHingeStatesItAndMovingAStatedOneEditsItInPlace) {
  auto s = open_cat(cat_folder("hinge"));
  ASSERT_TRUE(s);
  const std::string before = s->text();
  const std::vector<StudioHinge> hs = s->hinges();
  ASSERT_FALSE(hs.empty());
  EXPECT_EQ(count_of(before, "[[joint]]"), 0u) << "the plain rig states no joints: they come from the drawing";
  const size_t j = 0;
  const Vec2 to = hs[j].rest + Vec2(4, 3);
  ASSERT_EQ(s->move_hinge(j, to), "");
  EXPECT_EQ(count_of(s->text(), "[[joint]]"), 1u);
  EXPECT_TRUE(lines_kept(before, s->text()));
  auto moved = s->hinges();
  ASSERT_EQ(moved.size(), hs.size());
  bool found = false;
  for (const StudioHinge& h : moved)
    if (h.shape_a == hs[j].shape_a && h.shape_b == hs[j].shape_b) {
      EXPECT_LT((h.rest - to).norm(), 0.06) << "the hinge is where it was dropped";
      found = true;
    }
  EXPECT_TRUE(found);
  const std::string once = s->text();
  ASSERT_EQ(s->move_hinge(j, to + Vec2(2, 0)), "");
  EXPECT_EQ(count_of(s->text(), "[[joint]]"), 1u) << "the stated joint moves; no second one";
  EXPECT_NE(s->text(), once);
  ASSERT_TRUE(s->undo());
  EXPECT_EQ(s->text(), once);
  ASSERT_TRUE(s->undo());
  EXPECT_EQ(s->text(), before);
}

TEST(Studio, ScrollingOverAPartScalesItsStiffness) {
  auto s = open_cat(cat_folder("stiff"));
  ASSERT_TRUE(s);
  const int part = s->part_at(s->puppet().rig.handles[size_t(handle_named(*s, "tail"))].rest);
  ASSERT_GE(part, 0);
  const double k0 = s->stiffness(part);
  ASSERT_EQ(s->scale_stiffness(part, 1.25), "");
  EXPECT_NEAR(s->stiffness(part), k0 * 1.25, 1e-3);
  ASSERT_EQ(s->scale_stiffness(part, 1.25), "");
  EXPECT_NEAR(s->stiffness(part), k0 * 1.25 * 1.25, 2e-3);
  EXPECT_EQ(count_of(s->text(), "[[part]]"), 1u) << "one table, its value changed";
  auto r = parse_rig(s->text(), "cat.toml");
  ASSERT_TRUE(r.ok()) << r.error;
  ASSERT_EQ(r.value->parts.size(), 1u);
  EXPECT_EQ(r.value->parts[0].id, s->puppet().character.shapes[size_t(part)].id);
  EXPECT_NE(s->scale_stiffness(-1, 2), "") << "nothing under the pointer";
}

TEST(Studio, TheCurrentPoseSavesAsANamedKey) {
  auto s = open_cat(cat_folder("key"));
  ASSERT_TRUE(s);
  EXPECT_NE(s->save_key("wave"), "") << "nothing moved yet";
  const int tail = handle_named(*s, "tail");
  const Vec2 to = s->handle_point(size_t(tail)) + Vec2(-15, -25);
  s->set_target(size_t(tail), to);
  ASSERT_EQ(s->save_key("  wave "), "");
  auto r = parse_rig(s->text(), "cat.toml");
  ASSERT_TRUE(r.ok()) << r.error;
  ASSERT_EQ(r.value->keys.size(), 1u);
  EXPECT_EQ(r.value->keys[0].name, "wave");
  ASSERT_EQ(r.value->keys[0].targets.size(), 1u) << "only the moved handle";
  EXPECT_EQ(r.value->keys[0].targets[0].first, "tail");
  EXPECT_LT((r.value->keys[0].targets[0].second - to).norm(), 1e-3);
  EXPECT_NE(s->save_key("wave"), "") << "a second key of one name";
  EXPECT_NE(s->save_key("rest"), "");
  EXPECT_NE(s->save_key(""), "");
}

TEST(Studio, SaveIsAtomicAndKeepsWhatThePersonWrote) {
  const fs::path dir = cat_folder("save");
  const std::string original = read_all(dir / "rigs" / "cat.toml");
  auto s = open_cat(dir);
  ASSERT_TRUE(s);
  EXPECT_FALSE(s->dirty());
  ASSERT_EQ(s->add_handle(Vec2(250, 185)), "");
  ASSERT_EQ(s->scale_stiffness(s->part_at(Vec2(250, 185)), 0.8), "");
  ASSERT_EQ(s->move_hinge(0, s->hinges()[0].rest + Vec2(1, 1)), "");
  EXPECT_EQ(read_all(dir / "rigs" / "cat.toml"), original) << "nothing is written before S";
  ASSERT_EQ(s->save(), "");
  const std::string saved = read_all(dir / "rigs" / "cat.toml");
  EXPECT_EQ(saved, s->text());
  EXPECT_TRUE(lines_kept(original, saved)) << "every comment and line kept, in order";
  EXPECT_FALSE(fs::exists(dir / "rigs" / "cat.toml.tmp"));
  auto p = load_puppet("", (dir / "rigs" / "cat.toml").string());
  ASSERT_TRUE(p.ok()) << p.error;
  EXPECT_EQ((*p.value)->rig.handles.size(), s->puppet().rig.handles.size());
  // A file that cannot be replaced: the error names it, and the studio still holds the edits.
  const fs::path ro = dir / "locked";
  fs::create_directories(ro);
  auto locked = Studio::open((dir / "characters" / "cat.svg").string(), (ro / "cat.toml").string());
  ASSERT_TRUE(locked.ok()) << locked.error;
  fs::permissions(ro, fs::perms::owner_read | fs::perms::owner_exec);
  if (::geteuid() != 0) {  // root writes anywhere
    const std::string err = (*locked.value)->save();
    EXPECT_NE(err.find("cat.toml"), std::string::npos) << err;
    EXPECT_TRUE((*locked.value)->dirty());
  }
  fs::permissions(ro, fs::perms::owner_all);
}

TEST(Studio, ABrokenRigFileIsRefusedWithItsLine) {
  const fs::path dir = cat_folder("broken");
  std::ofstream(dir / "rigs" / "cat.toml", std::ios::app) << "\n[[handle]]\nname = \"x\"\nrest = [1.0]\n";
  auto s = Studio::open((dir / "characters" / "cat.svg").string(), (dir / "rigs" / "cat.toml").string());
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error.find("cat.toml:"), std::string::npos) << s.error;
}

// ---- the window, under Xvfb ----

// The window tests need a display: without one, each runs again in a process of its own under
// xvfb-run (this test's filter), and passes when that process does.
bool have_display_or_rerun() {
  const char* d = std::getenv("DISPLAY");
  if (d && *d) return true;
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  if (std::getenv("MARIONETTE_STUDIO_CHILD")) {
    ADD_FAILURE() << "xvfb-run gave no display";
    return false;
  }
  if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) {
    std::cout << "skipped: no display and xvfb-run is not installed" << std::endl;
    return false;
  }
  const std::string self = fs::read_symlink("/proc/self/exe").string();
  const std::string cmd = "MARIONETTE_STUDIO_CHILD=1 ASAN_OPTIONS=detect_leaks=0 " + test::xvfb_run() + " -s '-screen 0 1024x768x24' '" + self +
                          "' --gtest_filter=" + info->test_suite_name() + "." + info->name() + " 2>&1";
  FILE* p = ::popen(cmd.c_str(), "r");
  std::string out;
  char buf[4096];
  while (p && std::fgets(buf, sizeof buf, p)) out += buf;
  const int rc = p ? ::pclose(p) : -1;
  EXPECT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("[  PASSED  ] 1 test"), std::string::npos) << out;
  return false;
}

struct Win {
  std::unique_ptr<Studio> studio;
  std::unique_ptr<StudioWindow> window;
  explicit Win(const fs::path& dir, bool automatic = false) {
    studio = open_cat(dir, automatic);
    if (!studio) return;
    WindowOptions o;
    auto w = StudioWindow::open(*studio, o, 800, 600);
    EXPECT_TRUE(w.ok()) << w.error;
    if (w.ok()) window = std::move(*w.value);
    frames(2);
  }
  void frames(int n) {
    for (int i = 0; i < n; ++i) {
      window->frame();
      window->present();
    }
  }
  static void push(SDL_Event e) { ASSERT_EQ(SDL_PushEvent(&e), 1) << SDL_GetError(); }
  void button(Uint32 type, const Vec2& w) {
    SDL_Event e{};
    e.type = type;
    e.button.button = SDL_BUTTON_LEFT;
    e.button.state = type == SDL_MOUSEBUTTONDOWN ? SDL_PRESSED : SDL_RELEASED;
    e.button.x = int(std::lround(w.x()));
    e.button.y = int(std::lround(w.y()));
    push(e);
  }
  void move(const Vec2& w) {
    SDL_Event e{};
    e.type = SDL_MOUSEMOTION;
    e.motion.x = int(std::lround(w.x()));
    e.motion.y = int(std::lround(w.y()));
    push(e);
  }
  // A press, a move in steps (a frame each), a release.
  void drag(const Vec2& from, const Vec2& to) {
    move(from);
    button(SDL_MOUSEBUTTONDOWN, from);
    frames(1);
    for (int i = 1; i <= 8; ++i) {
      move(from + (to - from) * (i / 8.0));
      frames(1);
    }
    button(SDL_MOUSEBUTTONUP, to);
    frames(1);
  }
  void click(const Vec2& at) { drag(at, at); }
  void key(SDL_Keycode sym, Uint16 mod = 0) {
    SDL_Event e{};
    e.type = SDL_KEYDOWN;
    e.key.state = SDL_PRESSED;
    e.key.keysym.sym = sym;
    e.key.keysym.mod = mod;
    push(e);
    frames(1);
  }
  void type(const char* text) {
    SDL_Event e{};
    e.type = SDL_TEXTINPUT;
    std::snprintf(e.text.text, sizeof e.text.text, "%s", text);
    push(e);
    frames(1);
  }
  Vec2 at(const Vec2& character_point) const { return window->window_point(character_point); }
  // The window as a PNG in $MARIONETTE_STUDIO_SHOTS, when it is set (to look at).
  void shot(const std::string& name) {
    const char* dir = std::getenv("MARIONETTE_STUDIO_SHOTS");
    if (!dir || !*dir) return;
    Image img;
    img.width = window->canvas().window_width();
    img.height = window->canvas().window_height();
    img.rgba = window->canvas().read_window();
    EXPECT_EQ(write_png((fs::path(dir) / (name + ".png")).string(), img), "");
  }
  bool says(const std::string& what) const {
    for (const std::string& t : window->text())
      if (t.find(what) != std::string::npos) return true;
    return false;
  }
};

TEST(StudioWindow, DragAHandleWithTheMouseThenUndoAndRedo) {
  if (!have_display_or_rerun()) return;
  Win w(cat_folder("w_drag"));
  ASSERT_TRUE(w.window);
  Studio& s = *w.studio;
  const size_t tail = size_t(handle_named(s, "tail"));
  const Vec2 rest = s.handle_point(tail), from = w.at(rest), to = w.at(swing(s, tail, 25));
  w.drag(from, to);
  w.frames(30);
  const Vec2 want = w.window->character_point(to.x(), to.y());
  EXPECT_LT((s.handle_point(tail) - want).norm(), 2.0) << "the tail went where the mouse took it";
  EXPECT_TRUE(w.says("posed tail"));
  EXPECT_TRUE(w.says("tail")) << "the handle's label";
  w.key(SDLK_z, KMOD_LCTRL);
  EXPECT_LT((s.handle_point(tail) - rest).norm(), 0.5);
  EXPECT_TRUE(w.says("undone"));
  w.key(SDLK_y, KMOD_LCTRL);
  EXPECT_LT((s.handle_point(tail) - want).norm(), 2.0);
  w.key(SDLK_z, KMOD_LCTRL | KMOD_LSHIFT);  // Ctrl+Shift+Z redoes too: nothing left
  EXPECT_TRUE(w.says("nothing to redo"));
}

TEST(StudioWindow, APenOnATabletDragsAsTheMouseDoes) {
  if (!have_display_or_rerun()) return;
  Win w(cat_folder("w_pen"));
  ASSERT_TRUE(w.window);
  Studio& s = *w.studio;
  const size_t ear = size_t(handle_named(s, "ear-right"));
  const Vec2 from = w.at(s.handle_point(ear)), to = w.at(swing(s, ear, -20));
  int ww = 0, wh = 0;
  SDL_GetWindowSize(w.window->canvas().sdl_window(), &ww, &wh);
  auto finger = [&](Uint32 type, const Vec2& p) {
    SDL_Event e{};
    e.type = type;
    e.tfinger.touchId = 1;
    e.tfinger.fingerId = 0;
    e.tfinger.x = float(p.x() / ww);
    e.tfinger.y = float(p.y() / wh);
    e.tfinger.pressure = 0.6f;
    Win::push(e);
    w.frames(1);
  };
  finger(SDL_FINGERDOWN, from);
  for (int i = 1; i <= 6; ++i) finger(SDL_FINGERMOTION, from + (to - from) * (i / 6.0));
  finger(SDL_FINGERUP, to);
  w.frames(30);
  EXPECT_LT((s.handle_point(ear) - w.window->character_point(to.x(), to.y())).norm(), 2.0);
  EXPECT_TRUE(w.says("posed ear-right"));
}

TEST(StudioWindow, ClickAddsAHandleAndDeleteRemovesIt) {
  if (!have_display_or_rerun()) return;
  Win w(cat_folder("w_add"));
  ASSERT_TRUE(w.window);
  Studio& s = *w.studio;
  const std::string before = s.text();
  const size_t n = s.puppet().rig.handles.size();
  const Vec2 spot = w.at(Vec2(250, 185));
  w.click(spot);
  ASSERT_EQ(s.puppet().rig.handles.size(), n + 1) << w.window->status();
  const std::string name = s.puppet().rig.handles.back().name;
  EXPECT_TRUE(w.says("added the handle " + name));
  EXPECT_TRUE(w.says("(unsaved)"));
  w.move(spot);
  w.key(SDLK_DELETE);
  EXPECT_EQ(s.puppet().rig.handles.size(), n) << w.window->status();
  EXPECT_TRUE(w.says("removed the handle " + name));
  EXPECT_EQ(s.text(), before);
}

TEST(StudioWindow, DragAHingeToMoveIt) {
  if (!have_display_or_rerun()) return;
  Win w(cat_folder("w_hinge"));
  ASSERT_TRUE(w.window);
  Studio& s = *w.studio;
  const StudioHinge h = s.hinges()[0];
  const Vec2 from = w.at(h.at), to = from + Vec2(6, 4);
  w.drag(from, to);
  EXPECT_EQ(count_of(s.text(), "[[joint]]"), 1u) << w.window->status();
  bool moved = false;
  for (const StudioHinge& g : s.hinges())
    if (g.shape_a == h.shape_a && g.shape_b == h.shape_b) moved = (g.rest - w.window->character_point(to.x(), to.y())).norm() < 0.5;
  EXPECT_TRUE(moved);
  EXPECT_TRUE(w.says("moved the hinge"));
}

TEST(StudioWindow, ScrollOverAPartChangesItsStiffness) {
  if (!have_display_or_rerun()) return;
  Win w(cat_folder("w_scroll"));
  ASSERT_TRUE(w.window);
  Studio& s = *w.studio;
  const Vec2 p(250, 185);
  const int part = s.part_at(p);
  const double k0 = s.stiffness(part);
  w.move(w.at(p));
  w.frames(1);
  SDL_Event e{};
  e.type = SDL_MOUSEWHEEL;
  e.wheel.y = 2;
  e.wheel.direction = SDL_MOUSEWHEEL_NORMAL;
  Win::push(e);
  w.frames(1);
  EXPECT_NEAR(s.stiffness(part), k0 * 1.25 * 1.25, 2e-3) << w.window->status();
  EXPECT_TRUE(w.says("stiffness"));
  EXPECT_EQ(count_of(s.text(), "[[part]]"), 1u);
}

TEST(StudioWindow, KNamesAKeyFTogglesTheFrameAndSSaves) {
  if (!have_display_or_rerun()) return;
  const fs::path dir = cat_folder("w_key");
  const std::string original = read_all(dir / "rigs" / "cat.toml");
  Win w(dir);
  ASSERT_TRUE(w.window);
  Studio& s = *w.studio;
  const size_t tail = size_t(handle_named(s, "tail"));
  w.drag(w.at(s.handle_point(tail)), w.at(s.handle_point(tail)) + Vec2(20, -30));
  w.key(SDLK_k);
  w.type("wa");
  w.type("vex");
  w.key(SDLK_BACKSPACE);
  EXPECT_TRUE(w.says("key name: wave_"));
  w.key(SDLK_RETURN);
  EXPECT_TRUE(w.says("saved the key wave")) << w.window->status();
  EXPECT_NE(s.text().find("name = \"wave\""), std::string::npos) << s.text();
  // F: the frame overlay, drawn over the character.
  const std::vector<std::uint8_t> plain = w.window->canvas().read_window();
  w.key(SDLK_f);
  EXPECT_TRUE(w.window->overlay());
  const std::vector<std::uint8_t> framed = w.window->canvas().read_window();
  size_t differ = 0;
  for (size_t i = 0; i < plain.size() && i < framed.size(); ++i) differ += plain[i] != framed[i];
  EXPECT_GT(differ, 1000u) << "the frame's lines show";
  // Esc with unsaved changes asks first; S saves; then Esc quits.
  w.key(SDLK_ESCAPE);
  EXPECT_TRUE(w.says("unsaved changes"));
  w.key(SDLK_s);
  EXPECT_FALSE(s.dirty());
  const std::string saved = read_all(dir / "rigs" / "cat.toml");
  EXPECT_TRUE(lines_kept(original, saved));
  auto r = load_rig((dir / "rigs" / "cat.toml").string());
  ASSERT_TRUE(r.ok()) << r.error;
  ASSERT_EQ(r.value->keys.size(), 1u);
  EXPECT_EQ(r.value->keys[0].name, "wave");
  SDL_Event e{};
  e.type = SDL_KEYDOWN;
  e.key.keysym.sym = SDLK_ESCAPE;
  Win::push(e);
  EXPECT_FALSE(w.window->frame()) << "saved: Esc quits";
}

// B: the brush, dragged down over the belly with the mouse; K saves the sculpt as a key; C: the
// curve, drawn from the body out along the tail.
TEST(StudioWindow, BBrushesCDrawsACurveAndKSavesTheSculpt) {
  if (!have_display_or_rerun()) return;
  Win w(cat_folder("w_tools"));
  ASSERT_TRUE(w.window);
  Studio& s = *w.studio;
  w.key(SDLK_b);
  EXPECT_TRUE(w.says("[brush]"));
  const Puppet& p = s.puppet();
  int body = -1;
  for (size_t k = 0; k < p.character.shapes.size(); ++k) body = p.character.shapes[k].id == "ellipse1042" ? int(k) : body;
  ASSERT_GE(body, 0);
  Vec2 belly = p.shapes[size_t(body)][0];
  for (const Vec2& q : p.shapes[size_t(body)]) belly = q.y() > belly.y() ? q : belly;
  const std::vector<std::uint8_t> before = w.window->canvas().read_window();
  w.move(w.at(belly));
  w.button(SDL_MOUSEBUTTONDOWN, w.at(belly));
  w.frames(1);
  for (int i = 1; i <= 8; ++i) {
    w.move(w.at(belly) + Vec2(0, 25 * i / 8.0));
    w.frames(1);
  }
  w.shot("brushing");
  w.button(SDL_MOUSEBUTTONUP, w.at(belly) + Vec2(0, 25));
  w.frames(20);
  EXPECT_TRUE(w.says("brushed")) << w.window->status();
  EXPECT_TRUE(s.sculpted());
  const std::vector<std::uint8_t> after = w.window->canvas().read_window();
  size_t differ = 0;
  for (size_t i = 0; i < before.size() && i < after.size(); ++i) differ += before[i] != after[i];
  EXPECT_GT(differ, 500u) << "the belly's outline moved on screen";
  w.key(SDLK_k);
  w.type("belly");
  w.key(SDLK_RETURN);
  EXPECT_TRUE(w.says("saved the key belly")) << w.window->status();
  EXPECT_NE(s.text().find("shapes = \"cat.belly.key.json\""), std::string::npos);
  // The curve: from the body beside the tail's hinge, out along the tail and bending.
  w.key(SDLK_c);
  EXPECT_TRUE(w.says("[curve]"));
  EXPECT_FALSE(s.sculpted()) << "the curve's stroke lets the brush's sculpt go when it is drawn";
  int tail = -1;
  for (size_t k = 0; k < p.character.shapes.size(); ++k) tail = p.character.shapes[k].id == "path2291" ? int(k) : tail;
  Vec2 hinge(0, 0);
  for (const StudioHinge& j : s.hinges())
    if ((j.shape_a == tail && j.shape_b == body) || (j.shape_a == body && j.shape_b == tail)) hinge = j.at;
  Vec2 tip = hinge;
  for (const Vec2& q : p.shapes[size_t(tail)]) tip = (q - hinge).norm() > (tip - hinge).norm() ? q : tip;
  const Bounds bb = p.character.shapes[size_t(body)].bounds();
  const Vec2 start = hinge + 0.15 * (0.5 * (bb.lo + bb.hi) - hinge), axis = tip - hinge, normal(-axis.y(), axis.x());
  w.move(w.at(start));
  w.button(SDL_MOUSEBUTTONDOWN, w.at(start));
  w.frames(1);
  for (int i = 1; i <= 16; ++i) {
    const double t = i / 16.0;
    w.move(w.at(hinge + t * axis + 0.25 * std::sin(M_PI * t) * normal));
    w.frames(1);
  }
  w.shot("drawing");
  w.button(SDL_MOUSEBUTTONUP, w.at(hinge + axis));
  w.frames(20);
  EXPECT_TRUE(w.says("the curve took")) << w.window->status();
  w.shot("drawn");
  EXPECT_TRUE(s.sculpted());
  w.key(SDLK_c);
  EXPECT_TRUE(w.says("posing handles"));
  EXPECT_TRUE(s.sculpted()) << "back to the handles, the curve's shape held";
}

// The real program under Xvfb, driven by real X input (xdotool's XTEST events, as a mouse and
// a keyboard give them): a click adds a handle, a drag swings the tail, K names the pose, S
// saves, Esc quits; the file on disk has it all and every line the person wrote.
TEST(StudioCli, RealInputEditsAndSavesTheRig) {
  if (std::system("command -v xvfb-run >/dev/null 2>&1 && command -v xdotool >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "xvfb-run and xdotool (Debian packages xvfb, xdotool) drive the real window";
  const fs::path dir = cat_folder("cli");
  const fs::path rig = dir / "rigs" / "cat.toml";
  const std::string original = read_all(rig);
  auto model = open_cat(dir);
  ASSERT_TRUE(model);
  const size_t tail = size_t(handle_named(*model, "tail"));
  const Vec2 to = swing(*model, tail, 20);
  // The window is the canvas (960 x 720, no letterbox): a point shows where the view puts it.
  const Character& ch = model->puppet().character;
  const Affine2 view = StudioWindow::character_view(ch, 960, 720);
  auto px = [&](const Vec2& p) {
    const Vec2 w = view.apply(p);
    return std::to_string(std::lround(w.x())) + " " + std::to_string(std::lround(w.y()));
  };
  const Vec2 body_spot(250, 185);
  const std::string script = "set -e\n'" + std::string(MARIONETTE_BINARY) + "' rig '" + (dir / "characters" / "cat.svg").string() +
                             "' --rig '" + rig.string() + "' > '" + (dir / "out.txt").string() + "' 2>&1 &\npid=$!\n" +
                             "wid=$(timeout 60 xdotool search --sync --onlyvisible --name 'marionette rig studio')\n" +
                             "timeout 60 sh -c \"until grep -q 'S saves' '" + (dir / "out.txt").string() + "'; do sleep 0.1; done\"\n" +
                             "xdotool mousemove --window $wid " + px(body_spot) + " click 1\n" +
                             "xdotool mousemove --window $wid " + px(model->handle_point(tail)) + " mousedown 1 mousemove --window $wid " +
                             px((model->handle_point(tail) + to) / 2) + " mousemove --window $wid " + px(to) + " mouseup 1\n" +
                             "xdotool key k\nxdotool type wave\nxdotool key Return s Escape\n" + "timeout 60 tail --pid=$pid -f /dev/null\nwait $pid\n";
  const std::string sh = test::write_temp("studio_cli.sh", script);
  const std::string cmd = "ASAN_OPTIONS=detect_leaks=0 timeout 120 " + test::xvfb_run() + " -s '-screen 0 1280x800x24' bash '" + sh + "' 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << read_all(dir / "out.txt");
  const std::string saved = read_all(rig);
  EXPECT_TRUE(lines_kept(original, saved)) << saved;
  SCOPED_TRACE("the program said: " + read_all(dir / "out.txt"));
  auto r = load_rig(rig.string());
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_EQ(r.value->handles.size(), model->puppet().rig.handles.size() + 1) << "the click added a handle";
  ASSERT_EQ(r.value->keys.size(), 1u) << saved;
  EXPECT_EQ(r.value->keys[0].name, "wave");
  ASSERT_EQ(r.value->keys[0].targets.size(), 1u);
  EXPECT_EQ(r.value->keys[0].targets[0].first, "tail");
  EXPECT_LT((r.value->keys[0].targets[0].second - to).norm(), 1.0) << "where the drag ended, to a pixel";
}

}  // namespace
}  // namespace mar
