// The topology-aware rigid grid (seed 003) behind the solver seam (solve/rigid_grid.h).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "character/load.h"
#include "geom/polygon.h"
#include "solve/rigid_grid.h"
#include "test_util.h"

namespace mar {
namespace {

// A filled polygon as a one-part character.
Character polygon(const std::vector<Vec2>& outline) {
  Character c;
  SubShape s;
  s.id = "shape";
  s.points = outline;
  s.contours.push_back({0, int(outline.size()), true});
  s.fill.enabled = true;
  c.shapes.push_back(s);
  c.width = c.bounds().hi.x();
  c.height = c.bounds().hi.y();
  return c;
}

Rig grid_rig(double cell, int w) {
  Rig r = default_rig();
  r.solver = "rigid_grid";
  r.grid_cell = cell;
  r.grid_half_width = w;
  return r;
}

// Every shape of `c` as `s` has posed it.
std::vector<Points> posed(const Character& c, const RigidGrid& s) {
  std::vector<Points> out;
  for (const SubShape& sh : c.shapes) out.push_back(sh.points);
  s.shape_points(out);
  return out;
}

struct Figure {
  Character c;
  std::vector<Vec2> rest{{150, 60}, {150, 190}, {150, 280}, {55, 250}, {245, 250}, {95, 395}, {205, 395}};
  RigidGrid s;
  bool ok = false;
  explicit Figure(int w = 3, const char* file = "figure.svg", const char* junction = "triangles") {
    auto ch = load_character((test::characters_dir() / file).string());
    if (!ch.ok()) return;
    c = *ch.value;
    Rig r = default_rig();
    r.grid_half_width = w;
    r.grid_junction_term = junction;
    std::string err;
    ok = s.prepare(c, r, rest, SolverWeights{}, &err);
    EXPECT_TRUE(ok) << err;
  }
  std::vector<Points> shapes() const { return posed(c, s); }
};

TEST(RigidGrid, GridCurvesAndJunctionOverTheCharacterWithEveryPointBound) {
  for (const char* file : {"figure.svg", "boy.png"}) {
    Figure f(3, file);
    ASSERT_TRUE(f.ok) << file;
    EXPECT_GT(f.s.grid_nodes(), 100u) << file;
    EXPECT_GT(f.s.boundary_nodes(), 100u) << file;
    size_t junction = 0;
    for (char j : f.s.junction()) junction += j ? 1 : 0;
    EXPECT_GT(junction, 50u) << file;
    EXPECT_LT(junction, f.s.mesh_triangles().size()) << file << ": triangles deep inside the grid are not junction triangles";
    const auto shapes = f.shapes();
    for (size_t k = 0; k < shapes.size(); ++k)
      for (size_t i = 0; i < shapes[k].size(); ++i)
        ASSERT_LT((shapes[k][i] - f.c.shapes[k].points[i]).norm(), 1e-9) << file << " " << k << " " << i;
    for (size_t h = 0; h < f.rest.size(); ++h) EXPECT_LT((f.s.handle_point(h) - f.rest[h]).norm(), 1e-9) << file;
  }
}

// A wavy disc flattened the way an editor's curves are, a point every 0.6 units (a cell is 10),
// and its outline drawn again as a shape of its own through the same points.
Character wavy_disc_and_outline() {
  Points p;
  for (int k = 0; k < 2000; ++k) {
    const double a = 2 * M_PI * k / 2000, r = 180 + 6 * std::sin(30 * a);
    p.push_back(Vec2(200 + r * std::cos(a), 200 + r * std::sin(a)));
  }
  Character c = polygon(p);
  SubShape outline = c.shapes[0];
  outline.id = "outline";
  c.shapes.push_back(outline);
  return c;
}

TEST(RigidGrid, ContoursDrawnInManyPointsGetAboutACellBetweenNodesAndEveryPointFollows) {
  Character c = wavy_disc_and_outline(), c_every = c;  // (prepare adds the fill's interior points)
  const std::vector<Vec2> rest{{60, 200}, {340, 200}, {200, 40}};
  RigidGrid thinned, every;
  every.keep_every_contour_point(true);
  std::string err;
  ASSERT_TRUE(thinned.prepare(c, grid_rig(10, 3), rest, SolverWeights{}, &err)) << err;
  ASSERT_TRUE(every.prepare(c_every, grid_rig(10, 3), rest, SolverWeights{}, &err)) << err;
  // 2,000 points on each shape; the rim is about 1,150 units long: about a node a cell, and the
  // outline drawn through the fill's points shares the fill's nodes.
  EXPECT_GE(every.boundary_nodes(), 2000u);
  EXPECT_LT(thinned.boundary_nodes(), 300u);
  EXPECT_GT(thinned.boundary_nodes(), 80u);
  // At rest every drawn point is where it was drawn, the ones no node holds too.
  const auto at_rest = posed(c, thinned);
  for (size_t k = 0; k < at_rest.size(); ++k)
    for (size_t i = 0; i < at_rest[k].size(); ++i) ASSERT_LT((at_rest[k][i] - c.shapes[k].points[i]).norm(), 1e-9) << k << " " << i;
  // Turned and moved whole, every point is turned and moved with it, and the outline stays on its fill.
  const double a = 0.6, cs = std::cos(a), sn = std::sin(a);
  auto move = [&](const Vec2& q) { return Vec2(cs * q.x() - sn * q.y() + 40, sn * q.x() + cs * q.y() - 25); };
  std::vector<Vec2> t;
  for (const Vec2& q : rest) t.push_back(move(q));
  thinned.initial_guess(t);
  thinned.solve(t, 5);
  const auto moved = posed(c, thinned);
  for (size_t k = 0; k < moved.size(); ++k)
    for (size_t i = 0; i < moved[k].size(); ++i) ASSERT_LT((moved[k][i] - move(c.shapes[k].points[i])).norm(), 1e-6) << k << " " << i;
  // Bent, the outline drawn through the fill's points stays on it, point for point.
  t = rest;
  t[2] += Vec2(90, 30);
  for (int k = 0; k < 20; ++k) thinned.solve(t, 4);
  const auto bent = posed(c, thinned);
  double off = 0, moved_most = 0;
  for (size_t i = 0; i < 2000; ++i) {  // (the drawn points; the interior points follow them)
    off = std::max(off, (bent[0][i] - bent[1][i]).norm());
    moved_most = std::max(moved_most, (bent[0][i] - c.shapes[0].points[i]).norm());
  }
  EXPECT_GT(moved_most, 20.0);
  EXPECT_LT(off, 1e-9);
}

// A disc with 1,200 teeth three tenths of a cell deep, eight points a tooth: more bumps than
// the contours' budget of nodes. Each tooth's tip and root stray from the chords far more than
// the twentieth of a cell the contours keep, so each is a node however many there are (a
// leeway widened to the budget dropped the tips of an eagle's feathers, and the grid, bent and
// brought back, settled away from its rest); bent and brought back, every point is at rest.
TEST(RigidGrid, EveryToothOfAContourIsANodeHoweverManyAndTheGridComesBackToRest) {
  Points p;
  constexpr int kTeeth = 1200, kPer = 8;
  for (int k = 0; k < kTeeth * kPer; ++k) {
    const double a = 2 * M_PI * k / (kTeeth * kPer), r = 180 + 3 * std::abs(std::sin(M_PI * k / kPer));
    p.push_back(Vec2(200 + r * std::cos(a), 200 + r * std::sin(a)));
  }
  Character c = polygon(p);
  const std::vector<Vec2> rest{{60, 200}, {340, 200}, {200, 40}, {200, 360}};
  RigidGrid g;
  std::string err;
  ASSERT_TRUE(g.prepare(c, grid_rig(10, 3), rest, SolverWeights{}, &err)) << err;
  EXPECT_GE(g.boundary_nodes(), size_t(2 * kTeeth));
  EXPECT_LT(g.boundary_nodes(), p.size());
  std::vector<Vec2> t = rest;
  for (int f = 0; f <= 240; ++f) {  // the top swung 60 degrees about the middle and back, then held
    const double a = (M_PI / 3) * std::sin(M_PI * std::min(f, 160) / 160.0);
    t[2] = Vec2(200, 200) + 160 * Vec2(std::sin(a), -std::cos(a));
    t[1] = rest[1] + Vec2(0, 40 * std::sin(M_PI * std::min(f, 160) / 160.0));
    g.solve(t, 8);
    if (f == 80) {
      double moved = 0;
      for (size_t i = 0; i < g.rest().size(); ++i) moved = std::max(moved, (g.nodes()[i] - g.rest()[i]).norm());
      EXPECT_GT(moved, 60.0);
    }
  }
  const auto back = posed(c, g);
  double away = 0;
  for (size_t i = 0; i < p.size(); ++i) away = std::max(away, (back[0][i] - p[i]).norm());
  EXPECT_LT(away, 0.05);  // (of a drawing 366 units across)
}

TEST(RigidGrid, ARigidMotionOfTheHandlesMovesEveryNodeRigidly) {
  for (const char* junction : {"triangles", "mvc"}) {
    Figure f(3, "figure.svg", junction);
    ASSERT_TRUE(f.ok);
    const double a = 0.7, c = std::cos(a), s = std::sin(a);
    auto move = [&](const Vec2& p) { return Vec2(c * p.x() - s * p.y() + 30, s * p.x() + c * p.y() - 12); };
    std::vector<Vec2> t;
    for (const Vec2& p : f.rest) t.push_back(move(p));
    f.s.initial_guess(t);
    f.s.solve(t, 5);
    const double size = 400;
    for (size_t i = 0; i < f.s.rest().size(); ++i)
      ASSERT_LT((f.s.nodes()[i] - move(f.s.rest()[i])).norm(), 1e-9 * size) << junction << " " << i;
  }
}

TEST(RigidGrid, LocalGlobalStepsNeverRaiseTheEnergy) {
  for (const char* junction : {"triangles", "mvc"})
    for (int w : {1, 3, 6}) {
      Figure f(w, "figure.svg", junction);
      ASSERT_TRUE(f.ok);
      std::vector<Vec2> t = f.rest;
      t[4] = Vec2(290, 120);  // right hand up
      t[5] = Vec2(60, 420);
      double last = INFINITY;
      for (int k = 0; k < 30; ++k) {
        f.s.solve(t, 1);
        const double e = f.s.energy(t);
        ASSERT_TRUE(std::isfinite(e));
        EXPECT_LE(e, last * (1 + 1e-9) + 1e-9) << junction << " w " << w << " iteration " << k;
        last = e;
      }
    }
}

TEST(RigidGrid, FastSummationEqualsVisitingEveryMember) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1000, 1000);
  for (int w : {1, 3, 6, 9}) {
    Figure f(w, "boy.png");
    ASSERT_TRUE(f.ok);
    const size_t n = f.s.rest().size(), R = f.s.regions();
    std::vector<double> v(n), fast(R), naive(R);
    for (double& x : v) x = u(rng);
    f.s.region_sums(v, fast, true);
    f.s.region_sums(v, naive, false);
    for (size_t r = 0; r < R; ++r) {
      double scale = 0;
      for (int j : f.s.region(r)) scale += std::abs(v[size_t(j)]);
      ASSERT_NEAR(fast[r], naive[r], 1e-12 * scale) << "w " << w << " region " << r;
    }
    std::vector<double> g(R), tf(n), tn(n);
    for (double& x : g) x = u(rng);
    f.s.region_scatter(g, tf, true);
    f.s.region_scatter(g, tn, false);
    for (size_t j = 0; j < n; ++j) ASSERT_NEAR(tf[j], tn[j], 1e-12 * 1000 * double(R)) << "w " << w << " node " << j;
    // The solve gives the same pose either way.
    std::vector<Vec2> t = f.rest;
    t[4] = Vec2(260, 90);
    f.s.solve(t, 6);
    const Points a = f.s.nodes();
    f.s.reset_to_rest();
    f.s.set_fast_summation(false);
    f.s.solve(t, 6);
    for (size_t i = 0; i < n; ++i) ASSERT_LT((f.s.nodes()[i] - a[i]).norm(), 1e-9) << "w " << w << " node " << i;
  }
}

