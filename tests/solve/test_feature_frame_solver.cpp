#include "character/load.h"
#include "character/svg_loader.h"
#include "geom/polygon.h"
#include "geom/triangulate.h"
#include "solve/feature_frame.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <random>

namespace mar {
namespace {

Character example(const std::string& name) {
  auto r = load_character((test::characters_dir() / (name + ".svg")).string());
  EXPECT_TRUE(r.ok()) << r.error;
  return *r.value;
}

struct Rig {
  Character ch;
  FeatureFrame frame;
  std::vector<Vec2> rest;
  std::vector<ShapeParam> handles;
};

Rig make_rig(const std::string& name, std::vector<Vec2> rest_points) {
  Rig r;
  r.ch = example(name);
  r.frame = build_feature_frame(r.ch, default_frame_options());
  r.rest = std::move(rest_points);
  for (const Vec2& p : r.rest) r.handles.push_back(bind_point(r.frame, r.ch, p));
  return r;
}

std::vector<Points> rest_shapes(const Character& ch) {
  std::vector<Points> out;
  for (const SubShape& s : ch.shapes) out.push_back(s.points);
  return out;
}

// (a) Targets that are a rigid motion of the rest handles move every shape vertex by it,
// after the solve from rest (rigid initial guess + the live loop's 12 iterations).
TEST(FeatureFrameSolver, RigidMotionOfHandlesGivesThatMotionEverywhere) {
  for (const char* name : {"butterfly", "figure", "koi", "boy", "candle"}) {
    Rig r = make_rig(name, {});
    const Bounds b = r.ch.bounds();
    r = make_rig(name, {b.lo, b.hi, Vec2(b.lo.x(), b.hi.y()), 0.5 * (b.lo + b.hi)});
    FeatureFrameSolver s;
    ASSERT_TRUE(s.prepare(r.frame, r.handles, SolverWeights{}));
    const double ang = 0.7, c = std::cos(ang), sn = std::sin(ang);
    const Vec2 t(35, -12);
    auto motion = [&](const Vec2& p) { return Vec2(c * p.x() - sn * p.y() + t.x(), sn * p.x() + c * p.y() + t.y()); };
    std::vector<Vec2> targets;
    for (const ShapeParam& h : r.handles) targets.push_back(motion(eval_param(h, r.frame.rest)));
    s.initial_guess(targets);  // the start of a solve from rest
    s.solve(targets, 12);
    std::vector<Points> out = rest_shapes(r.ch);
    reconstruct_shapes(r.frame, s.vertices(), out);
    const double scale = (b.hi - b.lo).norm();
    double worst = 0;
    for (size_t k = 0; k < out.size(); ++k)
      for (size_t i = 0; i < out[k].size(); ++i) worst = std::max(worst, (out[k][i] - motion(r.ch.shapes[k].points[i])).norm());
    EXPECT_LE(worst / scale, 1e-9) << name;
    // The same motion as a live drag (30 frames, 8 iterations each, warm start).
    FeatureFrameSolver live;
    ASSERT_TRUE(live.prepare(r.frame, r.handles, SolverWeights{}));
    for (int f = 1; f <= 30; ++f) {
      const double a = ang * f / 30, cf = std::cos(a), sf = std::sin(a);
      std::vector<Vec2> tf;
      for (const ShapeParam& h : r.handles) {
        const Vec2 p = eval_param(h, r.frame.rest);
        tf.push_back(Vec2(cf * p.x() - sf * p.y(), sf * p.x() + cf * p.y()) + t * (f / 30.0));
      }
      live.solve(tf, 8);
    }
    reconstruct_shapes(r.frame, live.vertices(), out);
    worst = 0;
    for (size_t k = 0; k < out.size(); ++k)
      for (size_t i = 0; i < out[k].size(); ++i) worst = std::max(worst, (out[k][i] - motion(r.ch.shapes[k].points[i])).norm());
    EXPECT_LE(worst / scale, 1e-9) << name << " (live drag)";
  }
}

// (b) The alternation never increases the energy.
TEST(FeatureFrameSolver, EnergyNeverIncreases) {
  Rig r = make_rig("figure", {{150, 60}, {50, 250}, {250, 250}, {110, 395}, {190, 395}});
  FeatureFrameSolver s;
  ASSERT_TRUE(s.prepare(r.frame, r.handles, SolverWeights{}));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-60, 60);
  for (int trial = 0; trial < 5; ++trial) {
    std::vector<Vec2> targets;
    for (const Vec2& p : r.rest) targets.push_back(p + Vec2(jitter(rng), jitter(rng)));
    std::vector<double> e(41);
    s.solve(targets, 40, e);
    for (size_t k = 1; k < e.size(); ++k) EXPECT_LE(e[k], e[k - 1] * (1 + 1e-12) + 1e-12) << "trial " << trial << " it " << k;
    EXPECT_LT(e.back(), e.front());
  }
}

// (c) The closed-form energy equals a numerical quadrature of seed 000 Eqs. 1-2 (each line
// weighted by its parts' stiffness).
TEST(FeatureFrameSolver, ClosedFormEnergyMatchesQuadrature) {
  Rig r = make_rig("butterfly", {{200, 135}, {60, 100}, {340, 280}});
  SolverWeights w;
  w.rigidity = 1.3;
  w.coupling = 0.7;
  w.position = 100;
  FeatureFrameSolver s;
  ASSERT_TRUE(s.prepare(r.frame, r.handles, w));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-20, 20), ang(-3, 3);
  std::vector<Vec2> v(r.frame.rest.size());
  for (size_t i = 0; i < v.size(); ++i) v[i] = r.frame.rest[i] + Vec2(u(rng), u(rng));
  std::vector<double> la(r.frame.lines.size()), va(v.size());
  for (double& a : la) a = ang(rng);
  for (double& a : va) a = ang(rng);
  std::vector<Vec2> targets{{210, 140}, {50, 90}, {330, 300}};
  // 5-point Gauss-Legendre on [0, 1].
  const double gx[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831, 0.9061798459386640};
  const double gw[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665, 0.2369268850561891};
  auto rotate = [](double a, const Vec2& d) { return Vec2(std::cos(a) * d.x() - std::sin(a) * d.y(), std::sin(a) * d.x() + std::cos(a) * d.y()); };
  double e_rig = 0;  // Eq. 1: rotation about the midpoint of every feature line
  for (int j = 0; j < r.frame.feature_lines; ++j) {
    const FrameLine& l = r.frame.lines[static_cast<size_t>(j)];
    const Vec2 a = v[static_cast<size_t>(l.a)], b = v[static_cast<size_t>(l.b)];
    const Vec2 ab = r.frame.rest[static_cast<size_t>(l.a)], bb = r.frame.rest[static_cast<size_t>(l.b)];
    for (int k = 0; k < 5; ++k) {
      const double t = 0.5 * (gx[k] + 1);
      const Vec2 vt = (1 - t) * a + t * b, vbt = (1 - t) * ab + t * bb;
      e_rig += l.weight * 0.5 * gw[k] * (vt - 0.5 * (a + b) - rotate(la[static_cast<size_t>(j)], vbt - 0.5 * (ab + bb))).squaredNorm();
    }
  }
  double e_cou = 0;  // Eq. 2: every line incident to vertex i rotates about i
  for (size_t i = 0; i < v.size(); ++i) {
    for (const FrameLine& l : r.frame.lines) {
      if (l.a == l.b || (l.a != static_cast<int>(i) && l.b != static_cast<int>(i))) continue;
      const size_t n = static_cast<size_t>(l.a == static_cast<int>(i) ? l.b : l.a);
      for (int k = 0; k < 5; ++k) {
        const double t = 0.5 * (gx[k] + 1);
        const Vec2 vt = (1 - t) * v[i] + t * v[n], vbt = (1 - t) * r.frame.rest[i] + t * r.frame.rest[n];
        e_cou += l.weight * 0.5 * gw[k] * (vt - v[i] - rotate(va[i], vbt - r.frame.rest[i])).squaredNorm();
      }
    }
  }
  double e_pos = 0;
  for (size_t h = 0; h < targets.size(); ++h) e_pos += (eval_param(r.handles[h], v) - targets[h]).squaredNorm();
  const double quad = w.rigidity * e_rig + w.coupling * e_cou + w.position * e_pos;
  const double closed = s.energy_with_rotations(v, la, va, targets);
  EXPECT_NEAR(closed, quad, 1e-9 * quad);
}

