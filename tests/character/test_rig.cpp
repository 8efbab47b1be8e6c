#include "character/rig.h"
#include "base/config_toml.h"
#include "test_util.h"

#include <gtest/gtest.h>

namespace mar {
namespace {

constexpr const char* kRig = R"toml(character = "../characters/butterfly.svg"
iterations = 20

[weights]
rigidity = 2.0
coupling = 0.5
position = 50.0

[sampling]
mode = "uniform"
interval = 15.5

[[handle]]
name = "head"
rest = [200.0, 135.5]

[[handle]]
name = "tail"
rest = [200, 308]

[[sewing]]
action = "add"
from = [165.0, 75.0]
to = [189.0, 170.0]

[[sewing]]
action = "move"
from = [1.0, 2.0]
to = [3.0, 4.0]
new_from = [5.0, 6.0]
new_to = [7.0, 8.0]

[[sewing]]
action = "delete"
from = [9.0, 10.0]
to = [11.0, 12.0]
)toml";

TEST(parse_rig, ReadsEveryField) {
  auto r = parse_rig(kRig, "/rigs/b.toml");
  ASSERT_TRUE(r.ok()) << r.error;
  const Rig& g = *r.value;
  EXPECT_EQ(g.character_path(), "/characters/butterfly.svg");
  EXPECT_EQ(g.iterations, 20);
  EXPECT_EQ(g.w_rigidity, 2.0);
  EXPECT_EQ(g.w_coupling, 0.5);
  EXPECT_EQ(g.w_position, 50.0);
  EXPECT_TRUE(g.uniform_sampling);
  EXPECT_EQ(g.interval, 15.5);
  ASSERT_EQ(g.handles.size(), 2u);
  EXPECT_EQ(g.handles[0].rest, Vec2(200, 135.5));
  EXPECT_EQ(g.handles[1].rest, Vec2(200, 308));  // integers accepted
  ASSERT_EQ(g.sewing.size(), 3u);
  EXPECT_EQ(g.sewing[1].action, RigSewing::Move);
  EXPECT_EQ(g.sewing[1].new_to, Vec2(7, 8));
  EXPECT_EQ(g.sewing[2].action, RigSewing::Delete);
  EXPECT_EQ(g.sewing[0].line, 21);  // the [[sewing]] header line
  EXPECT_EQ(g.find_handle("tail"), 1);
  EXPECT_EQ(g.find_handle("nope"), -1);
}

// (g) A rig file round-trips.
TEST(write_rig, RoundTrips) {
  auto r = parse_rig(kRig, "b.toml");
  ASSERT_TRUE(r.ok());
  const std::string text = write_rig(*r.value);
  auto back = parse_rig(text, "b.toml");
  ASSERT_TRUE(back.ok()) << back.error << "\n" << text;
  const Rig &a = *r.value, &b = *back.value;
  EXPECT_EQ(a.character, b.character);
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(a.w_rigidity, b.w_rigidity);
  EXPECT_EQ(a.w_coupling, b.w_coupling);
  EXPECT_EQ(a.w_position, b.w_position);
  EXPECT_EQ(a.uniform_sampling, b.uniform_sampling);
  EXPECT_EQ(a.interval, b.interval);
  ASSERT_EQ(a.handles.size(), b.handles.size());
  for (size_t i = 0; i < a.handles.size(); ++i) {
    EXPECT_EQ(a.handles[i].name, b.handles[i].name);
    EXPECT_EQ(a.handles[i].rest, b.handles[i].rest);
  }
  ASSERT_EQ(a.sewing.size(), b.sewing.size());
  for (size_t i = 0; i < a.sewing.size(); ++i) {
    EXPECT_EQ(a.sewing[i].action, b.sewing[i].action);
    EXPECT_EQ(a.sewing[i].from, b.sewing[i].from);
    EXPECT_EQ(a.sewing[i].to, b.sewing[i].to);
    EXPECT_EQ(a.sewing[i].new_from, b.sewing[i].new_from);
    EXPECT_EQ(a.sewing[i].new_to, b.sewing[i].new_to);
  }
  EXPECT_EQ(write_rig(b), text);  // and the text is stable
}

TEST(parse_rig, ErrorsNameFileAndLine) {
  struct Case {
    const char* text;
    const char* expect;
  };
  const Case cases[] = {
      {"character = \"a.svg\"\niterations = 0\n", "r.toml:2: iterations"},
      {"character = \"a.svg\"\n[[handle]]\nname = \"h\"\nrest = [1]\n", "r.toml:4: rest must be [x, y]"},
      {"character = \"a.svg\"\n[[handle]]\nname = \"h\"\nrest = [1, 2]\n[[handle]]\nname = \"h\"\nrest = [3, 4]\n",
       "r.toml:6: handle 'h' defined twice"},
      {"character = \"a.svg\"\n[sampling]\nmode = \"random\"\n", "r.toml:3: sampling mode"},
      {"character = \"a.svg\"\n\n[[sewing]]\naction = \"stitch\"\nfrom = [0, 0]\nto = [1, 1]\n", "r.toml:3: sewing action"},
      {"character = \"a.svg\"\nspeed = 3\n", "r.toml:2: unknown key 'speed'"},
      {"character = \"a.svg\"\n[weights]\ncoupling = -1\n", "r.toml:3: coupling must not be negative"},
      {"iterations = 3\n", "'character'"},
      {"character = \"a.svg\"\nthis is not toml\n", "r.toml:2:"},
      {"character = \"a.svg\"\n[feature_frame]\nanderson = 40\n", "r.toml:3: anderson must be"},
      {"character = \"a.svg\"\n[feature_frame]\njoints = \"some\"\n", "r.toml:3: joints must be"},
      {"character = \"a.svg\"\nsolver = 3\n", "r.toml:2: solver must be a method name"},
      {"character = \"a.svg\"\n\n[[joint]]\nstiffness = 1.0\n", "r.toml:3: a joint needs at = [x, y] or parts"},
      {"character = \"a.svg\"\n[[joint]]\nat = [1, 2]\nkind = \"weld\"\n", "r.toml:2: a weld needs parts"},
      {"character = \"a.svg\"\n[[joint]]\nparts = [\"a\"]\n", "r.toml:3: parts must be two"},
      {"character = \"a.svg\"\n[[joint]]\nat = [1, 2]\nkind = \"ball\"\n", "r.toml:4: kind must be"},
      {"character = \"a.svg\"\n[[part]]\nid = \"torso\"\nstiffness = 0\n", "r.toml:4: stiffness must be positive"},
      {"character = \"a.svg\"\n[[part]]\nstiffness = 2\n", "r.toml:2: a part needs id"},
  };
  for (const Case& c : cases) {
    auto r = parse_rig(c.text, "r.toml");
    ASSERT_FALSE(r.ok()) << c.text;
    EXPECT_NE(r.error.find(c.expect), std::string::npos) << "got: " << r.error;
  }
  EXPECT_FALSE(load_rig("/nonexistent/rig.toml").ok());
}

TEST(parse_rig, JointsPartsAndSolverRoundTrip) {
  const char* text = R"toml(character = "c.svg"
solver = "feature_frame"
[feature_frame]
anderson = 3
joints = "none"
stiffness = "auto"

[[joint]]
at = [176.0, 160.0]
parts = ["arm-right", "shirt"]
stiffness = 0.5

[[joint]]
parts = ["hair", "head"]
kind = "weld"

[[part]]
id = "shirt"
stiffness = 3.5
)toml";
  auto r = parse_rig(text, "j.toml");
  ASSERT_TRUE(r.ok()) << r.error;
  const Rig& a = *r.value;
  EXPECT_EQ(a.anderson, 3);
  EXPECT_FALSE(a.auto_joints);
  EXPECT_TRUE(a.auto_stiffness);
  ASSERT_EQ(a.joints.size(), 2u);
  EXPECT_TRUE(a.joints[0].has_at);
  EXPECT_EQ(a.joints[0].at, Vec2(176, 160));
  EXPECT_EQ(a.joints[0].part_a, "arm-right");
  EXPECT_EQ(a.joints[0].part_b, "shirt");
  EXPECT_DOUBLE_EQ(a.joints[0].stiffness, 0.5);
  EXPECT_EQ(a.joints[0].line, 8);
  EXPECT_EQ(a.solver, "feature_frame");
  EXPECT_EQ(a.solver_line, 2);
  EXPECT_FALSE(a.joints[1].has_at);
  EXPECT_TRUE(a.joints[1].weld);
  ASSERT_EQ(a.parts.size(), 1u);
  EXPECT_EQ(a.parts[0].id, "shirt");
  EXPECT_DOUBLE_EQ(a.parts[0].stiffness, 3.5);
  auto back = parse_rig(write_rig(a), "j.toml");
  ASSERT_TRUE(back.ok()) << back.error;
  EXPECT_EQ(back.value->anderson, 3);
  EXPECT_FALSE(back.value->auto_joints);
  ASSERT_EQ(back.value->joints.size(), 2u);
  EXPECT_EQ(back.value->joints[0].at, a.joints[0].at);
  EXPECT_EQ(back.value->joints[1].weld, true);
  EXPECT_EQ(back.value->joints[1].part_a, "hair");
  ASSERT_EQ(back.value->parts.size(), 1u);
  EXPECT_EQ(write_rig(*back.value), write_rig(a));
}

