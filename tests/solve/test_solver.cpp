// The solver seam (solve/solver.h): the factory and the feature frame behind it.
#include "character/load.h"
#include "geom/polygon.h"
#include "solve/make_solver.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace mar {
namespace {

TEST(make_solver, KnowsTheFeatureFrameTheRigidGridAndTheOutlineArapBaseline) {
  EXPECT_TRUE(solver_known("feature_frame"));
  EXPECT_TRUE(solver_known("arap"));
  EXPECT_EQ(make_solver("arap")->name(), "arap");
  EXPECT_TRUE(solver_known("rigid_grid"));
  EXPECT_EQ(make_solver("rigid_grid")->name(), "rigid_grid");
  EXPECT_FALSE(solver_known("rigid-grid"));
  auto s = make_solver("feature_frame");
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(s->name(), "feature_frame");
  EXPECT_EQ(make_solver("bogus"), nullptr);
}

// Through the seam only: prepare, solve, handle points, shape points, grab and release.
TEST(Solver, FeatureFrameBehindTheSeamPosesAndGrabs) {
  auto ch = load_character((test::characters_dir() / "figure.svg").string());
  ASSERT_TRUE(ch.ok());
  Character c = *ch.value;
  Rig rig = default_rig();
  const std::vector<Vec2> rest{{150, 190}, {150, 280}, {245, 250}};
  std::unique_ptr<Solver> s = make_solver("feature_frame");
  std::string err;
  ASSERT_TRUE(s->prepare(c, rig, rest, SolverWeights{}, &err)) << err;
  ASSERT_EQ(s->handle_count(), 3u);
  for (size_t h = 0; h < 3; ++h) EXPECT_LT((s->handle_point(h) - rest[h]).norm(), 1e-9);
  std::vector<Vec2> targets = rest;
  targets[2] = Vec2(265.8, 232.3);  // the arm turned 15 degrees about its shoulder joint (188.1, 162.0)
  for (int f = 0; f < 20; ++f) s->solve(targets, 8);
  EXPECT_LT((s->handle_point(2) - targets[2]).norm(), 2.0);
  std::vector<Points> shapes;
  for (const SubShape& sh : c.shapes) shapes.push_back(sh.points);
  s->shape_points(shapes);
  bool moved = false;
  for (size_t k = 0; k < shapes.size(); ++k)
    for (size_t i = 0; i < shapes[k].size(); ++i) moved = moved || (shapes[k][i] - c.shapes[k].points[i]).norm() > 1;
  EXPECT_TRUE(moved);
  // A grab: the point under the pen follows the last target.
  s->grab(Vec2(150, 230));
  EXPECT_TRUE(s->grabbing());
  targets.push_back(Vec2(165, 230));
  for (int f = 0; f < 20; ++f) s->solve(targets, 8);
  s->release();
  EXPECT_FALSE(s->grabbing());
  s->reset_to_rest();
  for (size_t h = 0; h < 3; ++h) EXPECT_LT((s->handle_point(h) - rest[h]).norm(), 1e-9);
}

// A [[rider]] of the feature frame: the left sleeve, a detail drawn over the arm, rides on it
// whole. Out of the frame, it takes the arm's best rigid motion about where it is on it: the
// arm turned 60 degrees up about its shoulder carries it exactly rigid and in its place on the
// arm, and back at rest it is as drawn. A rider on a shape the drawing lacks, or riding on
// itself through another, is refused by name.
TEST(Solver, FeatureFrameCarriesARiderWholeOnItsPart) {
  auto ch = load_character((test::characters_dir() / "figure.svg").string());
  ASSERT_TRUE(ch.ok());
  Character c = *ch.value;
  Rig rig = default_rig();
  RigRider sleeve;
  sleeve.part = "sleeve-left", sleeve.on = "arm-left", sleeve.at = Vec2(105, 165);
  rig.riders = {sleeve};
  const std::vector<Vec2> rest{{150, 190}, {150, 280}, {55, 250}};
  std::unique_ptr<Solver> s = make_solver("feature_frame");
  std::string err;
  ASSERT_TRUE(s->prepare(c, rig, rest, SolverWeights{}, &err)) << err;
  auto shape_of = [&](const std::string& id) {
    for (size_t k = 0; k < c.shapes.size(); ++k)
      if (c.shapes[k].id == id) return k;
    return c.shapes.size();
  };
  const size_t sl = shape_of("sleeve-left"), arm = shape_of("arm-left");
  ASSERT_LT(sl, c.shapes.size());
  ASSERT_LT(arm, c.shapes.size());
  const Points sleeve_rest = c.shapes[sl].points, arm_rest = c.shapes[arm].points;
  ASSERT_FALSE(sleeve_rest.empty());
  // (each sleeve point's distance to the arm's outline, at rest and posed)
  auto gaps = [&](const Points& sv, const Points& am) {
    std::vector<double> g;
    for (const Vec2& q : sv) {
      double d = INFINITY;
      for (const Vec2& a : am) d = std::min(d, (a - q).norm());
      g.push_back(d);
    }
    return g;
  };
  const std::vector<double> gap0 = gaps(sleeve_rest, arm_rest);
  const Vec2 shoulder(112, 150);
  const double a = -60 * M_PI / 180;
  const Vec2 d = rest[2] - shoulder;
  std::vector<Vec2> targets = rest;
  targets[2] = shoulder + Vec2(std::cos(a) * d.x() - std::sin(a) * d.y(), std::sin(a) * d.x() + std::cos(a) * d.y());
  for (int f = 0; f < 30; ++f) s->solve(targets, 8);
  std::vector<Points> shapes;
  for (const SubShape& sh : c.shapes) shapes.push_back(sh.points);
  s->shape_points(shapes);
  EXPECT_LT(rigid_fit_rms(sleeve_rest, shapes[sl]), 1e-9) << "the sleeve is carried whole";
  Vec2 moved = Vec2::Zero();
  for (size_t k = 0; k < sleeve_rest.size(); ++k) moved += (shapes[sl][k] - sleeve_rest[k]) / double(sleeve_rest.size());
  EXPECT_GT(moved.norm(), 5.0) << "it moved with the arm";
  const std::vector<double> gap1 = gaps(shapes[sl], shapes[arm]);
  double worst = 0;
  for (size_t k = 0; k < gap0.size(); ++k) worst = std::max(worst, std::abs(gap1[k] - gap0[k]));
  EXPECT_LT(worst, 3.0) << "and stayed in its place on the arm";
  s->reset_to_rest();
  s->shape_points(shapes);
  for (size_t k = 0; k < sleeve_rest.size(); ++k) EXPECT_LT((shapes[sl][k] - sleeve_rest[k]).norm(), 1e-6);
  // Refused, by name.
  RigRider lost = sleeve;
  lost.on = "no-such-part";
  rig.riders = {lost};
  Character c2 = *ch.value;
  std::unique_ptr<Solver> s2 = make_solver("feature_frame");
  EXPECT_FALSE(s2->prepare(c2, rig, rest, SolverWeights{}, &err));
  EXPECT_NE(err.find("rides on 'no-such-part', which is not a sub-shape of the character"), std::string::npos) << err;
  RigRider arm_on_sleeve;
  arm_on_sleeve.part = "arm-left", arm_on_sleeve.on = "sleeve-left", arm_on_sleeve.at = Vec2(105, 165);
  rig.riders = {sleeve, arm_on_sleeve};
  Character c3 = *ch.value;
  std::unique_ptr<Solver> s3 = make_solver("feature_frame");
  EXPECT_FALSE(s3->prepare(c3, rig, rest, SolverWeights{}, &err));
  EXPECT_NE(err.find("rides, through riders, on itself"), std::string::npos) << err;
}

// Live parameters go through the seam: named, ranged, and set keeping the pose.
TEST(Solver, ParametersAreNamedAndSettingThemKeepsThePose) {
  auto ch = load_character((test::characters_dir() / "figure.svg").string());
  ASSERT_TRUE(ch.ok());
  Character c = *ch.value;
  const std::vector<Vec2> rest{{150, 190}, {150, 280}, {245, 250}};
  std::unique_ptr<Solver> s = make_solver("feature_frame");
  SolverWeights w;
  w.rigidity = 2;
  std::string err;
  ASSERT_TRUE(s->prepare(c, default_rig(), rest, w, &err)) << err;
  const auto params = s->parameters();
  ASSERT_EQ(params.size(), 3u);
  EXPECT_EQ(params[0].name, "rigidity");
  EXPECT_EQ(params[0].value, 2.0);
  EXPECT_EQ(params[1].name, "coupling");
  EXPECT_EQ(params[2].name, "position");
  EXPECT_GT(params[0].lo, 0.0);
  std::vector<Vec2> targets = rest;
  targets[2] += Vec2(20, -10);
  s->solve(targets, 8);
  const Vec2 before = s->handle_point(2);
  ASSERT_TRUE(s->set_parameters(std::vector<double>{4.0, 1.0, 100.0}, &err)) << err;
  EXPECT_LT((s->handle_point(2) - before).norm(), 1e-9) << "re-factorising keeps the pose";
  EXPECT_EQ(s->parameters()[0].value, 4.0);
  EXPECT_FALSE(s->set_parameters(std::vector<double>{1.0}, &err));
  EXPECT_NE(err.find("3 parameters"), std::string::npos) << err;
}

}  // namespace
}  // namespace mar