// Without the rigid initial guess the alternation still gets there, only slowly.
TEST(FeatureFrameSolver, ConvergesTowardRigidMotionWithoutAlignment) {
  Rig r = make_rig("butterfly", {{40, 80}, {360, 80}, {200, 300}, {200, 135}});
  FeatureFrameSolver s;
  ASSERT_TRUE(s.prepare(r.frame, r.handles, SolverWeights{}));
  std::vector<Vec2> targets;
  for (const ShapeParam& h : r.handles) {
    const Vec2 p = eval_param(h, r.frame.rest);
    targets.push_back(Vec2(std::cos(0.3) * p.x() - std::sin(0.3) * p.y(), std::sin(0.3) * p.x() + std::cos(0.3) * p.y()));
  }
  std::vector<double> e(401);
  s.solve(targets, 400, e);
  EXPECT_LT(e[400], 1e-3 * e[0]);
}

// (d) Reachable targets are met: residual below 0.5% of the character's diagonal after
// the live loop's 12 iterations (warm-started frame to frame, as in a show).
// The hinge of the figure's left arm (the joint nearest its shoulder).
Vec2 left_shoulder(const FeatureFrame& f) {
  Vec2 best = f.joints.at(0).at;
  for (const FrameJoint& j : f.joints) {
    if ((j.at - Vec2(110, 160)).norm() < (best - Vec2(110, 160)).norm()) best = j.at;
  }
  return best;
}