TEST(parse_rig, GridAndStiffnessRoundTrip) {
  const char* text = R"toml(character = "c.png"
mask = "c-mask.png"
solver = "rigid_grid"
[grid]
cell = 8.5
half_width = 4
stride = 1
junction = "mvc"
weights = { rigidity = 5.0, junction = 2.0 }

[[stiffness]]
name = "arm"
center = [10, 20]
radius = 15
weight = 3.0

[[stiffness]]
center = [1, 2]
radius = 4
weight = 0.5
)toml";
  auto a = parse_rig(text, "g.toml");
  ASSERT_TRUE(a.ok()) << a.error;
  const Rig& r = *a.value;
  EXPECT_EQ(r.mask, "c-mask.png");
  EXPECT_EQ(r.mask_path(), "c-mask.png");  // beside the rig (here: no folder)
  EXPECT_EQ(r.grid_cell, 8.5);
  EXPECT_EQ(r.grid_half_width, 4);
  EXPECT_EQ(r.grid_stride, 1);
  EXPECT_EQ(r.grid_junction_term, "mvc");
  EXPECT_EQ(r.grid_rigidity, 5.0);
  EXPECT_EQ(r.grid_junction, 2.0);
  ASSERT_EQ(r.stiffness.size(), 2u);
  EXPECT_EQ(r.stiffness[0].name, "arm");
  EXPECT_EQ(r.stiffness[0].center, Vec2(10, 20));
  EXPECT_EQ(r.stiffness[1].weight, 0.5);
  auto back = parse_rig(write_rig(r), "g.toml");
  ASSERT_TRUE(back.ok()) << back.error << "\n" << write_rig(r);
  EXPECT_EQ(write_rig(*back.value), write_rig(r));
  EXPECT_EQ(back.value->stiffness.size(), 2u);
  EXPECT_EQ(back.value->mask, "c-mask.png");
  struct Case {
    const char* text;
    const char* expect;
  };
  const Case cases[] = {
      {"character = \"a.png\"\n[grid]\nhalf_width = 0\n", "r.toml:3: half_width must be a whole number"},
      {"character = \"a.png\"\nmask = 3\n", "r.toml:2: mask must be the path of a PNG"},
      {"character = \"a.png\"\n[grid]\ncell = -2\n", "r.toml:3: cell must be positive"},
      {"character = \"a.png\"\n[grid]\nstride = -1\n", "r.toml:3: stride must be a whole number 0..32"},
      {"character = \"a.png\"\n[grid]\njunction = \"glue\"\n", "r.toml:3: junction must be"},
      {"character = \"a.png\"\n[grid]\nsize = 3\n", "r.toml:3: unknown key 'size'"},
      {"character = \"a.png\"\n[[stiffness]]\ncenter = [1, 2]\nradius = 3\n", "r.toml:2: a stiffness region needs"},
      {"character = \"a.png\"\n[[stiffness]]\nname = \"a\"\ncenter = [1, 2]\nradius = 3\nweight = 1\n[[stiffness]]\nname = \"a\"\ncenter = [1, 2]\nradius = 3\nweight = 1\n",
       "r.toml:7: stiffness region 'a' defined twice"},
  };
  for (const Case& c : cases) {
    auto e = parse_rig(c.text, "r.toml");
    ASSERT_FALSE(e.ok()) << c.text;
    EXPECT_NE(e.error.find(c.expect), std::string::npos) << e.error;
  }
}

