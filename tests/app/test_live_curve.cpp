// The drawn curve of seed 001 in a show ([[curve]], app/loop/curve.h): a simulated pen draws a
// line of action, and the figure's neck, face and hair take its curve — the chain's axis on the
// drawn curve, each part keeping its shape, the rest of the figure still, nothing allocated; a
// spring brings the chain back; a bad [[curve]] is refused with file:line.
#include "alloc_counter.h"
#include "app/alloc_count.h"
#include "app/live.h"
#include "live_util.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace mar {
namespace {

using test::height;
using test::off_rest;

std::string curve_show(const std::string& name, const std::string& release, const std::string& script) {
  const std::string rig = (test::source_dir() / "config/rigs/figure.toml").string();
  return test::write_temp(name, "[show]\nrig = \"" + rig + "\"\nrate = 60\niterations = 12\nmin_iterations = 12\n"
                                "[display]\nwidth = 400\nheight = 560\n"
                                "[[device]]\nname = \"pen\"\nsim = \"pen_tablet\"\nscript = \"\"\"\n" + script + "\"\"\"\n"
                                "[[curve]]\ndevice = \"pen\"\nparts = [\"neck\", \"face\", \"hair-cap\"]\nfrom = \"torso\"\nstrength = 1.0\n" +
                                    release + "\n");
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

// A line of action bending to the right, drawn up from the middle of the tablet over 0.6 s.
const char* kStroke =
    "0.1 hover 0.5,0.5\n0.2 stroke 0.5,0.5 0.515,0.43 0.54,0.37 0.575,0.32 0.615,0.285 over 0.6 pressure 0.8\n";

// Where a rest point of the drawing is now (bound to the frame as a handle is).
Vec2 now(const Puppet& p, const Vec2& rest) {
  const FeatureFrameMethod& ff = *p.feature_frame();
  return eval_param(bind_point(ff.frame(), p.character, rest), ff.core().vertices());
}

TEST(Curve, TheChainTakesTheDrawnCurveAndTheRestStays) {
  set_allocation_counter(&heap_allocation_count);
  auto s = load(curve_show("curve_hold.toml", "release = \"hold\"", kStroke), 6);
  ASSERT_TRUE(s);
  const Actor& a = *s->actors()[0];
  ASSERT_TRUE(a.has_curve());
  for (int f = 0; f < 6; ++f) s->frame(int64_t(f * 1e9 / 60));
  const long before = test::allocation_count();
  for (int f = 6; f < 90; ++f) s->frame(int64_t(f * 1e9 / 60));  // drawn 0.2 - 0.8 s, then held
  EXPECT_EQ(test::allocation_count() - before, 0) << "drawing and holding the curve allocate nothing";
  const CurveStage& c = a.curve();
  EXPECT_EQ(c.strokes(), 1);
  EXPECT_TRUE(c.active());
  EXPECT_GT(c.stroke_length(), 0.8 * c.axis_length()) << "(the stroke spans the chain)";
  const Puppet& p = a.puppet();
  const double h = height(p);
  // The chain's axis — where each part hangs and the last one's far end — on the drawn curve.
  const ChainGeometry& g = c.chain();
  double axis_off = 0, s_at = 0;
  for (size_t i = 0; i < g.rest.size(); ++i) {
    if (i > 0) s_at += (g.rest[i] - g.rest[i - 1]).norm();
    axis_off = std::max(axis_off, (now(p, g.rest[i]) - c.curve_at(s_at)).norm());
  }
  // Each part's own shape apart from its bend: the RMS distance of its points from its rest
  // points laid along the curve (bent by it and nothing else); and, bend and all, the RMS of
  // its best rigid fit to its rest shape.
  double own = 0, bent = 0;
  for (int k : g.shapes) {
    const Points& rest = p.character.shapes[size_t(k)].points;
    double sum = 0;
    for (size_t i = 0; i < rest.size(); ++i) sum += (p.shapes[size_t(k)][i] - c.lay(rest[i])).squaredNorm();
    own = std::max(own, std::sqrt(sum / double(std::max<size_t>(1, rest.size()))));
    bent = std::max(bent, rigid_fit_rms(rest, p.shapes[size_t(k)]));
  }
  std::cout << "axis off the drawn curve: " << 100 * axis_off / h << " % of the height; the parts' distortion apart from their bend "
            << 100 * own / h << " %, bend and all " << 100 * bent / h << " %; the face moved " << off_rest(p, "face") << " units\n";
  EXPECT_LT(axis_off, 0.01 * h);
  EXPECT_LT(own, 0.005 * h);
  EXPECT_GT(off_rest(p, "face"), 0.05 * h) << "the head leaned along the curve";
  for (const char* id : {"leg-left", "leg-right", "arm-left", "arm-right"}) EXPECT_LT(off_rest(p, id), 0.005 * h) << id;
  EXPECT_EQ(s->allocations_after_warmup(), 0u);
}

// The chain takes a straight stroke leaning right, a C and an S alike: its axis on the stroke
// within 1 % of the height, each part within 0.5 % of its rest shape laid along it.
TEST(Curve, AStraightACAndAnSStrokeAreEachTaken) {
  const struct {
    const char* name;
    const char* stroke;
  } strokes[] = {
      {"straight", "0.1 hover 0.5,0.5\n0.2 stroke 0.5,0.5 0.54,0.39 0.58,0.28 over 0.6 pressure 0.8\n"},
      {"C", kStroke},
      {"S", "0.1 hover 0.5,0.5\n0.2 stroke 0.5,0.5 0.515,0.44 0.52,0.38 0.505,0.33 0.49,0.28 over 0.6 pressure 0.8\n"},
  };
  for (const auto& k : strokes) {
    auto s = load(curve_show(std::string("curve_") + k.name + ".toml", "release = \"hold\"", k.stroke));
    ASSERT_TRUE(s);
    for (int f = 0; f < 90; ++f) s->frame(int64_t(f * 1e9 / 60));
    const CurveStage& c = s->actors()[0]->curve();
    const Puppet& p = s->actors()[0]->puppet();
    ASSERT_TRUE(c.active()) << k.name;
    const double h = height(p);
    const ChainGeometry& g = c.chain();
    double axis_off = 0, s_at = 0, own = 0;
    for (size_t i = 0; i < g.rest.size(); ++i) {
      if (i > 0) s_at += (g.rest[i] - g.rest[i - 1]).norm();
      axis_off = std::max(axis_off, (now(p, g.rest[i]) - c.curve_at(s_at)).norm());
    }
    for (int part : g.shapes) {
      const Points& rest = p.character.shapes[size_t(part)].points;
      double sum = 0;
      for (size_t i = 0; i < rest.size(); ++i) sum += (p.shapes[size_t(part)][i] - c.lay(rest[i])).squaredNorm();
      own = std::max(own, std::sqrt(sum / double(std::max<size_t>(1, rest.size()))));
    }
    std::cout << k.name << ": axis off the stroke " << 100 * axis_off / h << " % of the height, parts off their laid shape "
              << 100 * own / h << " %\n";
    EXPECT_LT(axis_off, 0.01 * h) << k.name;
    EXPECT_LT(own, 0.005 * h) << k.name;
  }
}

TEST(Curve, ASpringBringsTheChainBackAndANewStrokeReplacesTheCurve) {
  // Bent right at 0.2 - 0.8 s, springing back over 1 s; then a stroke bending left at 2.5 s.
  const std::string two = std::string(kStroke) + "2.4 hover 0.5,0.5\n2.5 stroke 0.5,0.5 0.485,0.43 0.46,0.37 0.425,0.32 over 0.4\n";
  auto s = load(curve_show("curve_spring.toml", "release = \"spring\"", two));
  ASSERT_TRUE(s);
  const Puppet& p = s->actors()[0]->puppet();
  const CurveStage& c = s->actors()[0]->curve();
  const Vec2 rest_tip = c.chain().rest.back();
  double held = 0, back = 0;
  Vec2 right(0, 0), left(0, 0);
  for (int f = 0; f < 190; ++f) {
    s->frame(int64_t(f * 1e9 / 60));
    if (f == 48) {  // drawn: the head leans right
      held = off_rest(p, "face");
      right = now(p, rest_tip);
    }
    if (f == 140) back = off_rest(p, "face");  // 2.33 s: sprung back
    if (f == 178) left = now(p, rest_tip);     // 2.97 s: the second stroke drawn
  }
  EXPECT_GT(held, 10.0);
  EXPECT_LT(back, 0.005 * height(p)) << "sprung back to rest";
  EXPECT_EQ(c.strokes(), 2);
  EXPECT_GT(right.x(), rest_tip.x() + 10) << "the first stroke bent right";
  EXPECT_LT(left.x(), rest_tip.x() - 10) << "the second stroke replaced it, bending left";
}

// A show whose pen redraws the face's outline (fit = "contour"): the pen's stroke in canvas
// pixels through the probe's view, as the brush's test draws.
double distance_to(std::span<const Vec2> poly, const Vec2& x) {
  double best = 1e300;
  for (size_t i = 0; i + 1 < poly.size(); ++i) {
    const Vec2 e = poly[i + 1] - poly[i];
    const double t = e.squaredNorm() > 0 ? std::clamp((x - poly[i]).dot(e) / e.squaredNorm(), 0.0, 1.0) : 0.0;
    best = std::min(best, (poly[i] + t * e - x).norm());
  }
  return best;
}

TEST(Curve, AContourFitRedrawsTheOutlineWhereTheStrokeRuns) {
  set_allocation_counter(&heap_allocation_count);
  const std::string rig = (test::source_dir() / "config/rigs/figure.toml").string();
  auto show = [&](const std::string& name, const std::string& script) {
    return test::write_temp(name, "[show]\nrig = \"" + rig + "\"\nrate = 60\niterations = 12\nmin_iterations = 12\n"
                                  "[display]\nwidth = 400\nheight = 560\n"
                                  "[[device]]\nname = \"pen\"\nsim = \"pen_tablet\"\nscript = \"\"\"\n" + script + "\"\"\"\n"
                                  "[[curve]]\ndevice = \"pen\"\nfit = \"contour\"\nparts = [\"face\"]\nrelease = \"hold\"\n");
  };
  auto probe = load(show("contour_probe.toml", "0.1 leave\n"));
  ASSERT_TRUE(probe);
  const Affine2 view = probe->actors()[0]->view;
  // The face is an ellipse about (150, 88), 44 across and 48 down: the stroke runs from its
  // left point down round its cheek, pushed out 9 units at the middle (a fuller cheek).
  std::string pts;
  for (int i = 0; i <= 10; ++i) {
    const double a = M_PI * (1.0 + 0.25 * i / 10.0), bulge = 9 * std::sin(M_PI * i / 10.0);
    const Vec2 on(150 + 44 * std::cos(a), 88 - 48 * std::sin(a)), out = on + bulge * Vec2(std::cos(a), -std::sin(a));
    const Vec2 c = view.apply(out);
    char b[64];
    std::snprintf(b, sizeof b, " %.6f,%.6f", c.x() / 400, c.y() / 560);
    pts += b;
  }
  auto s = load(show("contour.toml", "0.1 hover" + pts.substr(0, pts.find(' ', 1)) + "\n0.2 stroke" + pts + " over 0.6 pressure 0.8\n"), 6);
  ASSERT_TRUE(s);
  const Actor& a = *s->actors()[0];
  ASSERT_TRUE(a.has_curve());
  for (int f = 0; f < 6; ++f) s->frame(int64_t(f * 1e9 / 60));
  const long before = test::allocation_count();
  for (int f = 6; f < 49; ++f) s->frame(int64_t(f * 1e9 / 60));  // (0.8 s: the stroke drawn, the pen still down)
  const ContourStage& c = a.contour();
  ASSERT_TRUE(c.drawing());
  ASSERT_GE(c.segment().size(), 6u);
  const FeatureFrameMethod& ff = *a.puppet().feature_frame();
  double worst = 0, detail = 0;
  for (size_t j = 0; j < c.segment().size(); ++j) {
    worst = std::max(worst, distance_to(c.stroke(), ff.core().vertices()[size_t(c.segment()[j])]));
    detail = std::max(detail, c.detail(int(j)).norm());
  }
  for (int f = 49; f < 120; ++f) s->frame(int64_t(f * 1e9 / 60));  // lifted: held on the face
  EXPECT_EQ(test::allocation_count() - before, 0) << "drawing, fitting and holding allocate nothing";
  std::cout << c.segment().size() << " outline vertices took the stroke; the farthest " << worst * a.px_per_unit
            << " canvas px from it (its detail off a smooth line: " << detail * a.px_per_unit << " px)\n";
  EXPECT_LT(worst * a.px_per_unit, 1.0 + detail * a.px_per_unit);
  EXPECT_TRUE(c.active()) << "held after the lift";
  EXPECT_GT(off_rest(a.puppet(), "face"), 6.0) << "the cheek is fuller";
  for (const char* id : {"leg-left", "leg-right", "arm-left", "arm-right", "torso"})
    EXPECT_LT(off_rest(a.puppet(), id), 0.005 * height(a.puppet())) << id;
}

// The detail kept: a part whose top edge is a zigzag (3 units each way of its mean line) is
// redrawn by a straight stroke 12 units above that line; the edge takes the stroke's course and
// keeps its zigzag.
TEST(Curve, AContourFitKeepsTheOutlinesDetailOnTopOfTheStroke) {
  std::string top;
  for (int i = 0; i <= 12; ++i) top += " L " + std::to_string(40 + 10 * i) + " " + (i % 2 ? "54" : "60");
  test::write_temp("wavy.svg", "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"200\" height=\"200\" viewBox=\"0 0 200 200\">"
                               "<path id=\"block\" fill=\"#c84\" d=\"M 40 100" + top + " L 160 100 Z\"/></svg>");
  const std::string rig = test::write_temp("wavy.toml", "character = \"wavy.svg\"\n[[handle]]\nname = \"left\"\nrest = [45.0, 95.0]\n"
                                                        "[[handle]]\nname = \"right\"\nrest = [155.0, 95.0]\n");
  auto s = load(test::write_temp("wavy_show.toml", "[show]\nrig = \"" + rig + "\"\nrate = 60\niterations = 12\nmin_iterations = 12\n"
                                                   "[display]\nwidth = 400\nheight = 400\n"
                                                   "[[device]]\nname = \"pen\"\nsim = \"pen_tablet\"\nscript = \"\"\"\n"
                                                   "0.1 hover 0.2,0.3\n0.2 stroke 0.2,0.3 0.5,0.225 0.8,0.225 over 0.6 pressure 0.8\n"
                                                   "\"\"\"\n[[curve]]\ndevice = \"pen\"\nfit = \"contour\"\narea = [0, 0, 200, 200]\n"));
  ASSERT_TRUE(s);
  for (int f = 0; f < 49; ++f) s->frame(int64_t(f * 1e9 / 60));  // (drawn; the pen still down)
  const Actor& a = *s->actors()[0];
  const ContourStage& c = a.contour();
  ASSERT_TRUE(c.drawing());
  const auto v = a.puppet().feature_frame()->core().vertices();
  const auto& rest = a.puppet().feature_frame()->frame().rest;
  // The straight run of the stroke (x 100 .. 160 at y 45): each fitted vertex there sits off
  // it by its own detail (its offset from the running mean of the edge at rest: the zigzag).
  double worst = 0, zig = 0;
  size_t n = 0;
  for (size_t j = 1; j + 1 < c.segment().size(); ++j) {
    const int k = c.segment()[j];
    if (rest[size_t(k)].x() < 105 || rest[size_t(k)].x() > 155) continue;
    const double across = v[size_t(k)].y() - 45;  // (the stroke runs +x: its normal is +y)
    const double want = c.detail(int(j)).y();
    worst = std::max(worst, std::abs(across - want));
    zig = std::max(zig, std::abs(want));
    ++n;
  }
  std::cout << n << " vertices on the stroke's straight run keep the zigzag to within " << worst * a.px_per_unit
            << " canvas px (it stands " << zig * a.px_per_unit << " px off its mean)\n";
  ASSERT_GE(n, 4u);
  EXPECT_GT(zig, 2.5);
  EXPECT_LT(worst * a.px_per_unit, 1.0);
}

// One pen with a tool on each of a cast's characters (the figure's brush, the cat's curve): as
// its tip goes down it takes the tool whose character is drawn under it, whichever table comes
// first in the show.
TEST(Curve, OnePenTakesTheToolOfTheCharacterUnderIt) {
  const std::string dir = (test::source_dir() / "config/rigs").string();
  auto show = [&](const std::string& name, const std::string& script) {
    return test::write_temp(name, "[show]\nrate = 60\n[display]\nwidth = 1000\nheight = 600\n"
                                  "[[character]]\nname = \"figure\"\nrig = \"" + dir + "/figure.toml\"\nposition = [400, 300]\n"
                                  "[[character]]\nname = \"cat\"\nrig = \"" + dir + "/cat.toml\"\nposition = [780, 420]\nscale = 0.55\n"
                                  "[[device]]\nname = \"pen\"\nsim = \"pen_tablet\"\nscript = \"\"\"\n" + script + "\"\"\"\n"
                                  "[[brush]]\ndevice = \"pen\"\ncharacter = \"figure\"\nrelease = \"hold\"\n"
                                  "[[curve]]\ndevice = \"pen\"\ncharacter = \"cat\"\nparts = [\"path2291\"]\nfrom = \"ellipse1042\"\n");
  };
  // The cat's tail drawn up from where it hangs (as sculpt.toml's tail pen draws it), then the
  // figure's cheek brushed out (as its brush pen does).
  auto s = load(show("one_pen.toml", "0.5 hover 0.665,0.70\n0.6 stroke 0.665,0.70 0.63,0.62 0.62,0.53 over 0.6 pressure 0.8\n"
                                     "1.5 hover 0.3412,0.2430\n1.6 stroke 0.3412,0.2430 0.3169,0.2430 over 0.5 pressure 1.0\n"));
  ASSERT_TRUE(s);
  const Actor& figure = *s->actors()[0];
  const Actor& cat = *s->actors()[1];
  for (int f = 0; f < 80; ++f) s->frame(int64_t(f * 1e9 / 60));  // (1.33 s: the tail drawn)
  EXPECT_EQ(cat.curve().strokes(), 1) << "the pen went down on the cat: its curve";
  EXPECT_EQ(figure.brush().strokes(), 0) << "not the figure's brush, the first table";
  for (int f = 80; f < 140; ++f) s->frame(int64_t(f * 1e9 / 60));
  EXPECT_EQ(figure.brush().strokes(), 1) << "then down on the figure's cheek: its brush";
  EXPECT_EQ(cat.curve().strokes(), 1);
  EXPECT_GE(figure.brush().points().size(), 5u);
}

// release = "key": the lifted curve springs back while the figure blends into its kick.
TEST(Curve, AKeyReleaseSpringsTheChainBackIntoTheKeyPose) {
  auto s = load(curve_show("curve_key.toml", "release = \"key\"\nkey = \"kick\"\nrelease_seconds = 0.5", kStroke));
  ASSERT_TRUE(s);
  const Actor& a = *s->actors()[0];
  ASSERT_TRUE(a.has_keys());
  double during = -1;
  for (int f = 0; f < 120; ++f) {
    s->frame(int64_t(f * 1e9 / 60));
    if (f == 47) during = a.key_weights()[1];  // (drawing: no key yet)
  }
  EXPECT_EQ(during, 0.0);
  EXPECT_DOUBLE_EQ(a.key_weights()[1], 1.0) << "the kick, held";
  EXPECT_DOUBLE_EQ(a.key_weights()[0], 0.0);
  EXPECT_FALSE(a.curve().active()) << "the curve let go";
}

TEST(Curve, ABadCurveIsRefusedWithItsLine) {
  auto refused = [](const std::string& body) {
    const std::string rig = (test::source_dir() / "config/rigs/figure.toml").string();
    const std::string path = test::write_temp("curve_bad.toml", "[show]\nrig = \"" + rig +
                                                                "\"\n[[device]]\nname = \"pen\"\nsim = \"pen_tablet\"\n" + body);
    RunOptions o;
    o.headless = true;
    o.quiet = true;
    auto s = LiveShow::load(path, o);
    return s.ok() ? std::string("loaded") : s.error;
  };
  EXPECT_NE(refused("[[curve]]\ndevice = \"pen\"\nparts = [\"neck\", \"tail\"]\nfrom = \"torso\"\n").find(":6: [[curve]]: part 'tail'"),
            std::string::npos);
  EXPECT_NE(refused("[[curve]]\ndevice = \"pen\"\nparts = [\"neck\"]\n").find(":6: [[curve]] names its chain"), std::string::npos);
  EXPECT_NE(refused("[[curve]]\ndevice = \"pen\"\nparts = [\"neck\", \"neck\"]\nfrom = \"torso\"\n")
                .find(":6: [[curve]]: the chain names part 'neck' twice"),
            std::string::npos);
  EXPECT_NE(refused("[[curve]]\ndevice = \"pen\"\nparts = [\"neck\"]\nfrom = \"torso\"\nfit = \"contour\"\n").find(":9: from is a chain's"),
            std::string::npos);
  EXPECT_NE(refused("[[curve]]\ndevice = \"pen\"\nfit = \"contour\"\nparts = [\"nose\"]\n").find(":6: [[curve]]: part 'nose'"),
            std::string::npos);
  EXPECT_NE(refused("[[curve]]\ndevice = \"pen\"\nparts = [\"neck\"]\nfrom = \"torso\"\nkey = \"wave\"\n").find(":10: key is for release = \"key\""),
            std::string::npos);
  EXPECT_NE(refused("[[brush]]\ndevice = \"pen\"\n[[curve]]\ndevice = \"pen\"\nparts = [\"neck\"]\nfrom = \"torso\"\n")
                .find(":8: [[curve]]: a character takes one pen tool"),
            std::string::npos);
}

}  // namespace
}  // namespace mar
