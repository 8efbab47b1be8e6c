// The brush of seed 004 in a show ([[brush]], app/loop/brush.h): a simulated pen touches the
// figure's cheek and drags it out; the outline's points move by the Gaussian of their distance
// along the outline, the rest of the figure keeps its place, nothing is allocated, a spring
// brings the cheek back and a held stroke stays; the same run twice gives the same run_hash.
#include "alloc_counter.h"
#include "app/alloc_count.h"
#include "app/live.h"
#include "live_util.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace mar {
namespace {

using test::height;
using test::off_rest;
using test::shape_of;

const Vec2 kCheek(106.5, 96.0);  // on the face's outline (an ellipse [106, 40] - [194, 136])
const Vec2 kDrag(-24.0, 6.0);    // out and a little down

std::string normalised(const Vec2& canvas_px) {
  char s[64];
  std::snprintf(s, sizeof s, "%.6f,%.6f", canvas_px.x() / 400, canvas_px.y() / 560);
  return s;
}

std::unique_ptr<LiveShow> load(const std::string& path, int warmup = 0) {
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  o.warmup = warmup;
  auto s = LiveShow::load(path, o);
  EXPECT_TRUE(s.ok()) << s.error;
  return s.ok() ? std::move(*s.value) : nullptr;
}

// A show of the figure with a pen brushing; `script` is the pen's, in canvas pixels mapped by
// the probe's view (the pen covers the canvas).
std::string brush_show(const std::string& name, const std::string& release, const std::string& script) {
  const std::string rig = (test::source_dir() / "config/rigs/figure.toml").string();
  return test::write_temp(name, "[show]\nrig = \"" + rig + "\"\nrate = 60\niterations = 12\nmin_iterations = 12\n"
                                "[display]\nwidth = 400\nheight = 560\n"
                                "[[device]]\nname = \"pen\"\nsim = \"pen_tablet\"\nscript = \"\"\"\n" + script + "\"\"\"\n"
                                "[[brush]]\ndevice = \"pen\"\nradius = [10, 40]\narea = \"canvas\"\n" + release + "\n");
}

struct Brushing {
  std::unique_ptr<LiveShow> s;
  Affine2 view;
};

// Loads a probe for the view, then the show whose pen touches the cheek at 0.2 s and drags it
// by kDrag over 0.5 s (pressure `pressure`), lifting at the end.
Brushing brushing(const std::string& name, const std::string& release, double pressure, int warmup = 0) {
  auto probe = load(brush_show(name, release, "0.1 leave\n"));
  if (!probe) return {};
  const Affine2 view = probe->actors()[0]->view;
  const Vec2 a = view.apply(kCheek), b = view.apply(kCheek + kDrag);
  char p[32];
  std::snprintf(p, sizeof p, "%.3f", pressure);
  const std::string script = "0.1 hover " + normalised(a) + "\n0.2 stroke " + normalised(a) + " " + normalised(b) +
                             " over 0.5 pressure " + p + "\n";
  return {load(brush_show(name, release, script), warmup), view};
}

TEST(Brush, TheOutlineMovesByTheGaussianOfItsDistanceAndTheRestStays) {
  set_allocation_counter(&heap_allocation_count);
  Brushing r = brushing("brush_hold.toml", "release = \"hold\"", 1.0, 6);
  ASSERT_TRUE(r.s);
  LiveShow& s = *r.s;
  const Actor& a = *s.actors()[0];
  ASSERT_TRUE(a.has_brush());
  for (int f = 0; f < 6; ++f) s.frame(int64_t(f * 1e9 / 60));  // (warm-up: before the pen touches)
  const long before = test::allocation_count();
  for (int f = 6; f < 72; ++f) s.frame(int64_t(f * 1e9 / 60));  // touched at 0.2 s, lifted at 0.7 s
  EXPECT_EQ(test::allocation_count() - before, 0) << "touching, dragging and lifting allocate nothing";
  EXPECT_EQ(s.allocations_after_warmup(), 0u);
  const BrushStage& br = a.brush();
  EXPECT_EQ(br.strokes(), 1);
  EXPECT_FALSE(br.down());
  ASSERT_GE(br.points().size(), 5u);
  // The radius at full pressure: 40 canvas px in character units.
  EXPECT_NEAR(br.radius(), 40 / a.px_per_unit, 1e-9);
  // Every brushed vertex moved by its Gaussian weight of the drag (held after the lift), within
  // 2 % of the drag; its weight from its distance along the outline.
  const FeatureFrameMethod& ff = *a.puppet().feature_frame();
  const double drag = kDrag.norm(), sigma = br.radius() / 3;
  // (the anchors beyond the radius, d = 0, hold still: the profile's tail there is below 1 %)
  double worst = 0, far = 1;
  size_t brushed = 0;
  for (const BrushStage::Point& pt : br.points()) {
    const Vec2 moved = ff.core().vertices()[size_t(pt.v)] - ff.frame().rest[size_t(pt.v)];
    const double d = std::exp(-pt.s * pt.s / (2 * sigma * sigma));
    worst = std::max(worst, (moved - d * kDrag).norm() / drag);
    if (pt.s <= br.radius()) {
      ++brushed;
      far = std::min(far, d);
    }
  }
  std::cout << brushed << " brushed vertices and " << br.points().size() - brushed << " anchors, weights down to " << far
            << "; worst off the Gaussian profile: " << 100 * worst << " % of the drag\n";
  EXPECT_LT(worst, 0.02);
  EXPECT_GE(brushed, 5u);
  EXPECT_LT(far, 0.3) << "(the profile reaches its tail)";
  // The rest of the figure stays: legs, torso and arms within 0.5 % of its height.
  const Puppet& p = a.puppet();
  for (const char* id : {"leg-left", "leg-right", "torso", "arm-left", "arm-right"}) {
    const int k = shape_of(p, id);
    ASSERT_GE(k, 0) << id;
    EXPECT_LT(off_rest(p, k), 0.005 * height(p)) << id;
    std::cout << id << " off its rest: " << 100 * off_rest(p, k) / height(p) << " % of the height\n";
  }
  EXPECT_GT(off_rest(p, shape_of(p, "face")), 0.8 * drag) << "the cheek went out";
}

TEST(Brush, ASpringBringsTheOutlineBackAndTheRunIsTheSameEachTime) {
  Brushing r = brushing("brush_spring.toml", "release = \"spring\"\nrelease_seconds = 0.4", 0.5);
  ASSERT_TRUE(r.s);
  LiveShow& s = *r.s;
  const Puppet& p = s.actors()[0]->puppet();
  const int face = shape_of(p, "face");
  double held = 0;
  for (int f = 0; f < 150; ++f) {
    s.frame(int64_t(f * 1e9 / 60));
    if (f == 40) held = off_rest(p, face);  // dragging
  }
  EXPECT_GT(held, 5.0);
  EXPECT_NEAR(s.actors()[0]->brush().radius(), 25 / s.actors()[0]->px_per_unit, 0.005 * 25 / s.actors()[0]->px_per_unit) << "half pressure: half way";
  EXPECT_EQ(s.actors()[0]->brush().points().size(), 0u) << "sprung back: nothing held";
  EXPECT_LT(off_rest(p, face), 0.002 * height(p)) << "the cheek back at rest";
  Brushing again = brushing("brush_spring.toml", "release = \"spring\"\nrelease_seconds = 0.4", 0.5);
  ASSERT_TRUE(again.s);
  for (int f = 0; f < 150; ++f) again.s->frame(int64_t(f * 1e9 / 60));
  EXPECT_EQ(again.s->run_hash(), s.run_hash());
}

// The example show (a cast: the figure brushed, the cat's tail drawn) recorded and replayed:
// the same run_hash, the pens' strokes coming back from the take as any input does.
TEST(Brush, TheSculptShowReplaysFromItsTakeToTheSameRunHash) {
  const std::string show = (test::source_dir() / "config/shows/sculpt.toml").string();
  const std::string take = (test::temp_dir("sculpt-take") / "sculpt.take").string();
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  o.record_path = take;
  auto live = LiveShow::load(show, o);
  ASSERT_TRUE(live.ok()) << live.error;
  EXPECT_EQ((*live.value)->run(), 0);
  const uint64_t played = (*live.value)->run_hash();
  EXPECT_EQ((*live.value)->actors()[0]->brush().strokes(), 3);
  EXPECT_EQ((*live.value)->actors()[1]->curve().strokes(), 2);
  live.value->reset();
  RunOptions r;
  r.headless = true;
  r.quiet = true;
  r.replay_path = take;
  auto again = LiveShow::load(show, r);
  ASSERT_TRUE(again.ok()) << again.error;
  EXPECT_EQ((*again.value)->run(), 0);
  EXPECT_EQ((*again.value)->run_hash(), played);
  EXPECT_EQ((*again.value)->actors()[0]->brush().strokes(), 3);
}

TEST(Brush, ABrushNeedsAFeatureFrameRigAndAPointer) {
  const std::string grid = (test::source_dir() / "config/rigs/boy_grid.toml").string();
  const std::string path = test::write_temp("brush_grid.toml", "[show]\nrig = \"" + grid + "\"\n"
                                                              "[[device]]\nname = \"pen\"\nsim = \"pen_tablet\"\n"
                                                              "[[brush]]\ndevice = \"pen\"\n");
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  auto s = LiveShow::load(path, o);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error.find(":6: [[brush]]: the brush needs the feature frame"), std::string::npos) << s.error;
  const std::string key = test::write_temp("brush_key.toml", "[show]\nrig = \"" + grid + "\"\n"
                                                             "[[device]]\nname = \"pen\"\nsim = \"pen_tablet\"\n"
                                                             "[[brush]]\ndevice = \"pen\"\nrelease = \"key\"\n");
  auto k = LiveShow::load(key, o);
  ASSERT_FALSE(k.ok());
  EXPECT_NE(k.error.find(":8: release = \"key\" names the key pose it blends into"), std::string::npos) << k.error;
  auto nope = LiveShow::load(brush_show("brush_nokey.toml", "release = \"key\"\nkey = \"smile\"", "0.1 leave\n"), o);
  ASSERT_FALSE(nope.ok());
  EXPECT_NE(nope.error.find(":20: the rig has no key pose 'smile' (wave, kick, rest)"), std::string::npos) << nope.error;
}