namespace mar {
namespace {

// A soft target (SolverWeights::handle_weights, a chain's end in secondary motion) pulls its part
// less than a full one and drags the rest less, in every method behind the seam.
TEST(Solver, ASoftTargetPullsLessAndDragsTheRestLessInEveryMethod) {
  auto ch = load_character((test::characters_dir() / "figure.svg").string());
  ASSERT_TRUE(ch.ok());
  const std::vector<Vec2> rest{{150, 190}, {150, 280}, {245, 250}};
  for (const char* method : {"feature_frame", "arap", "rigid_grid"}) {
    double miss[2] = {0, 0}, drag[2] = {0, 0};
    for (int soft = 0; soft < 2; ++soft) {
      Character c = *ch.value;
      std::unique_ptr<Solver> s = make_solver(method);
      SolverWeights w;
      if (soft) w.handle_weights = {1.0, 1.0, 0.05};
      std::string err;
      ASSERT_TRUE(s->prepare(c, default_rig(), rest, w, &err)) << method << ": " << err;
      std::vector<Vec2> targets = rest;
      targets[2] += Vec2(90, -60);  // the hand pulled far past its reach
      for (int f = 0; f < 30; ++f) s->solve(targets, 8);
      miss[soft] = (s->handle_point(2) - targets[2]).norm();
      drag[soft] = (s->handle_point(0) - rest[0]).norm() + (s->handle_point(1) - rest[1]).norm();
      ASSERT_TRUE(std::isfinite(miss[soft]) && std::isfinite(drag[soft])) << method;
    }
    std::printf("%s: the hand misses by %.2f (full) / %.2f (soft); the body dragged %.2f / %.2f\n", method, miss[0], miss[1], drag[0], drag[1]);
    EXPECT_GT(miss[1], miss[0] + 1.0) << method << ": the soft target gives way";
    EXPECT_LE(drag[1], drag[0] + 1e-6) << method << ": and drags the body no more";
  }
}

}  // namespace
}  // namespace mar
