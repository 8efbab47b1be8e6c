// Joints and per-part stiffness of the feature frame (frame/joints.h).
#include "character/load.h"
#include "character/rig.h"
#include "character/svg_loader.h"
#include "frame/joints.h"
#include "geom/polygon.h"
#include "solve/feature_frame.h"
#include "test_util.h"

#include <gtest/gtest.h>

namespace mar {
namespace {

Character example(const std::string& name) {
  auto r = load_character((test::characters_dir() / (name + ".svg")).string());
  EXPECT_TRUE(r.ok()) << r.error;
  return *r.value;
}

int shape_index(const Character& ch, const std::string& id) {
  for (size_t s = 0; s < ch.shapes.size(); ++s) {
    if (ch.shapes[s].id == id) return static_cast<int>(s);
  }
  return -1;
}

const FrameJoint* joint_between(const FeatureFrame& f, const Character& ch, const std::string& a, const std::string& b) {
  const int ia = shape_index(ch, a), ib = shape_index(ch, b);
  for (const FrameJoint& j : f.joints) {
    if ((j.shape_a == ia && j.shape_b == ib) || (j.shape_a == ib && j.shape_b == ia)) return &j;
  }
  return nullptr;
}

FeatureFrame frame_of(Character& ch, const FrameOptions& o = default_frame_options()) {
  refine_for_frame(ch, o);
  return build_feature_frame(ch, o);
}

TEST(overlap_centre, CentreAndAreaOfTwoOverlappingSquares) {
  const Points a{{0, 0}, {10, 0}, {10, 10}, {0, 10}}, b{{5, 5}, {15, 5}, {15, 15}, {5, 15}};
  Vec2 c;
  double area = 0;
  ASSERT_TRUE(overlap_centre(a, b, c, &area));
  EXPECT_NEAR(c.x(), 7.5, 1e-9);
  EXPECT_NEAR(c.y(), 7.5, 1e-9);
  EXPECT_NEAR(area, 25.0, 1e-9);
  const Points far{{20, 20}, {30, 20}, {30, 30}};
  EXPECT_FALSE(overlap_centre(a, far, c));
}

// An arm drawn over a body is hinged where it overlaps the body; hair over a face stays
// welded (it keeps its orientation on the head).
TEST(add_joints_and_stiffness, ArmsAndLegsAreHingedHairIsWelded) {
  Character ch = example("figure");
  const FeatureFrame f = frame_of(ch);
  const FrameJoint* shoulder = joint_between(f, ch, "sleeve-right", "torso");
  ASSERT_NE(shoulder, nullptr);
  EXPECT_LT((shoulder->at - Vec2(190, 160)).norm(), 8.0);  // at the shoulder
  EXPECT_NE(joint_between(f, ch, "torso", "leg-left"), nullptr);
  EXPECT_EQ(joint_between(f, ch, "face", "hair-cap"), nullptr);
  EXPECT_EQ(joint_between(f, ch, "arm-right", "sleeve-right"), nullptr);  // a sleeve on its arm: welded
  // A hinge is two frame vertices at the joint, pinned by a zero-length line.
  bool pinned = false;
  for (const FrameLine& l : f.lines) {
    if (l.kind == FrameLine::Joint && ((l.a == shoulder->va && l.b == shoulder->vb) || (l.a == shoulder->vb && l.b == shoulder->va))) {
      pinned = true;
      EXPECT_NEAR((f.rest[static_cast<size_t>(l.a)] - f.rest[static_cast<size_t>(l.b)]).norm(), 0.0, 1e-12);
    }
  }
  EXPECT_TRUE(pinned);
  // Wings on a butterfly's body are hinges too (a small share of the body is covered).
  Character b = example("butterfly");
  const FeatureFrame fb = frame_of(b);
  EXPECT_NE(joint_between(fb, b, "wing-left", "body"), nullptr);
  EXPECT_NE(joint_between(fb, b, "wing-right", "body"), nullptr);
}

TEST(add_joints_and_stiffness, RigJointsMoveAddAndWeld) {
  Character ch = example("figure");
  FrameOptions o = default_frame_options();
  o.joints.push_back({true, Vec2(192, 158), "sleeve-right", "torso", 2.0, false, "rig:1"});  // moved, stiffer
  o.joints.push_back({false, Vec2::Zero(), "torso", "leg-left", -1, true, "rig:2"});         // welded
  o.joints.push_back({true, Vec2(150, 100), "", "", -1, false, "rig:3"});                    // face over neck? by containment
  o.joints.push_back({true, Vec2(5, 5), "", "", -1, false, "rig:4"});                        // nothing there
  const FeatureFrame f = frame_of(ch, o);
  const FrameJoint* shoulder = joint_between(f, ch, "sleeve-right", "torso");
  ASSERT_NE(shoulder, nullptr);
  EXPECT_NEAR((shoulder->at - Vec2(192, 158)).norm(), 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(shoulder->stiffness, 2.0);
  EXPECT_FALSE(shoulder->automatic);
  EXPECT_EQ(joint_between(f, ch, "torso", "leg-left"), nullptr);
  EXPECT_NE(joint_between(f, ch, "torso", "leg-right"), nullptr);
  bool warned = false;
  for (const std::string& w : f.warnings) warned = warned || w.rfind("rig:4: joint needs two closed parts", 0) == 0;
  EXPECT_TRUE(warned);
}

TEST(part_stiffness, BiggerPartsAreStifferAndTheRigOverrides) {
  const Character ch = example("figure");
  FrameOptions o = default_frame_options();
  std::vector<double> k = part_stiffness(ch, o, nullptr);
  const int torso = shape_index(ch, "torso"), eye = shape_index(ch, "eye-left"), mouth = shape_index(ch, "mouth");
  EXPECT_GT(k[static_cast<size_t>(torso)], 2.0);
  EXPECT_DOUBLE_EQ(k[static_cast<size_t>(eye)], 1.0);    // small parts: 1
  EXPECT_DOUBLE_EQ(k[static_cast<size_t>(mouth)], 1.0);  // open strokes: 1
  for (double v : k) EXPECT_LE(v, 4.0);
  o.stiffness.push_back({"torso", 7.5, "rig:9"});
  o.stiffness.push_back({"nobody", 2.0, "rig:10"});
  std::vector<std::string> warnings;
  k = part_stiffness(ch, o, &warnings);
  EXPECT_DOUBLE_EQ(k[static_cast<size_t>(torso)], 7.5);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("rig:10: no sub-shape 'nobody'"), std::string::npos);
}

// Under the same drag, a stiffer torso bends less (monotone).
TEST(part_stiffness, StifferTorsoBendsLessUnderTheSameDrag) {
  double previous = 1e300;
  for (double stiffness : {0.5, 1.0, 4.0, 16.0}) {
    Character ch = example("figure");
    FrameOptions o = default_frame_options();
    o.stiffness.push_back({"torso", stiffness, "t"});
    const FeatureFrame f = frame_of(ch, o);
    const std::vector<Vec2> rest{{150, 190}, {150, 280}};  // chest, hips
    std::vector<ShapeParam> hs;
    for (const Vec2& p : rest) hs.push_back(bind_point(f, ch, p));
    FeatureFrameSolver s;
    ASSERT_TRUE(s.prepare(f, hs, SolverWeights{}));
    const std::vector<Vec2> targets{{185, 190}, {150, 280}};  // chest dragged aside
    s.solve(targets, 300);
    std::vector<Points> shapes;
    for (const SubShape& sh : ch.shapes) shapes.push_back(sh.points);
    reconstruct_shapes(f, s.vertices(), shapes);
    const size_t torso = static_cast<size_t>(shape_index(ch, "torso"));
    const double bend = rigid_fit_rms(ch.shapes[torso].points, shapes[torso]);
    EXPECT_LT(bend, previous) << "stiffness " << stiffness;
    previous = bend;
  }
}

// A hinged limb turns about its joint while the body, held by its handles, stays put.
TEST(add_joints_and_stiffness, AHingedArmTurnsAboutItsJointAndTheBodyKeepsItsShape) {
  Character ch = example("figure");
  const FeatureFrame f = frame_of(ch);
  const FrameJoint* shoulder = joint_between(f, ch, "sleeve-right", "torso");
  ASSERT_NE(shoulder, nullptr);
  const std::vector<Vec2> rest{{150, 190}, {150, 280}, {245, 250}};  // chest, hips, right hand
  std::vector<ShapeParam> hs;
  for (const Vec2& p : rest) hs.push_back(bind_point(f, ch, p));
  FeatureFrameSolver s;
  ASSERT_TRUE(s.prepare(f, hs, SolverWeights{}));
  const double a = -100 * M_PI / 180;
  const Vec2 d = rest[2] - shoulder->at;
  std::vector<Vec2> targets = rest;
  targets[2] = shoulder->at + Vec2(std::cos(a) * d.x() - std::sin(a) * d.y(), std::sin(a) * d.x() + std::cos(a) * d.y());
  s.initial_guess(targets);
  s.solve(targets, 12);
  std::vector<Points> shapes;
  for (const SubShape& sh : ch.shapes) shapes.push_back(sh.points);
  reconstruct_shapes(f, s.vertices(), shapes);
  const size_t torso = static_cast<size_t>(shape_index(ch, "torso")), arm = static_cast<size_t>(shape_index(ch, "arm-right"));
  EXPECT_LT(rigid_fit_rms(ch.shapes[torso].points, shapes[torso]), 0.003 * ch.height);
  EXPECT_LT(rigid_fit_rms(ch.shapes[arm].points, shapes[arm]), 0.003 * ch.height);
  EXPECT_LT((eval_param(hs[2], s.vertices()) - targets[2]).norm(), 0.005 * ch.height);
}

}  // namespace
}  // namespace mar