// A U whose arms are half a cell apart: dragging one arm must leave the other where it is, where a
// plain regular grid (square regions) drags it along.
TEST(RigidGrid, ArmsCloserThanACellAreNotNeighbours) {
  const Character c = polygon({{0, 0}, {62, 0}, {62, 200}, {67, 200}, {67, 0}, {127, 0}, {127, 260}, {0, 260}});
  const std::vector<Vec2> rest{{20, 240}, {107, 240}, {30, 10}};
  std::vector<Vec2> t = rest;
  t[2] = Vec2(-40, 30);  // arm A's top, out to the left
  auto arm_b_moves = [&](bool plain) {
    Character ch = c;
    RigidGrid s;
    std::string err;
    EXPECT_TRUE(s.prepare(ch, grid_rig(10, 3), rest, SolverWeights{}, &err)) << err;
    if (plain) {
      EXPECT_TRUE(s.set_plain_regions(true, &err)) << err;
    }
    s.solve(t, 60);
    std::vector<Points> out{ch.shapes[0].points};
    s.shape_points(out);
    double most = 0;
    for (size_t i = 0; i < ch.shapes[0].points.size(); ++i) {
      const Vec2 p = ch.shapes[0].points[i];
      if (p.x() > 66 && p.y() < 150) most = std::max(most, (out[0][i] - p).norm());
    }
    return most;
  };
  const double aware = arm_b_moves(false), plain = arm_b_moves(true);
  EXPECT_LT(aware, 2.0) << "arm B moved with arm A";
  EXPECT_GT(plain, 10.0) << "the plain grid should tie the arms";
}