Vec2 rotate_about(const Vec2& p, const Vec2& c, double deg) {
  const double a = deg * M_PI / 180, co = std::cos(a), si = std::sin(a);
  const Vec2 d = p - c;
  return c + Vec2(co * d.x() - si * d.y(), si * d.x() + co * d.y());
}

TEST(FeatureFrameSolver, ReachableTargetsAreMet) {
  Rig r = make_rig("figure", {{150, 60}, {110, 395}, {190, 395}, {50, 250}});
  FeatureFrameSolver s;
  ASSERT_TRUE(s.prepare(r.frame, r.handles, SolverWeights{}));
  std::vector<Vec2> targets = r.rest;
  const double diag = r.frame.diagonal;
  const Vec2 shoulder = left_shoulder(r.frame);
  // Raise the left hand over 30 frames, turning the arm 80 degrees about its shoulder.
  for (int f = 1; f <= 30; ++f) {
    targets[3] = rotate_about(r.rest[3], shoulder, 80.0 * f / 30);
    s.solve(targets, 12);
  }
  for (int f = 0; f < 5; ++f) s.solve(targets, 12);  // hold still a few frames
  for (size_t h = 0; h < targets.size(); ++h) {
    EXPECT_LT((eval_param(r.handles[h], s.vertices()) - targets[h]).norm(), 0.005 * diag) << "handle " << h;
  }
}

