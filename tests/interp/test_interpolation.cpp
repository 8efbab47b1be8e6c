// Structure-preserving interpolation of key poses (interp/interpolation.h, seed 000 §5).
#include "character/load.h"
#include "geom/polygon.h"
#include "interp/interpolation.h"
#include "alloc_counter.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <cmath>

namespace mar {
namespace {

struct KeyCase {
  Character ch;
  FeatureFrame f;
  KeyInterpolator interp;
  double size = 1;
  explicit KeyCase(const char* file = "figure.svg") {
    auto c = load_character((test::characters_dir() / file).string());
    EXPECT_TRUE(c.ok());
    ch = *c.value;
    refine_for_frame(ch, default_frame_options());
    f = build_feature_frame(ch, default_frame_options());
    size = f.diagonal;
    std::string err;
    EXPECT_TRUE(interp.prepare(f, &err)) << err;
  }
  Points moved(double deg, const Vec2& shift) const {  // the rest frame turned about its centre
    const Vec2 c = 0.5 * (ch.bounds().lo + ch.bounds().hi);
    const double a = deg * M_PI / 180;
    Points out;
    for (const Vec2& p : f.rest) {
      const Vec2 d = p - c;
      out.push_back(c + shift + Vec2(std::cos(a) * d.x() - std::sin(a) * d.y(), std::sin(a) * d.x() + std::cos(a) * d.y()));
    }
    return out;
  }
  Points warped(double k) const {  // a smooth non-rigid bend
    Points out;
    for (const Vec2& p : f.rest) out.push_back(p + Vec2(k * 40 * std::sin(p.y() / 90), k * 25 * std::cos(p.x() / 70)));
    return out;
  }
};

double max_diff(std::span<const Vec2> a, std::span<const Vec2> b) {
  double m = 0;
  for (size_t i = 0; i < a.size(); ++i) m = std::max(m, (a[i] - b[i]).norm());
  return m;
}

double polygon_area(const Points& p) {
  double a = 0;
  for (size_t i = 0, j = p.size() - 1; i < p.size(); j = i++) a += (p[j].x() * p[i].y() - p[i].x() * p[j].y());
  return 0.5 * std::abs(a);
}

TEST(frame_triangle_set, EveryVertexWithALineIsInATriangle) {
  KeyCase s;
  const auto tris = frame_triangle_set(s.f);
  EXPECT_GT(tris.size(), s.f.rest.size() / 2);
  std::vector<char> in(s.f.rest.size(), 0), lined(s.f.rest.size(), 0);
  for (const auto& t : tris)
    for (int v : t) in[size_t(v)] = 1;
  for (const FrameLine& l : s.f.lines)
    if (l.kind != FrameLine::Joint && l.kind != FrameLine::Spring && l.a != l.b) lined[size_t(l.a)] = lined[size_t(l.b)] = 1;
  for (size_t i = 0; i < in.size(); ++i) {
    EXPECT_TRUE(!lined[i] || in[i]) << "frame vertex " << i;
  }
}

TEST(KeyInterpolator, TheKeysComeBackAtZeroAndOne) {
  KeyCase s;
  const Points a = s.warped(1), b = s.warped(-0.7);
  const int ka = s.interp.add_key(a), kb = s.interp.add_key(b);
  Points v(s.f.rest.size());
  s.interp.morph(ka, kb, 0, v);
  EXPECT_LT(max_diff(v, a), 1e-9 * s.size);
  s.interp.morph(ka, kb, 1, v);
  EXPECT_LT(max_diff(v, b), 1e-9 * s.size);
  s.interp.morph(-1, kb, 0, v);  // rest
  EXPECT_LT(max_diff(v, s.f.rest), 1e-9 * s.size);
}

TEST(KeyInterpolator, KeysThatDifferByARigidMotionGiveRigidInBetweens) {
  KeyCase s;
  const int k = s.interp.add_key(s.moved(70, Vec2(30, -20)));
  Points v(s.f.rest.size());
  for (double t : {0.25, 0.5, 0.8}) {
    s.interp.morph(-1, k, t, v);
    EXPECT_LT(rigid_fit_rms(s.f.rest, v), 1e-9 * s.size) << t;
    const RigidMotion m = rigid_fit(s.f.rest, v);
    EXPECT_NEAR(std::atan2(m.s, m.c), t * 70 * M_PI / 180, 1e-9) << t;
  }
}

TEST(KeyInterpolator, AHalfTurnKeepsItsAreaWhereLinearBlendingLosesIt) {
  KeyCase s;
  const int k = s.interp.add_key(s.moved(180, Vec2::Zero()));
  Points v(s.f.rest.size());
  std::vector<Points> shapes;
  for (const SubShape& sh : s.ch.shapes) shapes.push_back(sh.points);
  auto worst_area_change = [&] {
    double worst = 0;
    for (size_t i = 0; i < shapes.size(); ++i) {
      if (!s.ch.shapes[i].closed() || s.ch.shapes[i].points.size() < 3) continue;
      const double a0 = polygon_area(s.ch.shapes[i].points);
      if (a0 < 1e-3 * s.size * s.size) continue;
      worst = std::max(worst, std::abs(polygon_area(shapes[i]) - a0) / a0);
    }
    return worst;
  };
  for (double t : {0.25, 0.5, 0.75}) {
    s.interp.morph(-1, k, t, v);
    reconstruct_shapes(s.f, v, shapes);
    EXPECT_LT(worst_area_change(), 0.01) << "ARAP at t = " << t;
  }
  s.interp.linear_morph(-1, k, 0.5, v);
  reconstruct_shapes(s.f, v, shapes);
  EXPECT_GT(worst_area_change(), 0.5) << "linear blending at t = 0.5";
}

TEST(KeyInterpolator, AChainOfKeysTurnsTheWayItWasKeyed) {
  KeyCase s;
  const int k1 = s.interp.add_key(s.moved(120, Vec2::Zero()));
  const int k2 = s.interp.add_key(s.moved(240, Vec2::Zero()));
  const int k3 = s.interp.add_key(s.moved(360, Vec2::Zero()));
  for (size_t t = 0; t < s.interp.triangles(); ++t) {
    ASSERT_NEAR(s.interp.angle(size_t(k1), t), 2 * M_PI / 3, 1e-6) << t;
    ASSERT_NEAR(s.interp.angle(size_t(k2), t), 4 * M_PI / 3, 1e-6) << t;
    ASSERT_NEAR(s.interp.angle(size_t(k3), t), 2 * M_PI, 1e-6) << t;
  }
  Points v(s.f.rest.size());
  s.interp.morph(k2, k3, 0.5, v);  // 300° (−60°), not back through 120°; rigid
  const RigidMotion m = rigid_fit(s.f.rest, v);
  EXPECT_NEAR(std::atan2(m.s, m.c), -M_PI / 3, 1e-6);
  EXPECT_LT(rigid_fit_rms(s.f.rest, v), 1e-6 * s.size);
}

TEST(KeyInterpolator, BlendsAreAdditiveOverRest) {
  KeyCase s;
  const Points a = s.warped(1), b = s.moved(30, Vec2(10, 0));
  s.interp.add_key(a);
  s.interp.add_key(b);
  Points v(s.f.rest.size());
  s.interp.blend(std::vector<double>{0, 1}, v);
  EXPECT_LT(max_diff(v, b), 1e-9 * s.size);
  s.interp.blend(std::vector<double>{1, 0}, v);
  EXPECT_LT(max_diff(v, a), 1e-9 * s.size);
  s.interp.blend(std::vector<double>{0, 0}, v);
  EXPECT_LT(max_diff(v, s.f.rest), 1e-9 * s.size);
  s.interp.blend(std::vector<double>{0, 0.5}, v);  // half of key b: half its turn
  const RigidMotion m = rigid_fit(s.f.rest, v);
  EXPECT_NEAR(std::atan2(m.s, m.c), 15 * M_PI / 180, 1e-6);
}

TEST(KeyInterpolator, AnInBetweenAllocatesNothing) {
  KeyCase s;
  const int a = s.interp.add_key(s.warped(1)), b = s.interp.add_key(s.moved(90, Vec2(5, 5)));
  Points v(s.f.rest.size());
  std::vector<Points> shapes;
  for (const SubShape& sh : s.ch.shapes) shapes.push_back(sh.points);
  std::vector<double> w{0.3, 0.4};
  s.interp.morph(a, b, 0.1, v);
  const long before = test::allocation_count();
  for (int k = 0; k < 100; ++k) {
    s.interp.morph(a, b, k / 99.0, v);
    s.interp.blend(w, v);
    reconstruct_shapes(s.f, v, shapes);
  }
  EXPECT_EQ(test::allocation_count() - before, 0);
}

}  // namespace
}  // namespace mar