TEST(RigidGrid, AWiderHalfWidthBendsLessUnderTheSameDrag) {
  const Character c = polygon({{0, 0}, {300, 0}, {300, 40}, {0, 40}});
  const std::vector<Vec2> rest{{5, 5}, {5, 35}, {295, 20}};
  std::vector<Vec2> t = rest;
  t[2] = Vec2(295, 120);
  double last = INFINITY;
  for (int w : {1, 2, 3, 6}) {
    Character ch = c;
    RigidGrid s;
    SolverWeights sw;
    sw.position = 1;  // soft handles: the bar's stiffness decides how far it follows
    std::string err;
    ASSERT_TRUE(s.prepare(ch, grid_rig(10, w), rest, sw, &err)) << err;
    s.solve(t, 300);
    const double bend = s.handle_point(2).y() - 20;
    EXPECT_LT(bend, last) << "w " << w;
    EXPECT_GT(bend, 0) << "w " << w;
    last = bend;
  }
}

// Regions on every stride-th node (the default, about w / 2) stand for all the grid's nodes and
// bend the figure as regions on every node do, with a factor that does not grow with w.
TEST(RigidGrid, StridedRegionsStandForEveryNodeAndBendLikeRegionsOnEveryNode) {
  std::vector<Vec2> t;
  for (int w : {3, 6}) {
    Figure strided(w);
    ASSERT_TRUE(strided.ok);
    EXPECT_EQ(strided.s.stride(), (w + 1) / 2);
    const RigidGrid& s = strided.s;
    const size_t G = s.grid_nodes();
    double share = 0;
    size_t counting = 0;
    std::vector<int> held(G, 0);
    for (size_t r = 0; r < G; ++r) {
      share += s.region_share(r);
      if (s.region_share(r) == 0) continue;
      ++counting;
      for (int j : s.region(r)) held[size_t(j)] = 1;
    }
    EXPECT_EQ(share, double(G)) << "w " << w;
    EXPECT_LT(counting, G / 2) << "w " << w;
    for (size_t j = 0; j < G; ++j) EXPECT_EQ(held[j], 1) << "grid node " << j << " in no counting region, w " << w;

    Figure every(w);
    std::string err;
    ASSERT_TRUE(every.s.set_stride(1, &err)) << err;
    EXPECT_EQ(every.s.stride(), 1);
    for (size_t r = 0; r < G; ++r) EXPECT_EQ(every.s.region_share(r), 1.0);
    EXPECT_LT(s.factor_nonzeros(), every.s.factor_nonzeros()) << "w " << w;

    t = strided.rest;  // right hand up, left hand down, feet apart
    t[4] += Vec2(30, -90);
    t[3] += Vec2(-20, 50);
    t[5] += Vec2(-25, 0);
    strided.s.solve(t, 200);
    every.s.solve(t, 200);
    double moved = 0, apart = 0;
    for (size_t k = 0; k < s.nodes().size(); ++k) {
      moved = std::max(moved, (s.nodes()[k] - s.rest()[k]).norm());
      apart = std::max(apart, (s.nodes()[k] - every.s.nodes()[k]).norm());
    }
    EXPECT_GT(moved, 50);
    EXPECT_LT(apart, 0.05 * moved) << "w " << w << ": moved " << moved;
  }
}

// Bad rigs still load and pose, with a warning that says what is wrong: a handle off the figure,
// a figure thinner than a cell everywhere.
TEST(RigidGrid, AHandleOffTheFigureAndAFigureThinnerThanACellAreNamed) {
  Character square = polygon({{40, 40}, {160, 40}, {160, 160}, {40, 160}});
  RigidGrid s;
  std::string err;
  const std::vector<Vec2> rest{{100, 100}, {190, 10}};
  ASSERT_TRUE(s.prepare(square, grid_rig(8, 3), rest, SolverWeights{}, &err)) << err;
  ASSERT_EQ(square.warnings.size(), 1u);
  EXPECT_NE(square.warnings[0].find("handle 2 at (190.0, 10.0) is 42.4 units off the figure"), std::string::npos)
      << square.warnings[0];
  s.solve(std::vector<Vec2>{Vec2(100, 100), Vec2(220, 40)}, 50);
  for (const Vec2& q : s.nodes()) EXPECT_TRUE(q.allFinite());
  EXPECT_GT(s.point_at(Vec2(160, 40)).x(), 165);  // the near corner follows the handle

  Character thin = polygon({{0, 0}, {200, 0}, {200, 3}, {0, 3}});
  RigidGrid t;
  ASSERT_TRUE(t.prepare(thin, grid_rig(4, 3), std::vector<Vec2>{{2, 1.5}, {198, 1.5}}, SolverWeights{}, &err)) << err;
  EXPECT_EQ(t.grid_nodes(), 0u);
  ASSERT_EQ(thin.warnings.size(), 1u);
  EXPECT_NE(thin.warnings[0].find("no grid cell (4.00 units) fits inside the figure"), std::string::npos) << thin.warnings[0];
  t.solve(std::vector<Vec2>{Vec2(2, 1.5), Vec2(150, 100)}, 100);
  for (const Vec2& q : t.nodes()) EXPECT_TRUE(q.allFinite());
}