// The rig written and read back writes the same text.
void round_trips(const Rig& r) {
  auto back = parse_rig(write_rig(r), "d.toml");
  ASSERT_TRUE(back.ok()) << back.error << "\n" << write_rig(r);
  EXPECT_EQ(write_rig(*back.value), write_rig(r));
}

// Each text is refused with a message holding its expected words (file and line first).
void refused(std::initializer_list<std::pair<std::string, std::string>> cases) {
  for (const auto& [text, expect] : cases) {
    auto e = parse_rig(text, "r.toml");
    ASSERT_FALSE(e.ok()) << text;
    EXPECT_NE(e.error.find(expect), std::string::npos) << e.error;
  }
}

TEST(parse_rig, RidersRoundTripAndErrorsNameTheLine) {
  const char* text = R"toml(character = "c.svg"
solver = "rigid_grid"
[[handle]]
name = "hand"
rest = [40, 5]

[[rider]]
part = "upper"
on = "body"
at = [10, 5]
handle = "hand"
with = ["sleeve", "cuff"]

[[rider]]
part = "lower"
on = "upper"
at = [30, 5]

[[rider]]
part = "backdrop"
still = true
)toml";
  auto a = parse_rig(text, "d.toml");
  ASSERT_TRUE(a.ok()) << a.error;
  const Rig& r = *a.value;
  ASSERT_EQ(r.riders.size(), 3u);
  EXPECT_EQ(r.riders[0].part, "upper");
  EXPECT_EQ(r.riders[0].on, "body");
  EXPECT_EQ(r.riders[0].at, Vec2(10, 5));
  EXPECT_EQ(r.riders[0].handle, "hand");
  EXPECT_EQ(r.riders[0].with, (std::vector<std::string>{"sleeve", "cuff"}));
  EXPECT_EQ(r.riders[1].line, 14);
  EXPECT_TRUE(r.riders[1].handle.empty());
  EXPECT_TRUE(r.riders[2].still);
  EXPECT_FALSE(r.riders[0].still);
  round_trips(r);
  refused({
      {"character = \"a.svg\"\n[[rider]]\npart = \"arm\"\nat = [1, 2]\n", "r.toml:2: on the feature frame a [[rider]] rides whole on the part it is on"},
      {"character = \"a.svg\"\n[[handle]]\nname = \"hand\"\nrest = [0, 0]\n[[rider]]\npart = \"arm\"\non = \"body\"\nat = [1, 2]\nhandle = \"hand\"\n",
       "r.toml:5: on the feature frame a [[rider]] rides whole on the part it is on: it needs on = \"sub-shape id\" and no handle"},
      {"character = \"a.svg\"\nsolver = \"arap\"\n[[rider]]\npart = \"arm\"\non = \"body\"\nat = [1, 2]\n", "r.toml:3: a [[rider]] rides on the rigid grid or the feature frame"},
      {"character = \"a.svg\"\nsolver = \"rigid_grid\"\n[[rider]]\npart = \"arm\"\n", "r.toml:3: a rider needs part"},
      {"character = \"a.svg\"\nsolver = \"rigid_grid\"\n[[rider]]\npart = \"arm\"\nat = [1, 2]\nhandle = \"hand\"\n",
       "r.toml:3: rider 'arm' names handle 'hand'"},
      {"character = \"a.svg\"\nsolver = \"rigid_grid\"\n[[rider]]\npart = \"arm\"\nat = [1, 2]\n[[rider]]\npart = \"arm\"\nat = [3, 4]\n",
       "r.toml:6: part 'arm' rides twice"},
      {"character = \"a.svg\"\nsolver = \"rigid_grid\"\n[[rider]]\npart = \"arm\"\nat = [1, 2]\nwith = \"cuff\"\n", "r.toml:6: with must be a list"},
      {"character = \"a.svg\"\nsolver = \"rigid_grid\"\n[[rider]]\npart = \"arm\"\nat = [1, 2]\nspin = 1\n", "r.toml:6: unknown key 'spin'"},
      {"character = \"a.svg\"\nsolver = \"rigid_grid\"\n[[rider]]\npart = \"sun\"\nstill = true\nat = [1, 2]\n",
       "r.toml:3: a still rider stays where it is drawn: it takes no on, at or handle"},
      {"character = \"a.svg\"\nsolver = \"rigid_grid\"\n[[rider]]\npart = \"sun\"\nstill = 1\n", "r.toml:5: still must be true or false"},
      {"character = \"a.svg\"\n[[rider]]\npart = \"sun\"\nstill = true\n", "r.toml:2: a still [[rider]] is left out of the rigid grid's mesh"},
  });
  // (a chain of riders costs the square of its length a frame: at most 256)
  std::string many = "character = \"a.svg\"\nsolver = \"rigid_grid\"\n";
  for (int k = 0; k < 257; ++k) many += "[[rider]]\npart = \"p" + std::to_string(k) + "\"\nat = [0, 0]\n";
  auto e = parse_rig(many, "r.toml");
  ASSERT_FALSE(e.ok());
  EXPECT_NE(e.error.find("at most 256 riders"), std::string::npos) << e.error;
  // (on the feature frame a rider costs only its own points and 64 of its part's: up to 4096)
  std::string details = "character = \"a.svg\"\n";
  for (int k = 0; k < 300; ++k) details += "[[rider]]\npart = \"p" + std::to_string(k) + "\"\non = \"body\"\nat = [0, 0]\n";
  EXPECT_TRUE(parse_rig(details, "r.toml").ok());
  for (int k = 300; k < 4097; ++k) details += "[[rider]]\npart = \"p" + std::to_string(k) + "\"\non = \"body\"\nat = [0, 0]\n";
  auto f = parse_rig(details, "r.toml");
  ASSERT_FALSE(f.ok());
  EXPECT_NE(f.error.find("at most 4096 riders"), std::string::npos) << f.error;
}

