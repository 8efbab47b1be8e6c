// A show with a cast ([[character]] tables): each character's names start with its name, each
// actor moves only by its own bindings, the canvas is drawn in z order, a cast of one computes
// what the single-rig show computes, and a cast's frame allocates nothing.
#include "alloc_counter.h"
#include "app/alloc_count.h"
#include "app/live.h"
#include "render/image.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace mar {
namespace {

std::string rig_path(const std::string& name) { return (test::source_dir() / "config/rigs" / (name + ".toml")).string(); }

std::string character(const std::string& name, const std::string& rig, const std::string& more = "") {
  return "[[character]]\nname = \"" + name + "\"\nrig = \"" + rig_path(rig) + "\"\n" + more + "\n";
}

std::string cast_show(const std::string& file, const std::string& body) {
  return test::write_temp(file, "[show]\nrate = 60\niterations = 12\nmin_iterations = 12\n[display]\nwidth = 320\nheight = 200\n" + body);
}

std::unique_ptr<LiveShow> load(const std::string& path, RunOptions o = {}) {
  o.headless = true;
  o.quiet = true;
  auto s = LiveShow::load(path, o);
  EXPECT_TRUE(s.ok()) << s.error;
  return s.ok() ? std::move(*s.value) : nullptr;
}

double moved(const Puppet& p) {
  double d = 0;
  for (size_t k = 0; k < p.shapes.size(); ++k)
    for (size_t i = 0; i < p.shapes[k].size(); ++i) d = std::max(d, (p.shapes[k][i] - p.character.shapes[k].points[i]).norm());
  return d;
}

std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void replace_all(std::string& s, const std::string& a, const std::string& b) {
  for (size_t at = s.find(a); at != std::string::npos; at = s.find(a, at + b.size())) s.replace(at, a.size(), b);
}

const char* kKnob = R"(
[[device]]
name = "knobs"
sim = "knob_box"
script = """
0.1 turn 1 -15 over 1.0
"""
)";

// Two figures side by side; a knob moves the second's right hand only.
TEST(Cast, EachCharacterMovesByItsOwnBindingsOnly) {
  const std::string path = cast_show("cast_own.toml", character("left", "figure") + character("right", "figure") + kKnob + R"(
[[binding]]
device = "knobs"
control = "encoder 1"
target = "right.handle.right-hand.y"
mode = "delta"
step = 6.0
)");
  auto s = load(path);
  ASSERT_TRUE(s);
  ASSERT_EQ(s->actors().size(), 2u);
  EXPECT_EQ(s->actors()[0]->name(), "left");
  EXPECT_EQ(s->actors()[1]->name(), "right");
  for (int f = 0; f < 90; ++f) s->frame(int64_t(f * 1e9 / 60));
  EXPECT_LT(moved(s->actors()[0]->puppet()), 1e-6) << "the left figure has no binding: it stays at rest";
  EXPECT_GT(moved(s->actors()[1]->puppet()), 20.0) << "the knob raised the right figure's hand";
  // The mapping holds both characters' handles, each named after its character.
  const auto& names = s->mapping().handle_names();
  EXPECT_NE(std::find(names.begin(), names.end(), "left.right-hand"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "right.right-hand"), names.end());
}

// A cast's names start with a character; the error names the file, the line and the cast.
TEST(Cast, ATargetWithoutItsCharacterIsRefusedWithTheCast) {
  auto check = [](const std::string& body, const std::string& want) {
    const std::string path = cast_show("cast_bad.toml", body);
    const std::string err = LiveShow::validate(path);
    EXPECT_NE(err.find(want), std::string::npos) << err;
    EXPECT_NE(err.find("cast_bad.toml:"), std::string::npos) << err;
  };
  const std::string two = character("robot", "robot") + character("cat", "cat") + kKnob;
  check(two + "[[binding]]\ndevice = \"knobs\"\ncontrol = \"encoder 1\"\ntarget = \"handle.head.y\"\n", "robot, cat");
  check(two + "[[binding]]\ndevice = \"knobs\"\ncontrol = \"encoder 1\"\ntarget = \"dog.handle.head.y\"\n", "starts with its character's name");
  check(two + "[[binding]]\ndevice = \"knobs\"\ncontrol = \"encoder 1\"\ntarget = \"cat.handle.antenna.y\"\n", "cat: the rig has no handle 'antenna'");
  check(two + "[[binding]]\ndevice = \"knobs\"\ncontrol = \"encoder 1\"\ntarget = \"robot.solver.iterations\"\n", "is the show's");
  check(character("robot", "robot") + character("robot", "cat"), "a second character named 'robot'");
  check(character("pose", "robot"), "word of the target grammar");
  check(character("a.b", "robot"), "no dots");
  check("[[character]]\nname = \"x\"\n", "needs a name and a rig");
  check(two + "[[group]]\nname = \"g\"\nhandles = [\"robot.head\", \"cat.head\"]\npivot = [0, 0]\n", "one character's handles");
  const std::string both = test::write_temp("cast_both.toml", "[show]\nrig = \"" + rig_path("figure") + "\"\n" + character("robot", "robot"));
  EXPECT_NE(LiveShow::validate(both).find("not both"), std::string::npos) << LiveShow::validate(both);
}