TEST(RigidGrid, StickFigureStrokesShareTheirJointAndKeepTheirLength) {
  Character c;
  for (const auto& [a, b] :
       std::vector<std::pair<Vec2, Vec2>>{{{100, 100}, {100, 0}}, {{100, 100}, {20, 180}}, {{100, 100}, {180, 180}}}) {
    SubShape s;
    s.id = "stroke" + std::to_string(c.shapes.size());
    for (int k = 0; k <= 10; ++k) s.points.push_back(a + (b - a) * (k / 10.0));
    s.contours.push_back({0, 11, false});
    s.stroke.enabled = true;
    c.shapes.push_back(s);
  }
  const std::vector<Vec2> rest{{100, 0}, {20, 180}, {180, 180}};
  RigidGrid s;
  std::string err;
  ASSERT_TRUE(s.prepare(c, grid_rig(10, 2), rest, SolverWeights{}, &err)) << err;
  EXPECT_EQ(s.grid_nodes(), 0u);
  std::vector<Vec2> t = rest;
  t[0] = Vec2(150, 20);  // the top stroke's end to the right
  s.solve(t, 100);
  std::vector<Points> out;
  for (const SubShape& sh : c.shapes) out.push_back(sh.points);
  s.shape_points(out);
  EXPECT_LT((out[0][0] - out[1][0]).norm(), 1e-9) << "the joint came apart";
  EXPECT_LT((out[0][0] - out[2][0]).norm(), 1e-9);
  EXPECT_GT((out[0][0] - Vec2(100, 100)).norm(), 1.0) << "the joint should follow";
  for (const Points& p : out) {
    double len = 0;
    for (size_t k = 1; k < p.size(); ++k) len += (p[k] - p[k - 1]).norm();
    EXPECT_NEAR(len, (p.back() - p.front()).norm(), 0.05 * len) << "a stroke bent";  // straight: rigid
  }
}

// The shipped stick figure (config/characters/stick.svg: polylines and a ring, no fill). A
// handle binds to the stroke it is drawn on, so a hand sent anywhere within reach is drawn
// there and the strokes it is not on stay; the head's handle, inside the ring, moves the ring.
// (Before, a handle off the mesh's joint triangles was extrapolated from the nearest one: the
// hand stayed 70-106 units from its target and the leg moved instead.)
TEST(RigidGrid, AStickFiguresHandleMovesTheStrokeItIsDrawnOn) {
  auto ch = load_character((test::characters_dir() / "stick.svg").string());
  ASSERT_TRUE(ch.ok()) << ch.error;
  Character c = *ch.value;
  Rig r = grid_rig(6, 3);
  const std::vector<Vec2> rest{{150, 58}, {150, 250}, {100, 212}, {200, 212}, {115, 352}, {185, 352}};
  RigidGrid s;
  std::string err;
  ASSERT_TRUE(s.prepare(c, r, rest, SolverWeights{}, &err)) << err;
  EXPECT_EQ(s.grid_nodes(), 0u);
  EXPECT_TRUE(c.warnings.empty()) << c.warnings[0];
  auto index = [&](const char* id) {
    for (size_t i = 0; i < c.shapes.size(); ++i)
      if (c.shapes[i].id == id) return i;
    ADD_FAILURE() << id;
    return size_t(0);
  };
  auto pose = [&](const std::vector<Vec2>& t) {
    s.reset_to_rest();
    s.initial_guess(t);
    double last = s.energy(t);
    for (int it = 0; it < 40; ++it) {
      s.solve(t, 1);
      const double e = s.energy(t);
      EXPECT_LE(e, last * (1 + 1e-9)) << "iteration " << it;
      last = e;
    }
    std::vector<Points> out;
    for (const SubShape& sh : c.shapes) out.push_back(sh.points);
    s.shape_points(out);
    return out;
  };
  const size_t arm = index("arm-right"), leg_l = index("leg-left"), leg_r = index("leg-right"), head = index("head");
  for (const Vec2& to : {Vec2(180, 60), Vec2(245, 110), Vec2(230, 250)}) {
    SCOPED_TRACE(to.transpose());
    std::vector<Vec2> t = rest;
    t[3] = to;
    const auto out = pose(t);
    EXPECT_LT((out[arm].back() - to).norm(), 2.0) << "the drawn hand";
    EXPECT_LT((s.handle_point(3) - out[arm].back()).norm(), 0.5) << "the handle is the drawn hand";
    for (size_t leg : {leg_l, leg_r})  // strokes it is not on stay
      for (size_t k = 0; k < out[leg].size(); ++k) EXPECT_LT((out[leg][k] - c.shapes[leg].points[k]).norm(), 3.0);
  }
  // The head's handle at the ring's centre carries the ring, whole.
  std::vector<Vec2> t = rest;
  t[0] = Vec2(172, 66);
  const auto out = pose(t);
  Vec2 centre = Vec2::Zero(), rest_centre = Vec2::Zero();
  for (size_t k = 0; k < out[head].size(); ++k) centre += out[head][k], rest_centre += c.shapes[head].points[k];
  centre /= double(out[head].size());
  rest_centre /= double(out[head].size());
  EXPECT_LT((centre - t[0]).norm(), 2.0) << centre.transpose();
  for (size_t k = 0; k < out[head].size(); ++k)  // a ring still: every point at its radius
    EXPECT_NEAR((out[head][k] - centre).norm(), (c.shapes[head].points[k] - rest_centre).norm(), 1.5);
}