TEST(parse_rig, BonesRoundTripAndErrorsNameTheLine) {
  const char* text = R"toml(character = "c.svg"
solver = "rigid_grid"
[[handle]]
name = "foot"
rest = [40, 95]

[[bone]]
handle = "foot"
at = [40, 50]
axis = [[40, 95, 6], [40.25, 70, 7.5], [40, 50, 9]]
band = 4.5

[[bone]]
at = [10, 50]
axis = [[0, 50, 3], [10, 50, 3]]
)toml";
  auto a = parse_rig(text, "d.toml");
  ASSERT_TRUE(a.ok()) << a.error;
  const Rig& r = *a.value;
  ASSERT_EQ(r.bones.size(), 2u);
  EXPECT_EQ(r.bones[0].handle, "foot");
  EXPECT_EQ(r.bones[0].at, Vec2(40, 50));
  EXPECT_EQ(r.bones[0].axis, (std::vector<Vec2>{{40, 95}, {40.25, 70}, {40, 50}}));
  EXPECT_EQ(r.bones[0].radius, (std::vector<double>{6, 7.5, 9}));
  EXPECT_EQ(r.bones[0].band, 4.5);
  EXPECT_EQ(r.bones[1].line, 13);
  EXPECT_TRUE(r.bones[1].handle.empty());
  EXPECT_EQ(r.bones[1].band, 0);
  round_trips(r);
  EXPECT_EQ(parse_rig(write_rig(r), "d.toml").value->bones[0].axis, r.bones[0].axis);
  const std::string grid = "character = \"a.svg\"\nsolver = \"rigid_grid\"\n";
  refused({
      {"character = \"a.svg\"\n[[bone]]\nat = [1, 2]\naxis = [[0, 0, 1], [1, 2, 1]]\n", "r.toml:2: a [[bone]] turns on the rigid grid"},
      {grid + "[[bone]]\nat = [1, 2]\n", "r.toml:3: a bone needs at = [x, y] (its joint) and axis"},
      {grid + "[[bone]]\nat = [1, 2]\naxis = [[0, 0, 1]]\n", "r.toml:5: axis must be 2 to 1024 points"},
      {grid + "[[bone]]\nat = [1, 2]\naxis = [[0, 0, 1], [1, 2]]\n", "r.toml:5: an axis point must be [x, y, half-width]"},
      {grid + "[[bone]]\nat = [1, 2]\naxis = [[0, 0, 1], [1, 2, 0]]\n", "r.toml:5: an axis point's half-width must be above 0"},
      {grid + "[[bone]]\nat = [1, 2]\naxis = [[0, 0, 1], [1, 2, nan]]\n", "r.toml:5: a half-width must be a finite number"},
      {grid + "[[bone]]\nat = [1, 2]\naxis = [[0, 0, 1], [1, 2, 1]]\nband = -1\n", "r.toml:6: band must be 0"},
      {grid + "[[bone]]\nhandle = \"foot\"\nat = [1, 2]\naxis = [[0, 0, 1], [1, 2, 1]]\n", "r.toml:3: the bone names handle 'foot'"},
      {grid + "[[bone]]\nat = [1, 2]\naxis = [[0, 0, 1], [1, 2, 1]]\nspin = 1\n", "r.toml:6: unknown key 'spin'"},
  });
  // (each bone weighs every point of the drawing when the rig is prepared: at most 64)
  std::string many = grid;
  for (int k = 0; k < 65; ++k) many += "[[bone]]\nat = [0, 0]\naxis = [[0, 0, 1], [1, 0, 1]]\n";
  auto e = parse_rig(many, "r.toml");
  ASSERT_FALSE(e.ok());
  EXPECT_NE(e.error.find("at most 64 bones"), std::string::npos) << e.error;
  std::string long_axis = grid + "[[bone]]\nat = [0, 0]\naxis = [";
  for (int k = 0; k < 1025; ++k) long_axis += std::string(k ? ", " : "") + "[" + std::to_string(k) + ", 0, 1]";
  e = parse_rig(long_axis + "]\n", "r.toml");
  ASSERT_FALSE(e.ok());
  EXPECT_NE(e.error.find("axis must be 2 to 1024 points"), std::string::npos) << e.error;
  std::string axes = grid;  // five bones of 1,000 points: more than 4,096 in all
  for (int b = 0; b < 5; ++b) {
    axes += "[[bone]]\nat = [0, 0]\naxis = [";
    for (int k = 0; k < 1000; ++k) axes += std::string(k ? ", " : "") + "[" + std::to_string(k) + ", 0, 1]";
    axes += "]\n";
  }
  e = parse_rig(axes, "r.toml");
  ASSERT_FALSE(e.ok());
  EXPECT_NE(e.error.find("at most 4,096 axis points in all the bones"), std::string::npos) << e.error;
}