// The demo show as a cast of one: the same bindings, groups and poses, each name with its
// character in front, compute exactly the demo's frames (the same run_hash).
TEST(Cast, ACastOfOneComputesWhatTheSingleRigShowComputes) {
  const std::filesystem::path demo = test::source_dir() / "config/shows/demo.toml";
  std::string text = read_text(demo);
  replace_all(text, "rig = \"../rigs/figure.toml\"", "");
  replace_all(text, "target = \"handle.", "target = \"figure.handle.");
  replace_all(text, "target = \"grab\"", "target = \"figure.grab\"");
  replace_all(text, "handles = [\"head\"]", "handles = [\"figure.head\"]");
  replace_all(text, "handles = { ", "handles = { figure = { ");
  replace_all(text, "] }\n", "] } }\n");
  text += "\n" + character("figure", "figure");
  const std::string cast = test::write_temp("cast_demo.toml", text);
  RunOptions o;
  o.frames = 300;  // (5 s: mid-performance)
  auto a = load(demo.string(), o);
  auto b = load(cast, o);
  ASSERT_TRUE(a && b);
  EXPECT_EQ(a->run(), 0);
  EXPECT_EQ(b->run(), 0);
  EXPECT_EQ(a->frames(), 300);
  EXPECT_EQ(a->run_hash(), b->run_hash());
  EXPECT_GT(moved(b->puppet()), 1.0);  // (it moved: the hash compares a performance, not a rest pose)
}

// The duet's actors solve on a pool of threads: the same frames as on the frame's thread alone,
// and no frame allocates.
TEST(Cast, TheRunHashIsTheSameOnOneThreadOrMany) {
  set_allocation_counter(&heap_allocation_count);
  std::string text = read_text(test::source_dir() / "config/shows/duet.toml");
  replace_all(text, "../", (test::source_dir() / "config").string() + "/");
  auto hash = [&](int threads) {
    std::string t = text;
    replace_all(t, "[show]\n", "[show]\nthreads = " + std::to_string(threads) + "\n");
    RunOptions o;
    o.frames = 420;
    auto s = load(test::write_temp("cast_threads.toml", t), o);
    EXPECT_TRUE(s);
    if (!s) return uint64_t(0);
    EXPECT_EQ(s->solve_threads(), threads);
    EXPECT_EQ(s->run(), 0);
    EXPECT_EQ(s->allocations_after_warmup(), 0u) << threads << " threads";
    return s->run_hash();
  };
  const uint64_t one = hash(1);
  EXPECT_EQ(hash(3), one);
  EXPECT_EQ(hash(2), one);
}

// Two characters at one place: the higher z is drawn over the other; swapping z swaps them.
TEST(Cast, TheCanvasIsDrawnInZOrder) {
  auto centre = [](int z_robot) {
    const std::string path =
        cast_show("cast_z.toml", character("robot", "robot", "position = [160, 100]\nz = " + std::to_string(z_robot)) +
                                     character("figure", "figure", "position = [160, 100]\nz = 0"));
    const std::string dir = (std::filesystem::temp_directory_path() / "marionette_cast_z").string();
    std::filesystem::remove_all(dir);
    RunOptions o;
    o.frames = 1;
    o.dump_dir = dir;
    auto s = load(path, o);
    EXPECT_TRUE(s);
    if (!s) return std::array<int, 3>{};
    EXPECT_EQ(s->run(), 0);
    auto img = read_png_image(dir + "/frame_000000.png");
    EXPECT_TRUE(img.ok()) << img.error;
    if (!img.ok()) return std::array<int, 3>{};
    // Where the robot's chest and the figure's shirt overlap (the centre of both boxes' centres).
    const Image& im = *img.value;
    const size_t at = (size_t(im.height / 2) * size_t(im.width) + size_t(im.width / 2)) * 4;
    return std::array<int, 3>{im.rgba[at], im.rgba[at + 1], im.rgba[at + 2]};
  };
  const auto over = centre(1), under = centre(-1);
  // The robot is grey (r = g = b), the figure's shirt red.
  EXPECT_LT(std::abs(over[0] - over[2]), 40) << over[0] << "," << over[1] << "," << over[2];
  EXPECT_GT(under[0] - under[2], 80) << under[0] << "," << under[1] << "," << under[2];
}