// A hand pulled beyond its arm's reach: the arm points at the target and stretches at most
// a little; the body keeps its shape and stays where its handles hold it.
TEST(FeatureFrameSolver, TargetsBeyondReachStopTheLimbNotTheBody) {
  Rig r = make_rig("figure", {{150, 60}, {110, 395}, {190, 395}, {50, 250}, {150, 190}});
  FeatureFrameSolver s;
  ASSERT_TRUE(s.prepare(r.frame, r.handles, SolverWeights{}));
  const Vec2 shoulder = left_shoulder(r.frame);
  const double reach = (r.rest[3] - shoulder).norm();
  std::vector<Vec2> targets = r.rest;
  for (int f = 1; f <= 60; ++f) {  // out to 2x the reach, straight left
    targets[3] = shoulder + Vec2(-reach * (1 + f / 60.0), 0);
    s.solve(targets, 8);
  }
  std::vector<Points> shapes = rest_shapes(r.ch);
  reconstruct_shapes(r.frame, s.vertices(), shapes);
  const Vec2 hand = eval_param(r.handles[3], s.vertices());
  EXPECT_LT((hand - shoulder).norm(), 1.06 * reach);            // stretched by at most ~5%
  EXPECT_LT(std::abs((hand - shoulder).normalized().y()), 0.05);  // and pointing at the target
  for (size_t k = 0; k < r.ch.shapes.size(); ++k) {
    if (r.ch.shapes[k].id != "torso") continue;
    EXPECT_LT(rigid_fit_rms(r.ch.shapes[k].points, shapes[k]), 0.005 * r.ch.height);  // the body keeps its shape
  }
  EXPECT_LT((eval_param(r.handles[4], s.vertices()) - r.rest[4]).norm(), 0.005 * r.frame.diagonal);  // and its place
  // No fold-over: no triangle of any part's fill triangulation flips.
  int flipped = 0, triangles = 0;
  for (size_t k = 0; k < r.ch.shapes.size(); ++k) {
    const SubShape& sh = r.ch.shapes[k];
    std::vector<Ring> rings;
    for (const Contour& c : sh.contours) {
      if (c.closed) rings.push_back({c.begin, c.count});
    }
    if (rings.empty()) continue;
    const FillMesh m = triangulate_fill(sh.points, rings, FillRule::NonZero);
    std::vector<Vec2> now(m.vertices.size());
    fill_mesh_positions(m, shapes[k], now);
    for (size_t t = 0; t + 2 < m.triangles.size(); t += 3) {
      auto area = [&](const std::vector<Vec2>& p) {
        const Vec2 &a = p[static_cast<size_t>(m.triangles[t])], &b = p[static_cast<size_t>(m.triangles[t + 1])],
                   &c = p[static_cast<size_t>(m.triangles[t + 2])];
        return (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
      };
      ++triangles;
      if (area(m.vertices) * area(now) < 0) ++flipped;
    }
  }
  EXPECT_GT(triangles, 300);  // every filled part checked
  EXPECT_EQ(flipped, 0);
}

bool all_finite(std::span<const Vec2> v) {
  for (const Vec2& p : v)
    if (!p.allFinite()) return false;
  return true;
}

// (e) Degenerate cases give finite, sensible output.
TEST(FeatureFrameSolver, DegenerateCases) {
  const Character ch = example("butterfly");
  const FeatureFrame f = build_feature_frame(ch, default_frame_options());
  const double diag = f.diagonal;
  FeatureFrameSolver s;
  {  // coincident handles pulled apart
    std::vector<ShapeParam> h{bind_point(f, ch, {200, 135}), bind_point(f, ch, {200, 135})};
    ASSERT_TRUE(s.prepare(f, h, SolverWeights{}));
    s.solve(std::vector<Vec2>{{150, 135}, {250, 135}}, 12);
    EXPECT_TRUE(all_finite(s.vertices()));
    // compromise: the bound point ends up between the two targets
    EXPECT_NEAR(eval_param(h[0], s.vertices()).x(), 200, 5);
  }
  {  // a target 100x the character size away
    std::vector<ShapeParam> h{bind_point(f, ch, {200, 135}), bind_point(f, ch, {70, 80})};
    ASSERT_TRUE(s.prepare(f, h, SolverWeights{}));
    s.solve(std::vector<Vec2>{{200, 135}, {70 + 100 * diag, 80}}, 12);
    EXPECT_TRUE(all_finite(s.vertices()));
  }
  {  // non-finite target: ignored, pose stays finite
    std::vector<ShapeParam> h{bind_point(f, ch, {200, 135})};
    ASSERT_TRUE(s.prepare(f, h, SolverWeights{}));
    s.solve(std::vector<Vec2>{{NAN, 1}}, 12);
    EXPECT_TRUE(all_finite(s.vertices()));
  }
  {  // one handle: the character translates rigidly
    std::vector<ShapeParam> h{bind_point(f, ch, {200, 135})};
    ASSERT_TRUE(s.prepare(f, h, SolverWeights{}));
    s.solve(std::vector<Vec2>{{230, 155}}, 12);
    for (size_t i = 0; i < f.rest.size(); ++i) EXPECT_NEAR((s.vertices()[i] - f.rest[i] - Vec2(30, 20)).norm(), 0, 1e-6);
  }
  {  // empty rig: nothing moves (up to the conditioning of the tiny regulariser)
    ASSERT_TRUE(s.prepare(f, {}, SolverWeights{}));
    s.solve({}, 12);
    for (size_t i = 0; i < f.rest.size(); ++i) EXPECT_NEAR((s.vertices()[i] - f.rest[i]).norm(), 0, 1e-6);
  }
  {  // a part with no handle: cut the antennae loose by deleting every sewing line
    FrameOptions o = default_frame_options();
    for (int k = f.feature_lines; k < static_cast<int>(f.lines.size()); ++k) {
      SewingEdit d;
      d.kind = SewingEdit::Delete;
      d.from = f.rest[static_cast<size_t>(f.lines[static_cast<size_t>(k)].a)];
      d.to = f.rest[static_cast<size_t>(f.lines[static_cast<size_t>(k)].b)];
      o.sewing.push_back(d);
    }
    const FeatureFrame loose = build_feature_frame(ch, o);
    ASSERT_EQ(loose.sewing_lines, 0);
    std::vector<ShapeParam> h{bind_point(loose, ch, {200, 135})};
    ASSERT_TRUE(s.prepare(loose, h, SolverWeights{}));
    s.solve(std::vector<Vec2>{{260, 135}}, 12);
    EXPECT_TRUE(all_finite(s.vertices()));
    // unhandled parts stay where they were
    EXPECT_NEAR((s.vertices()[0] - loose.rest[0]).norm(), 0, 1e-6);
  }
  {  // zero-length feature lines: a contour that doubles back on itself
    auto r = load_svg_string(R"svg(<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100">
      <path d="M10 10 L90 10 L10 10 L90 10" stroke="black" fill="none"/>
      <path d="M50 50 L50 50 L60 60" stroke="black" fill="none"/></svg>)svg", "z.svg");
    ASSERT_TRUE(r.ok());
    const FeatureFrame zf = build_feature_frame(*r.value, default_frame_options());
    std::vector<ShapeParam> h{bind_point(zf, *r.value, {10, 10})};
    ASSERT_TRUE(s.prepare(zf, h, SolverWeights{}));
    s.solve(std::vector<Vec2>{{40, 30}}, 12);
    EXPECT_TRUE(all_finite(s.vertices()));
    std::vector<Points> out{r.value->shapes[0].points, r.value->shapes[1].points};
    reconstruct_shapes(zf, s.vertices(), out);
    for (const Points& p : out) EXPECT_TRUE(all_finite(p));
  }
  EXPECT_FALSE(s.prepare(FeatureFrame{}, {}, SolverWeights{}));
}

}  // namespace
}  // namespace mar