TEST(parse_rig, KeyPosesRoundTripAndErrorsNameTheLine) {
  const char* text = R"toml(character = "c.svg"
[[handle]]
name = "hand"
rest = [1, 2]
[[handle]]
name = "foot"
rest = [3, 4]

[[key]]
name = "wave"
targets = { hand = [10, 20], foot = [30, 40] }

[[key]]
name = "saved"
frame = "saved.json"
)toml";
  auto a = parse_rig(text, "k.toml");
  ASSERT_TRUE(a.ok()) << a.error;
  ASSERT_EQ(a.value->keys.size(), 2u);
  EXPECT_EQ(a.value->keys[0].name, "wave");
  ASSERT_EQ(a.value->keys[0].targets.size(), 2u);
  EXPECT_EQ(a.value->keys[0].targets[0].first, "foot");  // TOML tables are ordered by key
  EXPECT_EQ(a.value->keys[0].targets[1].second, Vec2(10, 20));
  EXPECT_EQ(a.value->keys[0].line, 9);
  EXPECT_EQ(a.value->keys[1].frame, "saved.json");
  auto back = parse_rig(write_rig(*a.value), "k.toml");
  ASSERT_TRUE(back.ok()) << back.error << "\n" << write_rig(*a.value);
  EXPECT_EQ(write_rig(*back.value), write_rig(*a.value));
  EXPECT_EQ(a.value->max_spacing, 0.0);
  // A sculpted key (the studio's): its file, and the finer frame it asks for.
  auto sculpted = parse_rig(std::string(text) + "\n[[key]]\nname = \"sneer\"\nshapes = \"k.sneer.key.json\"\n", "k.toml");
  ASSERT_TRUE(sculpted.ok()) << sculpted.error;
  ASSERT_EQ(sculpted.value->keys.size(), 3u);
  EXPECT_EQ(sculpted.value->keys[2].shapes, "k.sneer.key.json");
  EXPECT_EQ(sculpted.value->max_spacing, kSculptSpacing);
  EXPECT_EQ(sculpt_spacing(*sculpted.value), kSculptSpacing);
  auto again = parse_rig(write_rig(*sculpted.value), "k.toml");
  ASSERT_TRUE(again.ok()) << again.error;
  EXPECT_EQ(again.value->keys[2].shapes, "k.sneer.key.json");
  const char* head = "character = \"c.svg\"\n[[handle]]\nname = \"hand\"\nrest = [1, 2]\n";
  struct Case {
    std::string text;
    const char* expect;
  };
  const Case cases[] = {
      {std::string(head) + "[[key]]\nname = \"k\"\ntargets = { elbow = [1, 2] }\n", "k.toml:7: key 'k' names no handle 'elbow'"},
      {std::string(head) + "[[key]]\nname = \"k\"\n", "k.toml:5: key 'k' needs one of targets"},
      {std::string(head) + "[[key]]\nname = \"k\"\nframe = \"f.json\"\nshapes = \"s.json\"\n", "k.toml:5: key 'k' needs one of targets"},
      {std::string(head) + "[[key]]\nname = \"rest\"\nframe = \"f.json\"\n", "k.toml:6: 'rest' is the rest pose"},
      {std::string(head) + "[[key]]\nname = \"k\"\nframe = \"f.json\"\n[[key]]\nname = \"k\"\nframe = \"g.json\"\n",
       "k.toml:8: key 'k' defined twice"},
  };
  for (const Case& c : cases) {
    auto e = parse_rig(c.text, "k.toml");
    ASSERT_FALSE(e.ok()) << c.text;
    EXPECT_NE(e.error.find(c.expect), std::string::npos) << e.error;
  }
}