// The duet: a recall goes to its character; the pen drags only the character it names; the
// cast's frames allocate nothing after warm-up.
TEST(Cast, TheDuetsRecallAndPenGoToTheirCharactersAndAllocateNothing) {
  set_allocation_counter(&heap_allocation_count);
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  o.warmup = 30;
  auto s = load((test::source_dir() / "config/shows/duet.toml").string(), o);
  ASSERT_TRUE(s);
  ASSERT_EQ(s->actors().size(), 3u);
  for (int f = 0; f < 30; ++f) s->frame(int64_t(f * 1e9 / 60));
  const long before = test::allocation_count();
  double cat_moved = 0, wave = 0;
  for (int f = 30; f < 600; ++f) {
    s->frame(int64_t(f * 1e9 / 60));
    if (f == 170) cat_moved = moved(s->actors()[2]->puppet());  // 2.8 s: the pen holds the cat's tail
    if (f == 420) wave = s->actors()[0]->key_weights()[0];     // 7 s: the figure recalled its wave at 5.5 s
  }
  EXPECT_EQ(test::allocation_count() - before, 0);
  EXPECT_EQ(s->allocations_after_warmup(), 0u);
  EXPECT_GT(cat_moved, 10.0);
  const auto j = nlohmann::json::parse(s->stats_json());
  EXPECT_EQ(j["grabs"]["count"].get<int>(), 2);  // down and up, on the cat
  EXPECT_EQ(j["cast"], nlohmann::json::array({"figure", "robot", "cat"}));
  EXPECT_GT(wave, 0.9);
  EXPECT_FALSE(s->actors()[1]->has_keys());  // (the robot's rig has none: its recall would be refused)
}

// In a cast a pen (or the mouse over the window) covers the canvas: where it touches, it takes
// the point of the character drawn under it — a character placed, scaled and turned included.
TEST(Cast, APenTakesThePointOfTheCharacterDrawnUnderIt) {
  const std::string place = "position = [210, 110]\nscale = 0.6\nrotation = 30\n";
  auto pen = [&](const std::string& script) {
    return cast_show("cast_pen.toml", character("figure", "figure") + character("robot", "robot", place) +
                                          "[[device]]\nname = \"pen\"\nsim = \"pen_tablet\"\nscript = \"\"\"\n" + script +
                                          "\"\"\"\n[[binding]]\ndevice = \"pen\"\ncontrol = \"pointer\"\ntarget = \"robot.grab\"\n");
  };
  auto probe = load(pen("0.1 leave\n"));
  ASSERT_TRUE(probe);
  const Actor& robot = *probe->actors()[1];
  const Vec2 chest(150, 206);  // the robot's chest, in its own units
  const Vec2 at = robot.view.apply(chest);
  ASSERT_GT(at.x(), 0);
  ASSERT_LT(at.x(), 320);
  char xy[64];
  std::snprintf(xy, sizeof xy, "%.5f,%.5f", at.x() / 320, at.y() / 200);
  auto s = load(pen(std::string("0.1 hover ") + xy + "\n0.2 stroke " + xy + " " + xy + " over 0.3 pressure 0.7\n"));
  ASSERT_TRUE(s);
  bool held = false;
  for (int f = 0; f < 24 && !held; ++f) {
    s->frame(int64_t(f * 1e9 / 60));
    held = s->mapping().grab_active();
  }
  ASSERT_TRUE(held) << "the pen's tip went down";
  const double diag = (robot.rest_bounds.hi - robot.rest_bounds.lo).norm();
  EXPECT_LT((s->mapping().grab_point() - chest).norm(), 0.01 * diag)
      << "took " << s->mapping().grab_point().transpose() << ", under the pen: " << chest.transpose();
}