TEST(RigidGrid, AGrabPullsItsPointAndReleasingItGivesThePoseWithoutIt) {
  Figure f, never;
  ASSERT_TRUE(f.ok && never.ok);
  const Vec2 grab_rest(130, 230), grab_to(100, 260);
  std::vector<Vec2> t = f.rest;
  t[4] = Vec2(260, 200);
  f.s.grab(grab_rest);
  ASSERT_TRUE(f.s.grabbing());
  std::vector<Vec2> tg = t;
  tg.push_back(grab_to);
  f.s.solve(tg, 30);
  // A soft pull against a stiff body whose neck and hips are held: most of the way.
  EXPECT_LT((f.s.point_at(grab_rest) - grab_to).norm(), 0.25 * (grab_rest - grab_to).norm());
  f.s.release();
  EXPECT_FALSE(f.s.grabbing());
  f.s.solve(t, 300);
  never.s.solve(t, 300);
  // (The local/global iterations approach the same pose slowly: within a few tenths of a unit on a
  // 400-unit figure after 300.)
  double sq = 0, worst = 0;
  for (size_t i = 0; i < f.s.nodes().size(); ++i) {
    const double d = (f.s.nodes()[i] - never.s.nodes()[i]).norm();
    sq += d * d;
    worst = std::max(worst, d);
  }
  EXPECT_LT(std::sqrt(sq / double(f.s.nodes().size())), 0.5);
  EXPECT_LT(worst, 3.0);
}

TEST(RigidGrid, DegenerateInputGivesNoNaN) {
  Figure f;
  ASSERT_TRUE(f.ok);
  auto finite = [&] {
    for (const Vec2& v : f.s.nodes())
      if (!v.allFinite()) return false;
    for (const Points& p : f.shapes())
      for (const Vec2& v : p)
        if (!v.allFinite()) return false;
    return true;
  };
  std::vector<Vec2> t(f.rest.size(), Vec2(150, 200));  // every handle to one point
  f.s.initial_guess(t);
  f.s.solve(t, 20);
  EXPECT_TRUE(finite());
  t.assign(f.rest.size(), Vec2(1e12, -1e12));
  f.s.initial_guess(t);
  f.s.solve(t, 5);
  EXPECT_TRUE(finite());
  t.assign(f.rest.size(), Vec2(NAN, INFINITY));
  f.s.initial_guess(t);
  f.s.solve(t, 5);
  EXPECT_TRUE(finite());
  // One target that is not a number holds its handle; the others still follow.
  f.s.reset_to_rest();
  t = f.rest;
  t[0] = Vec2(NAN, 60);
  t[4] = f.rest[4] + Vec2(30, -40);
  f.s.solve(t, 100);
  EXPECT_TRUE(finite());
  EXPECT_LT((f.s.handle_point(4) - t[4]).norm(), 8.0);
  // A speck, two handles at one rest point, a single stroke of two points.
  for (const std::vector<Vec2>& pts :
       std::vector<std::vector<Vec2>>{{{0, 0}, {1e-9, 0}, {0, 1e-9}}, {{0, 0}, {10, 0}, {10, 10}, {0, 10}}}) {
    Character c = polygon(pts);
    RigidGrid s;
    std::string err;
    const std::vector<Vec2> rest{pts[0], pts[0]};
    if (!s.prepare(c, default_rig(), rest, SolverWeights{}, &err)) continue;  // refused with a message is fine
    s.solve(std::vector<Vec2>{{5, 5}, {-5, 5}}, 10);
    for (const Vec2& v : s.nodes()) EXPECT_TRUE(v.allFinite());
  }
  Character line;
  SubShape st;
  st.points = {{0, 0}, {50, 0}};
  st.contours.push_back({0, 2, false});
  line.shapes.push_back(st);
  RigidGrid s;
  std::string err;
  ASSERT_TRUE(s.prepare(line, default_rig(), std::vector<Vec2>{{0, 0}}, SolverWeights{}, &err)) << err;
  s.solve(std::vector<Vec2>{{10, 10}}, 10);
  for (const Vec2& v : s.nodes()) EXPECT_TRUE(v.allFinite());
}

TEST(RigidGrid, HalfWidthAndNamedStiffnessAreLiveParameters) {
  auto ch = load_character((test::characters_dir() / "figure.svg").string());
  ASSERT_TRUE(ch.ok());
  Character c = *ch.value;
  Rig r = default_rig();
  r.stiffness.push_back({"arm", Vec2(230, 250), 40, 1.0, 0});
  r.stiffness.push_back({"", Vec2(150, 60), 30, 5.0, 0});  // unnamed: fixed
  const std::vector<Vec2> rest{{150, 60}, {150, 280}, {245, 250}};
  RigidGrid s;
  std::string err;
  ASSERT_TRUE(s.prepare(c, r, rest, SolverWeights{}, &err)) << err;
  const auto p = s.parameters();
  ASSERT_EQ(p.size(), 5u);
  EXPECT_EQ(p[0].name, "half_width");
  EXPECT_EQ(p[0].value, 3);
  EXPECT_EQ(p[4].name, "stiffness.arm");
  const size_t members3 = s.region(0).size();
  std::vector<double> v;
  for (const auto& q : p) v.push_back(q.value);
  v[0] = 6;
  ASSERT_TRUE(s.set_parameters(v, &err)) << err;
  EXPECT_EQ(s.half_width(), 6);
  EXPECT_GT(s.region(0).size(), members3);
  std::vector<Vec2> t = rest;
  t[2] = Vec2(280, 150);
  s.solve(t, 30);
  const Points soft = s.nodes();
  v[4] = 50;  // the arm region much stiffer
  ASSERT_TRUE(s.set_parameters(v, &err)) << err;
  s.solve(t, 30);
  double moved = 0;
  for (size_t i = 0; i < soft.size(); ++i) moved = std::max(moved, (s.nodes()[i] - soft[i]).norm());
  EXPECT_GT(moved, 0.5);
  v[0] = 0;
  EXPECT_FALSE(s.set_parameters(v, &err));
  EXPECT_NE(err.find("half_width"), std::string::npos);
}

