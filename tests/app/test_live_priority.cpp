// Performers with priorities in a running show (tests/data/shows/priority.toml): the guest's
// knob overrides the base player's fader on one handle axis, lets go, and the hand eases back
// to the fader with no jump; the HUD says who holds; the run repeats to the same run_hash; a
// priority on a target no value drives is refused with the file and line.
#include "alloc_counter.h"
#include "app/alloc_count.h"
#include "app/live.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <cmath>

namespace mar {
namespace {

std::string show_path() { return (test::source_dir() / "tests/data/shows/priority.toml").string(); }

TEST(LivePriority, AnOverrideLetsGoAndTheHandEasesBackToTheBaseWithNoJump) {
  set_allocation_counter(&heap_allocation_count);
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  o.warmup = 30;
  auto live = LiveShow::load(show_path(), o);
  ASSERT_TRUE(live.ok()) << live.error;
  LiveShow& s = **live.value;
  const int h = s.mapping().handle_index("left-hand");
  ASSERT_GE(h, 0);
  std::vector<double> x(300);
  long before = 0;
  for (int k = 0; k < 300; ++k) {
    if (k == 30) before = test::allocation_count();
    s.frame(int64_t(double(k) / 60 * 1e9));
    x[size_t(k)] = s.targets()[size_t(h)].x();
  }
  EXPECT_EQ(test::allocation_count() - before, 0) << "hand-overs allocate nothing";
  // the guest held it from 1.0 s (knob 0.9: the top of its range) to 1.5 s + hold 0.5 s
  const double base_at_1 = x[55], guest_top = x[118];
  EXPECT_GT(guest_top - base_at_1, 20) << "the override moved the hand";
  // after the hand-over (2.0 s + 0.6 s) the hand is where the base's fader is: rising slowly
  EXPECT_LT(std::fabs(x[170] - base_at_1), 0.3 * (guest_top - base_at_1)) << "back near the base";
  EXPECT_GT(x[299], x[170]) << "and following the base's fader again";
  // no jump: the largest frame-to-frame step after the override stopped moving
  double largest = 0;
  for (size_t k = 95; k < x.size(); ++k) largest = std::max(largest, std::fabs(x[k] - x[k - 1]));
  const double drop = guest_top - x[170];
  // (eased in-out over 36 frames: at most twice the mean step, plus one 7-bit step of the base's
  // fader, which moves meanwhile: 1.7 units)
  EXPECT_LE(largest, 2.0 * drop / (0.6 * 60) + 2.0) << "eased over the 0.6 s hand-over, not a jump of " << drop;
  EXPECT_EQ(s.allocations_after_warmup(), 0u);

  // the same take again: the same hand-overs, the same run_hash
  auto again = LiveShow::load(show_path(), o);
  ASSERT_TRUE(again.ok()) << again.error;
  for (int k = 0; k < 300; ++k) (*again.value)->frame(int64_t(double(k) / 60 * 1e9));
  EXPECT_EQ((*again.value)->run_hash(), s.run_hash());
}

TEST(LivePriority, APriorityOnAPoseOrAPenGrabIsRefusedWithFileAndLine) {
  const std::string text = "[show]\nrig = \"" + (test::source_dir() / "config/rigs/figure.toml").string() +
                           "\"\n[[device]]\nname = \"k\"\nsim = \"nanokontrol2\"\n[[binding]]\ndevice = \"k\"\ncontrol = \"cc 32\"\n"
                           "target = \"pose.rest\"\npriority = 3\n";
  const std::string path = test::write_temp("priority-on-pose.toml", text);
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  auto live = LiveShow::load(path, o);
  ASSERT_FALSE(live.ok());
  EXPECT_NE(live.error.find(path + ":10:"), std::string::npos) << live.error;
  EXPECT_NE(live.error.find("priority goes with a target a value drives"), std::string::npos) << live.error;
}

}  // namespace
}  // namespace mar