TEST(load_rig, ExampleRigsLoad) {
  for (const char* name : {"butterfly", "figure", "koi", "boy", "candle"}) {
    auto r = load_rig((test::source_dir() / "config" / "rigs" / (std::string(name) + ".toml")).string());
    ASSERT_TRUE(r.ok()) << r.error;
    EXPECT_GE(r.value->handles.size(), 5u);
    EXPECT_TRUE(std::filesystem::exists(r.value->character_path())) << r.value->character_path();
  }
}

}  // namespace
}  // namespace mar

namespace mar {
namespace {

TEST(parse_rig, SwapSetsAndTriggersRoundTripAndErrorsNameTheLine) {
  const char* text = R"toml(character = "c.svg"
[[swap]]
name = "mouth"
members = ["m-a", "m-o", "m-e"]
default = "m-o"

[[trigger]]
name = "blink"
shapes = ["lids"]
)toml";
  auto a = parse_rig(text, "s.toml");
  ASSERT_TRUE(a.ok()) << a.error;
  const Rig& r = *a.value;
  ASSERT_EQ(r.swaps.size(), 1u);
  EXPECT_EQ(r.swaps[0].members, (std::vector<std::string>{"m-a", "m-o", "m-e"}));
  EXPECT_EQ(r.swaps[0].default_member, 1);
  EXPECT_EQ(r.swaps[0].line, 2);
  ASSERT_EQ(r.triggers.size(), 1u);
  EXPECT_EQ(r.triggers[0].shapes, std::vector<std::string>{"lids"});
  auto back = parse_rig(write_rig(r), "s.toml");
  ASSERT_TRUE(back.ok()) << back.error << "\n" << write_rig(r);
  EXPECT_EQ(write_rig(*back.value), write_rig(r));
  EXPECT_EQ(back.value->swaps[0].default_member, 1);
  struct Case {
    const char* text;
    const char* expect;
  };
  const Case cases[] = {
      {"character = \"a.svg\"\n[[swap]]\nname = \"m\"\nmembers = [\"a\"]\ndefault = \"b\"\n", "r.toml:5: default 'b' is not one of the members"},
      {"character = \"a.svg\"\n[[swap]]\nname = \"m\"\n", "r.toml:2: swap set 'm' needs members"},
      {"character = \"a.svg\"\n[[swap]]\nname = \"m\"\nmembers = []\n", "r.toml:4: members must be a list of sub-shape ids"},
      {"character = \"a.svg\"\n[[trigger]]\nshapes = [\"a\"]\n", "r.toml:2: a trigger needs a name"},
      {"character = \"a.svg\"\n[[swap]]\nname = \"x\"\nmembers = [\"a\"]\n[[trigger]]\nname = \"x\"\nshapes = [\"a\"]\n",
       "r.toml:5: 'x' is already a swap set"},
      {"character = \"a.svg\"\n[[trigger]]\nname = \"x\"\nshapes = [\"a\"]\nmode = 1\n", "r.toml:5: unknown key 'mode'"},
  };
  for (const Case& c : cases) {
    auto e = parse_rig(c.text, "r.toml");
    ASSERT_FALSE(e.ok()) << c.text;
    EXPECT_NE(e.error.find(c.expect), std::string::npos) << e.error;
  }
}

}  // namespace
}  // namespace mar
