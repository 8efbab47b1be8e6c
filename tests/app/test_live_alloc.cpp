// After warm-up a live frame allocates nothing — with every simulated device feeding the
// decoders, mapping with filters, soft takeover and rotation, solving and rendering.
#include "alloc_counter.h"
#include "app/alloc_count.h"
#include "app/live.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace mar {
namespace {

// Loads a show headless at 120 Hz, runs 30 warm-up frames, then 570 frames that must not
// allocate (counted by the test's operator new and by the show itself).
std::unique_ptr<LiveShow> run_steady(const std::string& path) {
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  o.warmup = 30;
  auto s = LiveShow::load(path, o);
  EXPECT_TRUE(s.ok()) << s.error;
  if (!s.ok()) return nullptr;
  LiveShow& show = **s.value;
  for (int f = 0; f < 30; ++f) show.frame(int64_t(f * 1e9 / 120));
  const long before = test::allocation_count();
  for (int f = 30; f < 600; ++f) show.frame(int64_t(f * 1e9 / 120));
  EXPECT_EQ(test::allocation_count() - before, 0);
  EXPECT_EQ(show.allocations_after_warmup(), 0u);
  return std::move(*s.value);
}

TEST(LiveAlloc, SteadyFramesAllocateNothing) {
  set_allocation_counter(&heap_allocation_count);
  const std::string path = (test::source_dir() / "tests/data/shows/every_sim_looping.toml").string();
  const std::unique_ptr<LiveShow> s = run_steady(path);
  ASSERT_TRUE(s);
  LiveShow& show = *s;
  EXPECT_GT(show.mapping().stats().matched, 500u);  // the devices really drove it
}

// Pen grabs and releases (taking over a handle, and a new handle away from the handles:
// a rank-2 update of the factorisation) allocate nothing either, and re-factorise nothing.
TEST(LiveAlloc, PenGrabsAndReleasesAllocateNothing) {
  set_allocation_counter(&heap_allocation_count);
  const std::string path = (test::source_dir() / "tests/data/shows/pen_grab_looping.toml").string();
  const std::unique_ptr<LiveShow> s = run_steady(path);
  ASSERT_TRUE(s);
  LiveShow& show = *s;
  const auto j = nlohmann::json::parse(show.stats_json());
  EXPECT_GE(j["grabs"]["count"].get<int>(), 16);  // 4 strokes down and up per 1.2 s loop... at least 4 loops
  EXPECT_EQ(j["refactorizations"]["count"], 0);
}

// The attract loop starting (its mapping reset to the show's as loaded, its script rewound),
// playing and handing over allocates nothing either.
TEST(LiveAlloc, TheAttractLoopStartingAndHandingOverAllocatesNothing) {
  set_allocation_counter(&heap_allocation_count);
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  o.warmup = 30;
  auto s = LiveShow::load((test::source_dir() / "tests/data/shows/attract.toml").string(), o);
  ASSERT_TRUE(s.ok()) << s.error;
  LiveShow& show = **s.value;
  for (int f = 0; f < 30; ++f) show.frame(int64_t(f * 1e9 / 60));
  const long before = test::allocation_count();
  for (int f = 30; f < 660; ++f) show.frame(int64_t(f * 1e9 / 60));  // starts at 2.6 s, hands over at 9 s
  EXPECT_EQ(test::allocation_count() - before, 0);
  EXPECT_EQ(show.allocations_after_warmup(), 0u);
  ASSERT_NE(show.attract(), nullptr);
  EXPECT_EQ(show.attract()->starts(), 1u);
  EXPECT_EQ(show.attract()->handovers(), 1u);
}

}  // namespace
}  // namespace mar