// release = "key": lifting the pen springs the brushed cheek back while the figure blends into
// its "wave" key over the same seconds, and holds it there.
TEST(Brush, AKeyReleaseBlendsIntoTheKeyPose) {
  set_allocation_counter(&heap_allocation_count);
  Brushing r = brushing("brush_to_key.toml", "release = \"key\"\nkey = \"wave\"\nrelease_seconds = 0.4", 1.0, 6);
  ASSERT_TRUE(r.s);
  LiveShow& s = *r.s;
  const Actor& a = *s.actors()[0];
  ASSERT_TRUE(a.has_keys());
  const Puppet& p = a.puppet();
  const int face = shape_of(p, "face");
  double held = 0, half = -1;
  for (int f = 0; f < 6; ++f) s.frame(int64_t(f * 1e9 / 60));  // (warm-up: before the pen touches)
  const long before = test::allocation_count();
  for (int f = 6; f < 42; ++f) {  // (lifted at 0.7 s: frame 42)
    s.frame(int64_t(f * 1e9 / 60));
    if (f == 40) held = off_rest(p, face);
    if (f == 6) {
      EXPECT_EQ(a.key_weights()[0], 0.0) << "no key before the lift";
    }
  }
  for (int f = 42; f < 200; ++f) {
    s.frame(int64_t(f * 1e9 / 60));
    if (f == 54) half = a.key_weights()[0];  // 0.2 s after the lift: on its way
  }
  EXPECT_EQ(test::allocation_count() - before, 0) << "the release into the key allocates nothing";
  EXPECT_GT(held, 5.0);
  EXPECT_GT(half, 0.2);
  EXPECT_LT(half, 0.8);
  EXPECT_DOUBLE_EQ(a.key_weights()[0], 1.0) << "the wave, held";
  EXPECT_EQ(a.brush().points().size(), 0u) << "the brushed cheek let go";
  // The figure stands as the same show stands when a button recalls its wave at the lift
  // (pose.wave, transition 0.4 s) and the pen never touches it: within 0.5 % of its height.
  // (a brush's finer frame solves the keys its own way: the reference has a brush too)
  const std::string rig = (test::source_dir() / "config/rigs/figure.toml").string();
  auto ref = load(test::write_temp("wave_by_button.toml",
                                   "[show]\nrig = \"" + rig + "\"\nrate = 60\niterations = 12\nmin_iterations = 12\n"
                                   "[display]\nwidth = 400\nheight = 560\n"
                                   "[[device]]\nname = \"korg\"\nsim = \"nanokontrol2\"\nscript = \"0.7 press solo1 for 0.1\"\n"
                                   "[[binding]]\ndevice = \"korg\"\ncontrol = \"cc 32\"\ntarget = \"pose.wave\"\ntransition = 0.4\n"
                                   "[[device]]\nname = \"pen\"\nsim = \"pen_tablet\"\nscript = \"0.1 leave\"\n"
                                   "[[brush]]\ndevice = \"pen\"\n"));
  ASSERT_TRUE(ref);
  for (int f = 0; f < 200; ++f) ref->frame(int64_t(f * 1e9 / 60));
  EXPECT_DOUBLE_EQ(ref->actors()[0]->key_weights()[0], 1.0);
  // (its frame is finer than the brushed one's: the drawn shapes are compared)
  const Puppet& q = ref->actors()[0]->puppet();
  ASSERT_EQ(p.shapes.size(), q.shapes.size());
  double worst = 0;
  for (size_t k = 0; k < p.shapes.size(); ++k)
    for (size_t i = 0; i < p.shapes[k].size() && i < q.shapes[k].size(); ++i) worst = std::max(worst, (p.shapes[k][i] - q.shapes[k][i]).norm());
  std::cout << "off the figure waving by a button: " << 100 * worst / height(p) << " % of the height\n";
  EXPECT_LT(worst, 0.005 * height(p));
}

}  // namespace
}  // namespace mar
