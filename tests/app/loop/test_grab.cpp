// The pen grab unit against a real puppet (the figure and its rig).
#include "app/loop/grab.h"
#include "test_util.h"

#include <gtest/gtest.h>

namespace mar {
namespace {

std::unique_ptr<Puppet> figure() {
  auto p = load_puppet("", (test::source_dir() / "config/rigs/figure.toml").string());
  EXPECT_TRUE(p.ok()) << p.error;
  return p.ok() ? std::move(*p.value) : nullptr;
}

TEST(Grab, NearAHandleThePenTakesItOverKeepingItsOffset) {
  auto p = figure();
  ASSERT_TRUE(p);
  Grab g;
  const Vec2 at = p->solver->handle_point(0);
  const Vec2 pen = at + Vec2(0.01 * p->diagonal, 0);
  g.set(true, pen, *p);
  EXPECT_TRUE(g.active());
  EXPECT_EQ(g.handle(), 0);
  EXPECT_FALSE(p->solver->grabbing());
  std::vector<Vec2> targets = p->rest_targets();
  Vec2 temporary = Vec2::Zero();
  const Vec2 moved = pen + Vec2(5, -3);
  EXPECT_EQ(g.apply(moved, targets, temporary), targets.size());
  EXPECT_LT((targets[0] - (at + Vec2(5, -3))).norm(), 1e-12);
  EXPECT_EQ(temporary, Vec2::Zero());
  g.set(false, moved, *p);
  EXPECT_FALSE(g.active());
  EXPECT_EQ(g.count(), 2);
}

TEST(Grab, ElsewhereTheNearestPointBecomesATemporaryHandle) {
  auto p = figure();
  ASSERT_TRUE(p);
  // The shape point farthest from every handle.
  Vec2 far = Vec2::Zero();
  double best = -1;
  for (const Points& s : p->shapes)
    for (const Vec2& v : s) {
      double d = INFINITY;
      for (size_t h = 0; h < p->solver->handle_count(); ++h) d = std::min(d, (p->solver->handle_point(h) - v).norm());
      if (d > best) {
        best = d;
        far = v;
      }
    }
  ASSERT_GT(best, 0.05 * p->diagonal);
  Grab g;
  g.set(true, far, *p);
  EXPECT_EQ(g.handle(), -1);
  EXPECT_TRUE(p->solver->grabbing());
  std::vector<Vec2> targets = p->rest_targets();
  const std::vector<Vec2> before = targets;
  Vec2 temporary = Vec2::Zero();
  EXPECT_EQ(g.apply(far + Vec2(10, 0), targets, temporary), targets.size() + 1);
  EXPECT_EQ(temporary, far + Vec2(10, 0));
  EXPECT_EQ(targets, before);  // (the handles' targets are left alone)
  // Re-factorising drops the solver's temporary handle; restore() adds it back.
  std::string err;
  ASSERT_TRUE(p->solver->set_parameters(std::vector<double>{2.0, 1.0, 100.0}, &err)) << err;
  g.restore(far, *p);
  EXPECT_TRUE(p->solver->grabbing());
  g.set(false, far, *p);
  EXPECT_FALSE(p->solver->grabbing());
}

}  // namespace
}  // namespace mar