// A character off stage enters when its NAME.on-stage trigger comes on: a fade over its
// entrance's seconds (drawn as one layer: its parts do not show through each other), or a
// slide from beyond the canvas's edge; entering after warm-up allocates nothing.
TEST(Cast, ACharacterEntersAndLeavesByItsOnStageTrigger) {
  set_allocation_counter(&heap_allocation_count);
  const std::string path = cast_show("cast_enter.toml",
                                     character("a", "figure", "entrance = \"slide-left\"\nentrance_seconds = 0.5") +
                                         character("b", "figure", "shown = false\nentrance_seconds = 0.5") + R"(
[[device]]
name = "knobs"
sim = "knob_box"
script = """
1.0 press 1 for 0.2
3.0 press 1 for 0.2
3.0 press 2 for 0.2
"""

[[binding]]
device = "knobs"
control = "button 1"
target = "b.on-stage"
button = "toggle"

[[binding]]
device = "knobs"
control = "button 2"
target = "a.on-stage"
button = "toggle"
)");
  RunOptions o;
  o.warmup = 30;
  auto s = load(path, o);
  ASSERT_TRUE(s);
  const Actor& a = *s->actors()[0];
  const Actor& b = *s->actors()[1];
  std::vector<double> pb, oa;
  std::vector<float> fade;
  pb.reserve(300);
  oa.reserve(300);
  fade.reserve(300);
  for (int f = 0; f < 30; ++f) s->frame(int64_t(f * 1e9 / 60));
  const long before = test::allocation_count();
  for (int f = 30; f < 300; ++f) {
    s->frame(int64_t(f * 1e9 / 60));
    pb.push_back(b.presence());
    fade.push_back(b.opacity());
    oa.push_back((a.drawn_view().apply(Vec2(0, 0)) - a.view.apply(Vec2(0, 0))).norm());
  }
  EXPECT_EQ(test::allocation_count() - before, 0) << "a fade's layer and a slide allocate nothing";
  auto at = [](double t) { return size_t(t * 60) - 30; };
  EXPECT_EQ(pb[at(0.9)], 0.0) << "b starts off stage";
  EXPECT_GT(fade[at(1.3)], 0.1f);
  EXPECT_LT(fade[at(1.3)], 0.9f) << "half way in, b is half faded in";
  EXPECT_EQ(pb[at(1.8)], 1.0);
  EXPECT_EQ(fade[at(1.8)], 1.0f);
  EXPECT_EQ(oa[at(2.9)], 0.0) << "a stands where it stands";
  EXPECT_GT(oa[at(3.3)], 20.0) << "a slides away to the left";
  EXPECT_EQ(pb[at(3.8)], 0.0) << "b has left";
  EXPECT_EQ(a.presence(), 0.0);
  EXPECT_LT(a.drawn_view().apply(a.rest_bounds.hi).x(), 0.0) << "a ends beyond the canvas's left edge";
}

// A cast's pose dump: every character's shapes each frame, each id with its character's name.
TEST(Cast, ThePoseDumpListsEveryCharactersShapes) {
  const std::string out = (std::filesystem::temp_directory_path() / "marionette_cast_poses.jsonl").string();
  RunOptions o;
  o.frames = 120;
  o.dump_poses = out;
  auto s = load((test::source_dir() / "config/shows/duet.toml").string(), o);
  ASSERT_TRUE(s);
  ASSERT_EQ(s->run(), 0);
  std::ifstream in(out);
  std::string line, last;
  int lines = 0;
  while (std::getline(in, line)) {
    last = line;
    ++lines;
  }
  EXPECT_EQ(lines, 120);
  const auto j = nlohmann::json::parse(last);
  size_t total = 0;
  for (const auto& a : s->actors()) total += a->puppet().shapes.size();
  ASSERT_EQ(j["subshapes"].size(), total);
  // The robot's first shape, as the last frame left it.
  const Puppet& robot = s->actors()[1]->puppet();
  const size_t at = s->actors()[0]->puppet().shapes.size();
  const auto& sub = j["subshapes"][at];
  EXPECT_EQ(sub["id"].get<std::string>(), "robot." + robot.character.shapes[0].id);
  ASSERT_EQ(sub["points"].size(), robot.shapes[0].size());
  for (size_t i = 0; i < robot.shapes[0].size(); ++i) {
    EXPECT_NEAR(sub["points"][i][0].get<double>(), robot.shapes[0][i].x(), 1e-3);
    EXPECT_NEAR(sub["points"][i][1].get<double>(), robot.shapes[0][i].y(), 1e-3);
  }
}

// The family kiosk: a visitor calls the cat; left alone, the family plays by itself (the
// attract loop drives the cast's targets through the one mapping: the figure's hand, the
// robot's arm, the cat's entrance).
TEST(Cast, TheFamilyKioskPlaysByItselfWhenLeftAlone) {
  auto s = load((test::source_dir() / "config/shows/family.toml").string());
  ASSERT_TRUE(s);
  ASSERT_EQ(s->actors().size(), 3u);
  const Actor& cat = *s->actors()[2];
  double cat_in = 0, figure_moved_by_attract = 0;
  bool attract = false;
  for (int f = 0; f < 900; ++f) {
    s->frame(int64_t(f * 1e9 / 60));
    if (f == 360) cat_in = cat.presence();  // 6 s: the visitor called it at 4 s (a 1.2 s entrance)
    if (s->attract() && s->attract()->shown()) {
      attract = true;
      figure_moved_by_attract = std::max(figure_moved_by_attract, moved(s->actors()[1]->puppet()));
    }
  }
  EXPECT_EQ(cat_in, 1.0);
  EXPECT_TRUE(attract) << "6 s after the visitor's last touch the attract loop plays";
  EXPECT_GT(figure_moved_by_attract, 20.0) << "the attract raised the figure's hand";
}

}  // namespace
}  // namespace mar