// Riders: a body in the grid, an arm riding on it (no handle: it keeps the grid's turn at its
// shoulder), a hand riding on the arm and turned by its handle, a dot riding with the hand.
struct RiderFigure {
  Character c;
  RigidGrid s;
  Rig r = grid_rig(10, 2);
  std::vector<Vec2> rest{{50, 100}, {210, 30}};
  static SubShape box(const char* id, double x0, double y0, double x1, double y1) {
    SubShape s;
    s.id = id;
    s.points = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
    s.contours.push_back({0, 4, true});
    s.fill.enabled = true;
    return s;
  }
  RiderFigure() {
    c.shapes = {box("body", 0, 0, 100, 200), box("arm", 90, 20, 190, 40), box("hand", 185, 15, 215, 45), box("dot", 200, 28, 204, 32),
                box("hat", 120, 104, 140, 114), SubShape{}};
    c.shapes.back().id = "string";  // an open stroke from the body's side: the hat hangs beside it
    c.shapes.back().points = {{100, 100}, {160, 100}};
    c.shapes.back().contours.push_back({0, 2, false});
    c.shapes.back().stroke.enabled = true;
    c.width = 215;
    c.height = 200;
    r.path = "r.toml";
    r.handles = {{"body", rest[0]}, {"hand", rest[1]}};
    RigRider arm;
    arm.part = "arm", arm.on = "body", arm.at = Vec2(100, 30), arm.line = 7;
    RigRider hand;
    hand.part = "hand", hand.on = "arm", hand.at = Vec2(190, 30), hand.handle = "hand", hand.with = {"dot"}, hand.line = 12;
    RigRider hat;  // hinged beside a stroke, off the grid's figure: its point there is the stroke's nearest
    hat.part = "hat", hat.on = "string", hat.at = Vec2(130, 103), hat.line = 17;
    r.riders = {hand, arm, hat};  // (in any order: a rider is placed after what it hangs on)
  }
  std::vector<Points> shapes() const { return posed(c, s); }
};

TEST(RigidGrid, RidersTurnWholeAboutTheirHingesAndFollowWhatTheyHangOn) {
  RiderFigure f;
  std::string err;
  ASSERT_TRUE(f.s.prepare(f.c, f.r, f.rest, SolverWeights{}, &err)) << err;
  EXPECT_EQ(f.s.riders(), 3u);
  const std::vector<Points> rest = f.shapes();
  for (size_t k = 0; k < 5; ++k)
    for (size_t i = 0; i < 4; ++i) ASSERT_LT((rest[k][i] - f.c.shapes[k].points[i]).norm(), 1e-9) << k << " " << i;
  // The hand's handle turned a quarter about the wrist: the hand and its dot turn whole, the
  // arm and the body stay.
  auto turn = [](const Vec2& p) { return Vec2(Vec2(190, 30) + Vec2(-(p.y() - 30), p.x() - 190)); };
  std::vector<Vec2> t{f.rest[0], turn(f.rest[1])};
  f.s.solve(t, 4);
  std::vector<Points> now = f.shapes();
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_LT((now[0][i] - rest[0][i]).norm(), 1e-9) << "the body stays";
    EXPECT_LT((now[1][i] - rest[1][i]).norm(), 1e-9) << "the arm stays";
    EXPECT_LT((now[2][i] - turn(rest[2][i])).norm(), 1e-9) << "the hand turns about its wrist";
    EXPECT_LT((now[3][i] - turn(rest[3][i])).norm(), 1e-9) << "the dot with it";
  }
  EXPECT_LT((f.s.handle_point(1) - t[1]).norm(), 1e-9);
  // The body moved 20 to the right (its one handle): the arm goes with it, and the hand's
  // wrist with the arm; the hand turns toward its target, here moved with the body.
  t = {f.rest[0] + Vec2(20, 0), f.rest[1] + Vec2(20, 0)};
  f.s.solve(t, 30);
  now = f.shapes();
  for (size_t k = 0; k < 5; ++k)
    for (size_t i = 0; i < 4; ++i) EXPECT_LT((now[k][i] - rest[k][i] - Vec2(20, 0)).norm(), 1e-6) << k << " " << i;
  // A pen on the hand pulls it, with the arm it hangs on (the pen and the hand's handle, least
  // squares), and nothing of the grid's; let go, both settle back: the hand to its handle, the
  // arm (no handle of its own) as drawn.
  f.s.grab(Vec2(205, 40));
  EXPECT_TRUE(f.s.grabbing());
  t.push_back(Vec2(230, 110));
  auto grabbed = [&] {  // where the pen's point of the hand is
    const Points h = f.shapes()[2];
    const Vec2 a = h[1] - h[0];
    const double c = a.x() / a.norm(), s = a.y() / a.norm();
    const Vec2 d = Vec2(205, 40) - rest[2][0];
    return Vec2(h[0] + Vec2(c * d.x() - s * d.y(), s * d.x() + c * d.y()));
  };
  const double before = (grabbed() - t.back()).norm();
  f.s.solve(t, 4);
  now = f.shapes();
  EXPECT_LT((grabbed() - t.back()).norm(), 0.6 * before) << "the pen pulls the hand";
  EXPECT_GT((now[1][1] - rest[1][1] - Vec2(20, 0)).norm(), 5.0) << "and the arm with it";
  EXPECT_LT(rigid_fit_rms(rest[1], now[1]), 1e-9) << "each whole";
  EXPECT_LT(rigid_fit_rms(rest[2], now[2]), 1e-9);
  for (size_t i = 0; i < 4; ++i) EXPECT_LT((now[0][i] - rest[0][i] - Vec2(20, 0)).norm(), 1e-6) << "the body stays";
  f.s.release();
  t.pop_back();
  for (int k = 0; k < 60; ++k) f.s.solve(t, 4);  // (a second of frames)
  now = f.shapes();
  for (size_t k = 1; k < 5; ++k)
    for (size_t i = 0; i < 4; ++i) EXPECT_LT((now[k][i] - rest[k][i] - Vec2(20, 0)).norm(), 0.01) << "back as drawn " << k << " " << i;
  f.s.reset_to_rest();
  now = f.shapes();
  for (size_t i = 0; i < 4; ++i) EXPECT_LT((now[2][i] - rest[2][i]).norm(), 1e-9) << "at rest";
}

