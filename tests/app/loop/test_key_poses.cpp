// The poses stage on its own (app/loop/key_poses.h), on the figure's rig and its two keys
// (wave, kick): morph and blend settings make the key weights; the base pose at a key moves
// the handles by where that key has them; a recall eases to a key and a knob turned after it
// adds on top; a 0-second recall is a jump; only settings something drives are kept.
#include "app/keys.h"
#include "app/loop/key_poses.h"
#include "app/show.h"
#include "solve/solver.h"
#include "test_util.h"

#include <gtest/gtest.h>

namespace mar {
namespace {

constexpr double kDt = 1.0 / 60;

struct Figure {
  std::unique_ptr<Puppet> p;
  Mapping m;
  KeyPoseStage keys;
  std::vector<double> values;
  std::vector<Points> solved;  ///< the keys as frame vertices
  Figure() {
    auto r = load_puppet("", (test::source_dir() / "config/rigs/figure.toml").string());
    EXPECT_TRUE(r.ok()) << r.error;
    p = std::move(*r.value);
    keys.add_settings(m, int(p->rig.keys.size()));
  }
  // Keeps the settings bindings drive (by index into keys.settings()), prepares, sizes values.
  void drive(std::initializer_list<size_t> driven, bool recall = false) {
    ShowConfig sh;
    for (size_t k : driven) {
      Binding b;
      b.target = TargetKind::Setting;
      b.index = keys.settings()[k].setting;
      sh.bindings.push_back(b);
    }
    if (recall) {
      Binding b;
      b.target = TargetKind::Recall;
      sh.bindings.push_back(b);
    }
    ASSERT_TRUE(keys.keep_driven(sh));
    auto k = solve_keys(*p);
    ASSERT_TRUE(k.ok()) << k.error;
    solved = *k.value;
    ASSERT_EQ(keys.prepare(*p, solved), "");
    values.assign(keys.settings().size(), 0.0);
  }
  size_t find(int from, int to) const {
    for (size_t i = 0; i < keys.settings().size(); ++i)
      if (keys.settings()[i].from == from && keys.settings()[i].to == to) return i;
    ADD_FAILURE() << "no setting " << from << " -> " << to;
    return 0;
  }
};

TEST(KeyPoses, MorphsAndBlendsMakeTheKeyWeights) {
  Figure f;
  ASSERT_EQ(f.p->rig.keys.size(), 2u);
  const size_t rest_wave = f.find(-1, 0), wave_kick = f.find(0, 1), blend_kick = f.find(-2, 1);
  f.drive({rest_wave, wave_kick, blend_kick});
  ASSERT_EQ(f.keys.settings().size(), 3u) << "the undriven morphs and blends are dropped";
  // settings() keeps their order: rest->wave, wave->kick, blend.kick
  f.values = {0.5, 0, 0.25};
  f.keys.step(kDt, f.values, nullptr);
  // rest->wave at 0.5: wave 0.5; wave->kick at 0 puts 1 on wave; blend.kick adds 0.25
  EXPECT_NEAR(f.keys.weights()[0], 1.5, 1e-12);
  EXPECT_NEAR(f.keys.weights()[1], 0.25, 1e-12);
  Figure none;
  ShowConfig empty;
  EXPECT_FALSE(none.keys.keep_driven(empty)) << "nothing drives a key: no poses stage";
}

TEST(KeyPoses, AtAKeyTheHandlesMoveToWhereTheKeyHasThem) {
  Figure f;
  f.drive({f.find(-1, 0)});
  f.values = {1.0};  // rest -> wave, all the way
  f.keys.step(kDt, f.values, nullptr);
  std::vector<Vec2> targets(f.p->rig.handles.size());
  for (size_t h = 0; h < targets.size(); ++h) targets[h] = f.p->rig.handles[h].rest;
  f.keys.offset(targets);
  const int right = f.p->rig.find_handle("right-hand"), chest = f.p->rig.find_handle("chest");
  ASSERT_GE(right, 0);
  ASSERT_GE(chest, 0);
  const double height = f.p->character.height;
  // where the solved wave has the right hand (its stated target, as far as the arm reaches)
  const Vec2 waved = eval_param(f.p->feature_frame()->bindings()[size_t(right)], f.solved[0]);
  EXPECT_GT((waved - f.p->rig.handles[size_t(right)].rest).norm(), 0.2 * height) << "the wave lifts the hand";
  EXPECT_LT((targets[size_t(right)] - waved).norm(), 1e-6 * height);
  EXPECT_LT((targets[size_t(chest)] - f.p->rig.handles[size_t(chest)].rest).norm(), 0.02 * height) << "the chest stays";
}

TEST(KeyPoses, ARecallEasesToItsKeyAndAKnobTurnedAfterAddsOnTop) {
  Figure f;
  const size_t blend_kick = f.find(-2, 1);
  f.drive({blend_kick}, true);
  Recall to_wave{0, 0.5, Ease::InOut};
  EXPECT_FALSE(f.keys.step(kDt, f.values, &to_wave)) << "an eased recall is not a jump";
  double last = f.keys.weights()[0];
  for (int k = 1; k < 45; ++k) {
    f.keys.step(kDt, f.values, nullptr);
    EXPECT_GE(f.keys.weights()[0], last - 1e-12);
    if (k == 15) {
      EXPECT_GT(f.keys.weights()[0], 0.2);
      EXPECT_LT(f.keys.weights()[0], 0.8) << "half-way through the recall, half-way to the key";
    }
    last = f.keys.weights()[0];
  }
  EXPECT_NEAR(f.keys.weights()[0], 1.0, 1e-12);
  f.values[0] = 0.5;  // blend.kick turned up afterwards
  f.keys.step(kDt, f.values, nullptr);
  EXPECT_NEAR(f.keys.weights()[0], 1.0, 1e-12);
  EXPECT_NEAR(f.keys.weights()[1], 0.5, 1e-12);
  Recall jump{-1, 0, Ease::InOut};
  EXPECT_TRUE(f.keys.step(kDt, f.values, &jump)) << "a 0-second recall jumps (the chains start again)";
  EXPECT_NEAR(f.keys.weights()[0], 0.0, 1e-12);
  EXPECT_NEAR(f.keys.weights()[1], 0.0, 1e-12) << "rest: the knob's weight is offset too";
}

}  // namespace
}  // namespace mar
