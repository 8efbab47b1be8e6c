// Limbs from a silhouette (rig/silhouette.h): a creature drawn as one region gets a limb per
// leg, its tail and its head, each jointed where it leaves the body; a round blob gets none.
#include "character/svg_loader.h"
#include "geom/skeleton.h"
#include "rig/silhouette.h"

#include <gtest/gtest.h>

#include <numeric>

namespace mar {
namespace {

Character svg(const std::string& body) {
  auto r = load_svg_string("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"300\" height=\"220\">" + body + "</svg>", "t.svg");
  EXPECT_TRUE(r.ok()) << r.error;
  return r.ok() ? *r.value : Character{};
}

std::vector<int> all(const Character& ch) {
  std::vector<int> k(ch.shapes.size());
  std::iota(k.begin(), k.end(), 0);
  return k;
}

// A dog from the side, body, legs, neck, head and tail as pieces of one silhouette.
const char* kDog = R"(<ellipse cx="150" cy="100" rx="80" ry="35"/>
  <rect x="85" y="110" width="16" height="90"/><rect x="115" y="115" width="16" height="85"/>
  <rect x="170" y="115" width="16" height="85"/><rect x="200" y="110" width="16" height="90"/>
  <path d="M215 85 L245 45 L258 55 L230 95 z"/><circle cx="258" cy="38" r="24"/>
  <path d="M75 90 L20 50 L28 42 L80 80 z"/>)";

const SilhouetteLimb* nearest(const Silhouette& s, const Vec2& p) {
  const SilhouetteLimb* best = nullptr;
  for (const SilhouetteLimb& l : s.limbs)
    if (!best || (l.tip - p).norm() < (best->tip - p).norm()) best = &l;
  return best;
}

TEST(Silhouette, ACreatureInOneRegionHasALimbPerLegItsTailAndItsHead) {
  const Character ch = svg(kDog);
  const Silhouette s = silhouette_of(ch, all(ch));
  ASSERT_EQ(s.error, "");
  EXPECT_EQ(s.limbs.size(), 6u);
  EXPECT_NEAR(s.core.y(), 100, 20) << "the core is in the body";
  for (const Vec2& foot : {Vec2(93, 195), Vec2(123, 195), Vec2(178, 195), Vec2(208, 195)}) {
    const SilhouetteLimb* l = nearest(s, foot);
    ASSERT_TRUE(l);
    EXPECT_LT((l->tip - foot).norm(), 12) << foot.transpose();
    // jointed at the top of the leg, where it leaves the body's outline (y 120-135 there)
    EXPECT_NEAR(l->joint.x(), foot.x(), 10) << foot.transpose();
    EXPECT_GT(l->joint.y(), 100) << foot.transpose();
    EXPECT_LT(l->joint.y(), 150) << foot.transpose();
    EXPECT_NEAR(l->width, 16, 5);
  }
  const SilhouetteLimb* head = nearest(s, Vec2(258, 38));
  ASSERT_TRUE(head);
  EXPECT_LT((head->tip - Vec2(258, 38)).norm(), 25);
  EXPECT_GT(head->end_radius, 15) << "a head is wide at its end";
  const SilhouetteLimb* tail = nearest(s, Vec2(22, 46));
  ASSERT_TRUE(tail);
  EXPECT_LT((tail->tip - Vec2(22, 46)).norm(), 15);
}

TEST(Silhouette, ARoundBlobHasNoLimbsAndABentArmItsElbow) {
  const Character blob = svg(R"(<circle cx="150" cy="110" r="90"/>)");
  const Silhouette b = silhouette_of(blob, all(blob));
  ASSERT_EQ(b.error, "");
  EXPECT_EQ(b.limbs.size(), 0u);
  EXPECT_NEAR(b.core.x(), 150, 8);
  EXPECT_NEAR(b.core_radius, 90, 6);
  // a body and one arm bent at a right angle at (100, 60)
  const Character arm = svg(R"(<circle cx="200" cy="150" r="55"/><path d="M160 120 L100 68 L100 10 L116 10 L116 60 L170 108 z"/>)");
  const Silhouette a = silhouette_of(arm, all(arm));
  ASSERT_EQ(a.error, "");
  ASSERT_EQ(a.limbs.size(), 1u);
  ASSERT_EQ(a.limbs[0].bends.size(), 1u);
  EXPECT_LT((a.limbs[0].bends[0] - Vec2(108, 64)).norm(), 14) << a.limbs[0].bends[0].transpose();
}

TEST(Skeleton, ARectanglesAxisRunsAlongItsMiddle) {
  const Points rect{{0, 0}, {100, 0}, {100, 20}, {0, 20}};
  const SkeletonGraph g = straight_skeleton(rect);
  ASSERT_EQ(g.error, "");
  ASSERT_EQ(g.edges.size(), 1u);
  for (size_t k = 0; k < g.nodes.size(); ++k) {
    EXPECT_NEAR(g.nodes[k].y(), 10, 1e-9);
    EXPECT_NEAR(g.radius[k], 10, 1e-9);
  }
  const Points bow{{0, 0}, {10, 10}, {10, 0}, {0, 10}};
  EXPECT_EQ(straight_skeleton(bow).error, "an outline that crosses itself");
}

}  // namespace
}  // namespace mar