// A chain of two riders, each with its handle, swung far (the hand's target across the body,
// out of reach) and back: every rider back as drawn. (Kept from frame to frame, such a chain
// settled folded, each link pointing at its target.)
// Bones: a body and its arm drawn as one shape (an outline every 5 units), a spot on the arm
// and a button on the body; a [[bone]] along the arm, jointed at the body's side.
struct BoneFigure {
  Character c;
  RigidGrid s;
  Rig r = grid_rig(10, 2);
  std::vector<Vec2> rest{{50, 100}, {210, 30}};
  static SubShape outline(const char* id, const Points& corners) {
    SubShape s;
    s.id = id;
    for (size_t k = 0; k < corners.size(); ++k) {
      const Vec2 a = corners[k], b = corners[(k + 1) % corners.size()];
      const int n = std::max(1, int(std::lround((b - a).norm() / 5)));
      for (int i = 0; i < n; ++i) s.points.push_back(a + (double(i) / n) * (b - a));
    }
    s.contours.push_back({0, int(s.points.size()), true});
    s.fill.enabled = true;
    return s;
  }
  explicit BoneFigure(bool bone = true) {
    c.shapes = {outline("figure", {{0, 0}, {100, 0}, {100, 20}, {220, 20}, {220, 40}, {100, 40}, {100, 200}, {0, 200}}),
                outline("spot", {{180, 26}, {190, 26}, {190, 34}, {180, 34}}), outline("button", {{40, 90}, {50, 90}, {50, 100}, {40, 100}})};
    c.width = 220;
    c.height = 200;
    r.path = "r.toml";
    r.handles = {{"body", rest[0]}, {"hand", rest[1]}};
    if (bone) {
      RigBone b;
      b.handle = "hand", b.at = Vec2(100, 30), b.axis = {{215, 30}, {160, 30}, {100, 30}}, b.radius = {10, 10, 10}, b.line = 9;
      r.bones = {b};
    }
  }
  std::vector<Points> shapes() const { return posed(c, s); }
};

TEST(RigidGrid, BonesTurnALimbInsideOneShapeWholeAtItsJoint) {
  BoneFigure f;
  std::string err;
  ASSERT_TRUE(f.s.prepare(f.c, f.r, f.rest, SolverWeights{}, &err)) << err;
  EXPECT_EQ(f.s.riders(), 1u);
  const std::vector<Points> rest = f.shapes();
  for (size_t k = 0; k < rest.size(); ++k)
    for (size_t i = 0; i < rest[k].size(); ++i) ASSERT_LT((rest[k][i] - f.c.shapes[k].points[i]).norm(), 1e-9) << k << " " << i;
  // The hand's handle turned 60° up about the joint: the arm beyond its band (x >= 120) and its
  // spot turn whole, the band part of the way (each point as far from the joint as drawn), the
  // body and its button stay.
  const Vec2 joint(100, 30);
  const double a = -M_PI / 3;
  auto turn = [&](const Vec2& p) {
    const Vec2 d = p - joint;
    return Vec2(joint + Vec2(std::cos(a) * d.x() - std::sin(a) * d.y(), std::sin(a) * d.x() + std::cos(a) * d.y()));
  };
  std::vector<Vec2> t{f.rest[0], turn(f.rest[1])};
  f.s.solve(t, 4);
  std::vector<Points> now = f.shapes();
  int whole = 0, band = 0;
  for (size_t i = 0; i < rest[0].size(); ++i) {
    const Vec2 p = rest[0][i], q = now[0][i];
    if (p.x() <= 100 + 1e-9 && !(p.y() > 20 && p.y() < 40)) {
      EXPECT_LT((q - p).norm(), 1e-6) << "the body stays " << p.transpose();
    } else if (p.x() >= 120) {
      EXPECT_LT((q - turn(p)).norm(), 1e-6) << "the arm turns whole " << p.transpose();
      ++whole;
    } else {
      EXPECT_NEAR((q - joint).norm(), (p - joint).norm(), 1e-6) << "the band bends about the joint " << p.transpose();
      band += (q - p).norm() > 0.5 && (q - turn(p)).norm() > 0.5;
    }
  }
  EXPECT_GT(whole, 40);
  EXPECT_GT(band, 4) << "part of the way across the band";
  for (size_t i = 0; i < rest[1].size(); ++i) EXPECT_LT((now[1][i] - turn(rest[1][i])).norm(), 1e-6) << "the spot rides";
  for (size_t i = 0; i < rest[2].size(); ++i) EXPECT_LT((now[2][i] - rest[2][i]).norm(), 1e-6) << "the button stays";
  EXPECT_LT((f.s.handle_point(1) - t[1]).norm(), 1e-6);
  // The body moved 20 to the right, the hand's target with it: all of it goes along.
  t = {f.rest[0] + Vec2(20, 0), turn(f.rest[1]) + Vec2(20, 0)};
  f.s.solve(t, 30);
  now = f.shapes();
  for (size_t k = 0; k < now.size(); ++k)
    for (size_t i = 0; i < now[k].size(); ++i) {
      const Vec2 p = rest[k][i];
      const Vec2 want = (p.x() >= 120 ? turn(p) : p.x() <= 100 ? p : now[k][i] - Vec2(20, 0)) + Vec2(20, 0);
      EXPECT_LT((now[k][i] - want).norm(), 1e-5) << k << " " << i;
    }
  // A pen on the arm turns it (the pen and the hand's handle, least squares) and not the body;
  // let go, the arm settles back to its handle.
  t = {f.rest[0], f.rest[1]};
  f.s.solve(t, 4);
  f.s.grab(Vec2(180, 30));
  EXPECT_TRUE(f.s.grabbing());
  t.push_back(Vec2(150, 120));
  f.s.solve(t, 4);
  now = f.shapes();
  EXPECT_GT(now[1][0].y(), rest[1][0].y() + 20) << "the pen swings the arm down " << now[1][0].transpose();
  EXPECT_LT(rigid_fit_rms(rest[1], now[1]), 1e-9) << "its spot whole";
  for (size_t i = 0; i < rest[2].size(); ++i) EXPECT_LT((now[2][i] - rest[2][i]).norm(), 1e-6) << "the button stays";
  f.s.release();
  t.pop_back();
  f.s.solve(t, 4);
  now = f.shapes();
  for (size_t k = 0; k < now.size(); ++k)
    for (size_t i = 0; i < now[k].size(); ++i) EXPECT_LT((now[k][i] - rest[k][i]).norm(), 1e-6) << "back at rest " << k << " " << i;
  // Turned again with the body moved, then reset: every point, the band's too, at rest.
  f.s.solve(std::vector<Vec2>{f.rest[0] + Vec2(15, 5), turn(f.rest[1])}, 30);
  f.s.reset_to_rest();
  now = f.shapes();
  for (size_t k = 0; k < now.size(); ++k)
    for (size_t i = 0; i < now[k].size(); ++i) EXPECT_LT((now[k][i] - rest[k][i]).norm(), 1e-9) << "reset " << k << " " << i;
  // Without the bone the grid bends the arm toward the same target like a beam.
  BoneFigure g(false);
  ASSERT_TRUE(g.s.prepare(g.c, g.r, g.rest, SolverWeights{}, &err)) << err;
  g.s.solve(std::vector<Vec2>{g.rest[0], turn(g.rest[1])}, 30);
  const std::vector<Points> bent = g.shapes();
  Points arm_rest, arm_bent;
  for (size_t i = 0; i < rest[0].size(); ++i)
    if (rest[0][i].x() >= 120) arm_rest.push_back(rest[0][i]), arm_bent.push_back(bent[0][i]);
  EXPECT_GT(rigid_fit_rms(arm_rest, arm_bent), 1.0) << "(what a bone is for)";
}