namespace mar {
namespace {

// The extra handle (rank-2 Woodbury update of the factorised system) gives the same solve
// as factorising the system with that handle included.
TEST(FeatureFrameSolver, ExtraHandleEqualsRefactorisingWithIt) {
  Rig r = make_rig("figure", {{150, 60}, {110, 395}, {190, 395}, {50, 250}});
  const ShapeParam extra = bind_point(r.frame, r.ch, Vec2(120, 200));
  SolverWeights w;
  w.reach_stretch = -1;  // compare the linear algebra alone (no reach, no jump guess, and
  w.jump = 0;            // no Anderson mixing, whose accept/reject turns rounding into steps)
  w.anderson = 0;
  FeatureFrameSolver a, b;
  ASSERT_TRUE(a.prepare(r.frame, r.handles, w));
  std::vector<ShapeParam> with = r.handles;
  with.push_back(extra);
  ASSERT_TRUE(b.prepare(r.frame, with, w));
  a.set_extra_handle(extra);
  ASSERT_TRUE(a.has_extra_handle());
  std::vector<Vec2> targets = r.rest;
  targets.push_back(Vec2(90, 215));
  for (int f = 0; f < 5; ++f) {
    a.solve(targets, 6);
    b.solve(targets, 6);
  }
  for (size_t i = 0; i < a.vertices().size(); ++i) {
    EXPECT_NEAR((a.vertices()[i] - b.vertices()[i]).norm(), 0.0, 1e-9 * r.frame.diagonal) << i;
  }
  // Cleared, it is the system without it again.
  a.clear_extra_handle();
  FeatureFrameSolver c;
  ASSERT_TRUE(c.prepare(r.frame, r.handles, w));
  c.set_vertices(a.vertices());
  const std::vector<Vec2> base(targets.begin(), targets.end() - 1);
  a.solve(base, 4);
  c.solve(base, 4);
  for (size_t i = 0; i < a.vertices().size(); ++i) EXPECT_NEAR((a.vertices()[i] - c.vertices()[i]).norm(), 0.0, 1e-9 * r.frame.diagonal);
}

// Soft vertex targets (the brush: a rank-2k Woodbury update) give the same solve as
// factorising with a handle of that weight at each of those vertices, and cleared leave the
// system without them (their frames allocate nothing: Brush.*).
TEST(FeatureFrameSolver, SoftVertexTargetsEqualRefactorisingWithWeightedHandles) {
  Rig r = make_rig("figure", {{150, 60}, {110, 395}, {190, 395}, {50, 250}});
  SolverWeights w;
  w.reach_stretch = -1;
  w.jump = 0;
  w.anderson = 0;
  const std::vector<int> verts{3, 4, 5, 6, 7, 20};
  const std::vector<double> weights{1.0, 0.8, 0.5, 0.25, 0.1, 0.03};
  SolverWeights wb = w;
  std::vector<ShapeParam> with = r.handles;
  wb.handle_weights.assign(r.handles.size(), 1.0);
  for (size_t i = 0; i < verts.size(); ++i) {
    ShapeParam p;
    p.a = p.b = verts[i];
    p.offset_only = true;  // the vertex itself
    with.push_back(p);
    wb.handle_weights.push_back(weights[i]);
  }
  FeatureFrameSolver a, b;
  ASSERT_TRUE(a.prepare(r.frame, r.handles, w));
  ASSERT_TRUE(b.prepare(r.frame, with, wb));
  a.reserve_soft(8);
  ASSERT_TRUE(a.set_soft(verts, weights));
  EXPECT_FALSE(a.set_soft(std::vector<int>(9, 1), std::vector<double>(9, 1.0))) << "over the reserved count";
  ASSERT_TRUE(a.set_soft(verts, weights));
  std::vector<Vec2> targets = r.rest, more = r.rest;
  for (size_t i = 0; i < verts.size(); ++i) {
    a.soft_targets()[i] = r.frame.rest[size_t(verts[i])] + Vec2(12.0 + double(i), -20.0);
    more.push_back(a.soft_targets()[i]);
  }
  for (int f = 0; f < 5; ++f) a.solve(targets, 6);
  for (int f = 0; f < 5; ++f) b.solve(more, 6);
  double moved = 0;
  for (size_t i = 0; i < a.vertices().size(); ++i) {
    EXPECT_NEAR((a.vertices()[i] - b.vertices()[i]).norm(), 0.0, 1e-9 * r.frame.diagonal) << i;
    moved = std::max(moved, (a.vertices()[i] - r.frame.rest[i]).norm());
  }
  EXPECT_GT(moved, 5.0) << "(the soft targets pulled)";
  EXPECT_NEAR(a.energy(targets), b.energy(more), 1e-9 * std::max(1.0, b.energy(more)));
  a.clear_soft();
  FeatureFrameSolver c;
  ASSERT_TRUE(c.prepare(r.frame, r.handles, w));
  c.set_vertices(a.vertices());
  a.solve(targets, 4);
  c.solve(targets, 4);
  for (size_t i = 0; i < a.vertices().size(); ++i) EXPECT_NEAR((a.vertices()[i] - c.vertices()[i]).norm(), 0.0, 1e-9 * r.frame.diagonal);
}

// Anderson acceleration: accepted energies never increase, and in the same iteration count
// it gets lower than the plain alternation after a large move.
TEST(FeatureFrameSolver, AndersonLowersTheEnergyFasterAndNeverRaisesIt) {
  Rig r = make_rig("figure", {{150, 60}, {110, 395}, {190, 395}, {50, 250}});
  std::vector<Vec2> targets = r.rest;
  targets[3] = Vec2(40, 140);
  targets[0] = Vec2(170, 70);
  double final_energy[2] = {0, 0};
  for (int m : {0, 5}) {
    SolverWeights w;
    w.anderson = m;
    FeatureFrameSolver s;
    ASSERT_TRUE(s.prepare(r.frame, r.handles, w));
    std::vector<double> e(13);
    s.solve(targets, 12, e);
    for (size_t k = 1; k < e.size(); ++k) EXPECT_LE(e[k], e[k - 1] * (1 + 1e-12)) << "m=" << m << " k=" << k;
    final_energy[m == 0 ? 0 : 1] = e.back();
    if (m > 0) {
      EXPECT_GT(s.anderson_accepted(), 0);
    }
  }
  EXPECT_LT(final_energy[1], 0.8 * final_energy[0]);
}

// A jump in the targets (a pose recall) starts from the articulated guess: one solve lands
// near the pose instead of unwinding from the previous one.
TEST(FeatureFrameSolver, AJumpStartsFromTheArticulatedGuess) {
  Rig r = make_rig("figure", {{150, 60}, {110, 395}, {190, 395}, {50, 250}, {150, 190}});
  FeatureFrameSolver s;
  ASSERT_TRUE(s.prepare(r.frame, r.handles, SolverWeights{}));
  const Vec2 shoulder = left_shoulder(r.frame);
  std::vector<Vec2> targets = r.rest;
  s.solve(targets, 8);
  targets[3] = rotate_about(r.rest[3], shoulder, 120);
  s.solve(targets, 8);
  EXPECT_EQ(s.jumps(), 1);
  EXPECT_LT((eval_param(r.handles[3], s.vertices()) - targets[3]).norm(), 0.005 * r.frame.diagonal);
}

}  // namespace
}  // namespace mar
