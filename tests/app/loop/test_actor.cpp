// An actor on its own (app/loop/actor.h): its ranges in a mapping shared with another actor,
// its solve from its slice of the targets, its entrance, and the layers it needs.
#include "app/loop/actor.h"
#include "app/show.h"
#include "test_util.h"

#include <gtest/gtest.h>

namespace mar {
namespace {

std::unique_ptr<Puppet> puppet(const char* rig) {
  auto r = load_puppet("", (test::source_dir() / "config/rigs" / (std::string(rig) + ".toml")).string());
  EXPECT_TRUE(r.ok()) << r.error;
  return r.ok() ? std::move(*r.value) : nullptr;
}

// Two actors in one mapping: the second's handles and settings start where the first's end;
// moving its targets moves its shapes only.
TEST(Actor, TwoActorsShareAMappingEachInItsOwnRange) {
  auto a = puppet("figure"), b = puppet("robot");
  ASSERT_TRUE(a && b);
  const size_t na = a->rig.handles.size(), nb = b->rig.handles.size();
  const size_t sa = a->rig.swaps.size(), ta = a->rig.triggers.size();
  ShowConfig sh;
  Mapping m;
  std::vector<std::string> names(na + nb, "h");
  std::vector<Vec2> rest = a->rest_targets();
  for (const Vec2& v : b->rest_targets()) rest.push_back(v);
  m.set_handles(names, rest);
  m.add_setting({8, 2, 200, true});  // (the show's iterations)
  Actor first, second;
  ASSERT_EQ(first.prepare(std::move(a), sh, m, 0, 0, 0, 0), "");
  const size_t after_first = m.setting_count();
  ASSERT_EQ(second.prepare(std::move(b), sh, m, na, sa, ta, 1), "");
  EXPECT_EQ(second.ranges().handle0, na);
  EXPECT_EQ(second.ranges().handles, nb);
  EXPECT_EQ(second.ranges().who, 1);
  EXPECT_EQ(size_t(second.ranges().solver0), after_first) << "its solver's parameters follow the first actor's settings";
  EXPECT_EQ(second.ranges().swap0, sa);
  std::vector<Vec2> targets = rest;
  std::span<Vec2> mine = std::span<Vec2>(targets).subspan(na, nb);
  for (Vec2& t : mine) t += Vec2(0, -40);  // the robot up, whole
  for (int k = 0; k < 10; ++k) {
    first.solve(std::span<Vec2>(targets).subspan(0, na), 12);
    second.solve(mine, 12);
  }
  EXPECT_LT(first.reconstruct(), 1e-6) << "the figure at rest keeps its shape";
  second.reconstruct();
  double moved = 0;
  const Puppet& r = second.puppet();
  for (size_t k = 0; k < r.shapes.size(); ++k)
    for (size_t i = 0; i < r.shapes[k].size(); ++i) moved = std::max(moved, (r.shapes[k][i] - r.character.shapes[k].points[i]).norm());
  EXPECT_GT(moved, 20.0);
  for (size_t k = 0; k < first.puppet().shapes.size(); ++k)
    for (size_t i = 0; i < first.puppet().shapes[k].size(); ++i)
      EXPECT_LT((first.puppet().shapes[k][i] - first.puppet().character.shapes[k].points[i]).norm(), 1e-6);
}

// Entering: presence goes 0 -> 1 over its seconds; a fade shows in the opacity, a slide in the
// view (from `offstage`, back to where it stands); a cut is at once.
TEST(Actor, AnEntranceMovesItsPresenceOverItsSeconds) {
  auto p = puppet("figure");
  ASSERT_TRUE(p);
  ShowConfig sh;
  Mapping m;
  m.set_handles(std::vector<std::string>(p->rig.handles.size(), "h"), p->rest_targets());
  Actor a;
  a.shown = false;
  a.entrance_s = 0.5;
  ASSERT_EQ(a.prepare(std::move(p), sh, m, 0, 0, 0, 0), "");
  EXPECT_EQ(a.presence(), 0.0);
  a.stage_step(true, 0.25);
  EXPECT_NEAR(a.presence(), 0.5, 1e-12);
  EXPECT_NEAR(a.opacity(), 0.5f, 1e-6f);
  EXPECT_TRUE(a.drawn_view().e == a.view.e) << "a fade does not move it";
  a.fade = false;
  a.offstage = Vec2(-300, 0);
  EXPECT_NEAR(a.drawn_view().e - a.view.e, -150.0, 1e-9) << "half way along its slide";
  EXPECT_EQ(a.opacity(), 1.0f);
  a.stage_step(true, 1.0);
  EXPECT_EQ(a.presence(), 1.0);
  EXPECT_EQ(a.drawn_view().e, a.view.e);
  a.entrance_s = 0;  // a cut
  a.stage_step(false, 1.0 / 60);
  EXPECT_EQ(a.presence(), 0.0);
  EXPECT_EQ(a.layer_depth(), 0u) << "the figure has no layers, and a slide needs none";
  a.fade = true;
  EXPECT_EQ(a.layer_depth(), 1u);
}

}  // namespace
}  // namespace mar
