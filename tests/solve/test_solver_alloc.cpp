// (f) The steady-state solve (local + global steps, shape reconstruction) allocates nothing.
#include "character/load.h"
#include "solve/arap.h"
#include "solve/feature_frame.h"
#include "solve/feature_frame_method.h"
#include "solve/rigid_grid.h"
#include "alloc_counter.h"
#include "test_util.h"

#include <gtest/gtest.h>

namespace mar {
namespace {

TEST(FeatureFrameSolver, SteadyStateSolveAllocatesNothing) {
  auto ch = load_character((test::characters_dir() / "figure.svg").string());
  ASSERT_TRUE(ch.ok());
  const FeatureFrame f = build_feature_frame(*ch.value, default_frame_options());
  const std::vector<Vec2> rest{{150, 60}, {110, 395}, {190, 395}, {50, 250}};
  std::vector<ShapeParam> handles;
  for (const Vec2& p : rest) handles.push_back(bind_point(f, *ch.value, p));
  FeatureFrameSolver s;
  ASSERT_TRUE(s.prepare(f, handles, SolverWeights{}));
  std::vector<Points> shapes;
  for (const SubShape& sh : ch.value->shapes) shapes.push_back(sh.points);
  std::vector<Vec2> targets = rest;
  std::vector<double> energies(13);
  auto frame = [&](int k) {
    targets[3] = rest[3] + Vec2(std::sin(k * 0.1) * 40, std::cos(k * 0.13) * 40);
    s.solve(targets, 12, energies);
    reconstruct_shapes(f, s.vertices(), shapes);
  };
  for (int k = 0; k < 10; ++k) frame(k);
  const long before = test::allocation_count();
  for (int k = 10; k < 210; ++k) frame(k);
  EXPECT_EQ(test::allocation_count() - before, 0);
}

// Frames of a mesh solver behind the seam: one handle moving, a pen grab taken and released
// every 50 frames, 8 iterations and the shapes rebuilt each frame. Allocations over 200
// frames after 10 of warm-up.
long seam_frame_allocations(Solver& s, const Character& c, const std::vector<Vec2>& rest, const Vec2& grab_at) {
  std::vector<Points> shapes;
  for (const SubShape& sh : c.shapes) shapes.push_back(sh.points);
  std::vector<Vec2> targets = rest;
  targets.push_back(grab_at);
  auto frame = [&](int k) {
    targets[3] = rest[3] + Vec2(std::sin(k * 0.1) * 40, std::cos(k * 0.13) * 40);
    if (k % 50 == 0) s.grab(grab_at);
    if (k % 50 == 25) s.release();
    s.solve(std::span<const Vec2>(targets.data(), s.grabbing() ? targets.size() : rest.size()), 8);
    s.shape_points(shapes);
  };
  for (int k = 1; k < 10; ++k) frame(k);
  const long before = test::allocation_count();
  for (int k = 10; k < 210; ++k) frame(k);
  return test::allocation_count() - before;
}

// The feature frame carrying a detail whole ([[rider]]): no allocation, a pen on the body or
// on the arm under the sleeve.
TEST(FeatureFrameMethod, RidersAllocateNothing) {
  auto ch = load_character((test::characters_dir() / "figure.svg").string());
  ASSERT_TRUE(ch.ok());
  Character c = *ch.value;
  const std::vector<Vec2> rest{{150, 60}, {110, 395}, {190, 395}, {55, 250}};
  Rig r = default_rig();
  RigRider sleeve;
  sleeve.part = "sleeve-left", sleeve.on = "arm-left", sleeve.at = Vec2(105, 165);
  r.riders = {sleeve};
  FeatureFrameMethod s;
  std::string err;
  ASSERT_TRUE(s.prepare(c, r, rest, SolverWeights{}, &err)) << err;
  EXPECT_EQ(seam_frame_allocations(s, c, rest, Vec2(150, 200)), 0) << "a pen on the body";
  EXPECT_EQ(seam_frame_allocations(s, c, rest, Vec2(100, 170)), 0) << "a pen on the sleeve";
}

TEST(OutlineArap, SteadyStateSolveAndGrabAllocateNothing) {
  auto ch = load_character((test::characters_dir() / "figure.svg").string());
  ASSERT_TRUE(ch.ok());
  Character c = *ch.value;
  const std::vector<Vec2> rest{{150, 60}, {110, 395}, {190, 395}, {50, 250}};
  OutlineArap s;
  std::string err;
  ASSERT_TRUE(s.prepare(c, default_rig(), rest, SolverWeights{}, &err)) << err;
  EXPECT_EQ(seam_frame_allocations(s, c, rest, Vec2(150, 200)), 0);
}

TEST(RigidGrid, SteadyStateSolveAndGrabAllocateNothing) {
  for (const bool fast : {true, false}) {
    auto ch = load_character((test::characters_dir() / "boy.png").string());
    ASSERT_TRUE(ch.ok());
    Character c = *ch.value;
    const std::vector<Vec2> rest{{150, 60}, {110, 410}, {190, 410}, {214, 248}};
    RigidGrid s;
    std::string err;
    ASSERT_TRUE(s.prepare(c, default_rig(), rest, SolverWeights{}, &err)) << err;
    s.set_fast_summation(fast);
    EXPECT_EQ(seam_frame_allocations(s, c, rest, Vec2(150, 200)), 0) << (fast ? "fast summation" : "plain sums");
  }
}

// With riders: the left arm rides on the grid and its hand's handle turns it; a pen on the arm
// (a rider) and on the body (the grid).
TEST(RigidGrid, RidersAllocateNothing) {
  auto ch = load_character((test::characters_dir() / "figure.svg").string());
  ASSERT_TRUE(ch.ok());
  Character c = *ch.value;
  const std::vector<Vec2> rest{{150, 60}, {110, 395}, {190, 395}, {55, 250}};
  Rig r = default_rig();
  r.solver = "rigid_grid";
  r.handles = {{"head", rest[0]}, {"left-foot", rest[1]}, {"right-foot", rest[2]}, {"left-hand", rest[3]}};
  RigRider arm;
  arm.part = "arm-left", arm.on = "torso", arm.at = Vec2(105, 150), arm.handle = "left-hand", arm.with = {"sleeve-left"};
  r.riders = {arm};
  RigidGrid s;
  std::string err;
  ASSERT_TRUE(s.prepare(c, r, rest, SolverWeights{}, &err)) << err;
  ASSERT_EQ(s.riders(), 1u);
  EXPECT_EQ(seam_frame_allocations(s, c, rest, Vec2(60, 240)), 0) << "a pen on the arm";
  EXPECT_EQ(seam_frame_allocations(s, c, rest, Vec2(150, 200)), 0) << "a pen on the body";
}

// A limb inside one shape turning whole ([[bone]]): no allocation either, a pen on it or on the body.
TEST(RigidGrid, BonesAllocateNothing) {
  Character c;
  SubShape sh;
  sh.id = "figure";
  const Points corners{{0, 0}, {100, 0}, {100, 20}, {220, 20}, {220, 40}, {100, 40}, {100, 200}, {0, 200}};
  for (size_t k = 0; k < corners.size(); ++k)
    for (int i = 0; i < 10; ++i) sh.points.push_back(corners[k] + (i / 10.0) * (corners[(k + 1) % corners.size()] - corners[k]));
  sh.contours.push_back({0, int(sh.points.size()), true});
  sh.fill.enabled = true;
  c.shapes = {sh};
  c.width = 220;
  c.height = 200;
  const std::vector<Vec2> rest{{50, 100}, {210, 30}};
  Rig r = default_rig();
  r.solver = "rigid_grid";
  r.grid_cell = 10;
  r.handles = {{"body", rest[0]}, {"hand", rest[1]}};
  RigBone b;
  b.handle = "hand", b.at = Vec2(100, 30), b.axis = {{215, 30}, {100, 30}}, b.radius = {10, 10};
  r.bones = {b};
  RigidGrid s;
  std::string err;
  ASSERT_TRUE(s.prepare(c, r, rest, SolverWeights{}, &err)) << err;
  ASSERT_EQ(s.riders(), 1u);
  EXPECT_EQ(seam_frame_allocations(s, c, rest, Vec2(180, 30)), 0) << "a pen on the arm";
  EXPECT_EQ(seam_frame_allocations(s, c, rest, Vec2(50, 150)), 0) << "a pen on the body";
}

}  // namespace
}  // namespace mar