TEST(RigidGrid, ARiderOnABonesLimbTurnsWithIt) {
  BoneFigure f;
  // a hand drawn as a part of its own at the arm's end, riding on the grid at its wrist
  f.c.shapes.push_back(BoneFigure::outline("hand", {{215, 22}, {235, 22}, {235, 38}, {215, 38}}));
  f.c.width = 235;
  RigRider hand;
  hand.part = "hand", hand.at = Vec2(215, 30), hand.line = 20;
  f.r.riders = {hand};
  std::string err;
  ASSERT_TRUE(f.s.prepare(f.c, f.r, f.rest, SolverWeights{}, &err)) << err;
  const std::vector<Points> rest = f.shapes();
  const Vec2 joint(100, 30);
  const double a = M_PI / 4;
  auto turn = [&](const Vec2& p) {
    const Vec2 d = p - joint;
    return Vec2(joint + Vec2(std::cos(a) * d.x() - std::sin(a) * d.y(), std::sin(a) * d.x() + std::cos(a) * d.y()));
  };
  f.s.solve(std::vector<Vec2>{f.rest[0], turn(f.rest[1])}, 4);
  const std::vector<Points> now = f.shapes();
  for (size_t i = 0; i < rest[3].size(); ++i) EXPECT_LT((now[3][i] - turn(rest[3][i])).norm(), 1e-6) << "the hand turns with the arm";
}

TEST(RigidGrid, RidersComeBackAsDrawnWhenTheirTargetsDo) {
  RiderFigure f;
  f.r.handles.push_back({"elbow", Vec2(150, 30)});
  f.rest.push_back(Vec2(150, 30));
  f.r.riders[1].handle = "elbow";
  std::string err;
  ASSERT_TRUE(f.s.prepare(f.c, f.r, f.rest, SolverWeights{}, &err)) << err;
  const std::vector<Points> rest = f.shapes();
  std::vector<Vec2> t = f.rest;
  double swung = 0;
  for (int k = 0; k <= 120; ++k) {  // out and back over two seconds
    const double a = 3.0 * std::sin(M_PI * k / 120.0);
    t[1] = Vec2(100, 30) + Vec2(110 * std::cos(a), 110 * std::sin(a)) * (1 + 0.5 * std::sin(M_PI * k / 120.0));
    t[2] = Vec2(100, 30) + Vec2(50 * std::cos(0.5 * a), 50 * std::sin(0.5 * a));
    f.s.solve(t, 4);
    swung = std::max(swung, (f.shapes()[2][0] - rest[2][0]).norm());
  }
  EXPECT_GT(swung, 100) << "the hand went far";
  const std::vector<Points> now = f.shapes();
  for (size_t k = 0; k < now.size(); ++k)
    for (size_t i = 0; i < now[k].size(); ++i) EXPECT_LT((now[k][i] - rest[k][i]).norm(), 1e-6) << k << " " << i;
}

TEST(RigidGrid, ARiderNamingNoShapeOrHangingOnItselfIsRefusedWithItsLine) {
  {
    RiderFigure f;
    f.r.riders[0].with = {"cuff"};
    std::string err;
    EXPECT_FALSE(f.s.prepare(f.c, f.r, f.rest, SolverWeights{}, &err));
    EXPECT_NE(err.find("r.toml:12: rider 'hand': 'cuff' (with) is not a sub-shape"), std::string::npos) << err;
  }
  {
    RiderFigure f;
    f.r.riders[1].on = "hand";  // the arm on the hand, the hand on the arm
    std::string err;
    EXPECT_FALSE(f.s.prepare(f.c, f.r, f.rest, SolverWeights{}, &err));
    EXPECT_NE(err.find("hangs, through riders, on itself"), std::string::npos) << err;
  }
  {
    RiderFigure f;
    f.r.riders[1].with = {"hand"};  // the hand rides on the arm and is a rider of its own
    std::string err;
    EXPECT_FALSE(f.s.prepare(f.c, f.r, f.rest, SolverWeights{}, &err));
    EXPECT_NE(err.find("rides on two riders"), std::string::npos) << err;
  }
}

}  // namespace
}  // namespace mar
