#include "character/load.h"
#include "character/svg_loader.h"
#include "frame/feature_frame.h"
#include "frame/feature_points.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <functional>
#include <numeric>

namespace mar {
namespace {

Character svg(const std::string& body) {
  auto r = load_svg_string("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"200\" height=\"200\">" + body + "</svg>",
                           "t.svg");
  EXPECT_TRUE(r.ok()) << r.error;
  return *r.value;
}

Character example(const std::string& name) {
  auto r = load_character((test::characters_dir() / (name + ".svg")).string());
  EXPECT_TRUE(r.ok()) << r.error;
  return *r.value;
}

TEST(ipan99_corners, FindsTheFourCornersOfADenseSquare) {
  Points sq;
  for (int i = 0; i < 40; ++i) sq.emplace_back(i, 0);
  for (int i = 0; i < 40; ++i) sq.emplace_back(40, i);
  for (int i = 0; i < 40; ++i) sq.emplace_back(40 - i, 40);
  for (int i = 0; i < 40; ++i) sq.emplace_back(0, 40 - i);
  const auto c = ipan99_corners(sq, true, 2, 6, 150 * M_PI / 180);
  EXPECT_EQ(c, (std::vector<int>{0, 40, 80, 120}));
}

TEST(ipan99_corners, SmoothCircleHasNone) {
  Points circle;
  for (int i = 0; i < 200; ++i) circle.emplace_back(100 * std::cos(i * 2 * M_PI / 200), 100 * std::sin(i * 2 * M_PI / 200));
  EXPECT_TRUE(ipan99_corners(circle, true, 3, 9, 150 * M_PI / 180).empty());
}

TEST(inflection_points, SineWaveHasOnePerHalfPeriodAndNoiseAddsNone) {
  Points wave, noisy;
  for (int i = 0; i <= 400; ++i) {
    const double x = i * 0.5, y = 20 * std::sin(x * 2 * M_PI / 100);  // 2 periods over x in [0, 200]
    wave.emplace_back(x, y);
    noisy.emplace_back(x, y + ((i * 7919) % 13 - 6) * 0.02);
  }
  const auto a = inflection_points(wave, false, 6, 0.2);
  ASSERT_EQ(a.size(), 3u);  // x = 50, 100, 150
  EXPECT_NEAR(wave[static_cast<size_t>(a[0])].x(), 50, 2);
  EXPECT_NEAR(wave[static_cast<size_t>(a[1])].x(), 100, 2);
  EXPECT_EQ(inflection_points(noisy, false, 6, 0.2).size(), 3u);
}

TEST(arc_length_samples, EvenSpacing) {
  Points line;
  for (int i = 0; i <= 100; ++i) line.emplace_back(i, 0);
  EXPECT_EQ(arc_length_samples(line, false, 25), (std::vector<int>{0, 25, 50, 75, 100}));
}

TEST(build_feature_frame, OpenStrokesGetEndPointsAndEveryVertexIsParameterised) {
  const Character ch = svg(R"svg(<path d="M10 10 Q100 120 190 10" fill="none" stroke="black"/>
                                 <rect x="20" y="120" width="60" height="60"/>)svg");
  const FeatureFrame f = build_feature_frame(ch, default_frame_options());
  ASSERT_EQ(f.subframes.size(), 2u);
  const auto& open = f.subframes[0];
  EXPECT_EQ(f.rest[static_cast<size_t>(open.front())], ch.shapes[0].points.front());
  EXPECT_EQ(f.rest[static_cast<size_t>(open.back())], ch.shapes[0].points.back());
  EXPECT_EQ(f.subframes[1].size(), 4u);  // the rectangle's corners
  EXPECT_EQ(f.sewing_lines, 1);          // spanning tree over two sub-frames
  // Parametric coordinates reproduce the rest shape exactly.
  std::vector<Points> out{ch.shapes[0].points, ch.shapes[1].points};
  reconstruct_shapes(f, f.rest, out);
  for (size_t s = 0; s < 2; ++s)
    for (size_t i = 0; i < out[s].size(); ++i) EXPECT_NEAR((out[s][i] - ch.shapes[s].points[i]).norm(), 0, 1e-9);
}

TEST(build_feature_frame, ClosedContoursGetAtLeastThreePoints) {
  const Character ch = svg(R"svg(<circle cx="100" cy="100" r="50"/>)svg");
  const FeatureFrame f = build_feature_frame(ch, default_frame_options());
  ASSERT_EQ(f.subframes.size(), 1u);
  EXPECT_EQ(f.subframes[0].size(), 3u);
  EXPECT_EQ(f.feature_lines, 3);
}

TEST(build_feature_frame, IntersectionsGiveBothShapesAFeaturePointAndAWeld) {
  Character ch = svg(R"svg(<path d="M0 100 C50 100 150 100 200 100" stroke="black" fill="none"/>
                                 <path d="M100 0 C100 50 100 150 100 200" stroke="black" fill="none"/>)svg");
  EXPECT_EQ(refine_for_frame(ch, default_frame_options()), 2u);  // the crossing, on both strokes
  const FeatureFrame f = build_feature_frame(ch, default_frame_options());
  // Open strokes crossing are welded: the zero-length line at the crossing (a pin) plus a
  // second line that keeps their relative orientation.
  ASSERT_EQ(f.sewing_lines, 2);
  EXPECT_TRUE(f.joints.empty());
  int pins = 0, welds = 0;
  for (int li = f.feature_lines; li < static_cast<int>(f.lines.size()); ++li) {
    const FrameLine& sl = f.lines[static_cast<size_t>(li)];
    const double len = (f.rest[static_cast<size_t>(sl.a)] - f.rest[static_cast<size_t>(sl.b)]).norm();
    if (len < 1.0) {
      ++pins;
      EXPECT_NEAR(f.rest[static_cast<size_t>(sl.a)].x(), 100, 1.0);
    } else {
      ++welds;
      EXPECT_NE(f.origin[static_cast<size_t>(sl.a)].shape, f.origin[static_cast<size_t>(sl.b)].shape);
    }
  }
  EXPECT_EQ(pins, 1);
  EXPECT_EQ(welds, 1);
}

TEST(build_feature_frame, SewingSpansEverySubFrameOfTheExamples) {
  for (const char* name : {"butterfly", "figure", "koi"}) {
    const Character ch = example(name);
    const FeatureFrame f = build_feature_frame(ch, default_frame_options());
    // One connected frame: the spanning tree's lines, some of them replaced by hinges.
    std::vector<int> comp(f.rest.size());
    std::iota(comp.begin(), comp.end(), 0);
    std::function<int(int)> find = [&](int x) { return comp[static_cast<size_t>(x)] == x ? x : comp[static_cast<size_t>(x)] = find(comp[static_cast<size_t>(x)]); };
    for (const FrameLine& l : f.lines) comp[static_cast<size_t>(find(l.a))] = find(l.b);
    for (size_t i = 0; i < f.rest.size(); ++i) EXPECT_EQ(find(static_cast<int>(i)), find(0)) << name;
    EXPECT_GE(static_cast<size_t>(f.sewing_lines) + f.joints.size(), f.subframes.size() - 1) << name;
    EXPECT_LT(f.rest.size(), f.shape_vertices / 2) << name;  // the frame is much smaller than the shape
  }
}

TEST(build_feature_frame, UserSewingEditsAddMergeDeleteMove) {
  const Character plain = svg(R"svg(<rect x="10" y="10" width="40" height="40"/>
                                 <rect x="100" y="10" width="40" height="40"/>)svg");
  FrameOptions o = default_frame_options();
  const FeatureFrame base = build_feature_frame(plain, o);
  ASSERT_EQ(base.sewing_lines, 1);
  auto build = [&](const FrameOptions& opt) {
    Character ch = plain;
    refine_for_frame(ch, opt);
    return build_feature_frame(ch, opt);
  };
  // Add: one end on an existing corner (merged), one mid-edge (inserted as a new feature point).
  SewingEdit add;
  add.from = {50, 50};
  add.to = {100, 30};
  o.sewing = {add};
  const FeatureFrame added = build(o);
  EXPECT_EQ(added.sewing_lines, 2);
  EXPECT_EQ(added.user_sewing_lines, 1);
  EXPECT_EQ(added.rest.size(), base.rest.size() + 1);
  // Delete the automatic line (between the facing corners).
  const FrameLine auto_line = base.lines.back();
  SewingEdit del;
  del.kind = SewingEdit::Delete;
  del.from = base.rest[static_cast<size_t>(auto_line.a)];
  del.to = base.rest[static_cast<size_t>(auto_line.b)];
  o.sewing = {del};
  EXPECT_EQ(build(o).sewing_lines, 0);
  // Move it elsewhere.
  SewingEdit mv = del;
  mv.kind = SewingEdit::Move;
  mv.new_from = {30, 50};
  mv.new_to = {120, 50};
  o.sewing = {mv};
  const FeatureFrame moved = build(o);
  EXPECT_EQ(moved.sewing_lines, 1);
  EXPECT_EQ(moved.user_sewing_lines, 1);
  // A delete that matches nothing warns.
  SewingEdit bad;
  bad.kind = SewingEdit::Delete;
  bad.from = {190, 190};
  bad.to = {195, 195};
  bad.where = "rig.toml:7";
  o.sewing = {bad};
  const FeatureFrame w = build(o);
  ASSERT_EQ(w.warnings.size(), 1u);
  EXPECT_NE(w.warnings[0].find("rig.toml:7"), std::string::npos);
}

TEST(build_feature_frame, UniformSamplingIntervalControlsDensity) {
  const Character ch = svg(R"svg(<path d="M10 100 C60 0 140 200 190 100" stroke="black" fill="none"/>)svg");
  FrameOptions dense = default_frame_options(), sparse = dense;
  dense.mode = sparse.mode = SamplingMode::Uniform;
  dense.interval = 10;
  sparse.interval = 50;
  EXPECT_GT(build_feature_frame(ch, dense).rest.size(), 3 * build_feature_frame(ch, sparse).rest.size());
}

TEST(build_feature_frame, EmptyCharacter) {
  const FeatureFrame f = build_feature_frame(Character{}, default_frame_options());
  EXPECT_TRUE(f.rest.empty());
  EXPECT_EQ(f.sewing_lines, 0);
}

TEST(bind_point, ReproducesTheRestPoint) {
  const Character ch = example("butterfly");
  const FeatureFrame f = build_feature_frame(ch, default_frame_options());
  for (const Vec2& p : {Vec2(200, 135), Vec2(100, 120), Vec2(150, 62), Vec2(0, 0)}) {
    const ShapeParam b = bind_point(f, ch, p);
    EXPECT_NEAR((eval_param(b, f.rest) - p).norm(), 0, 1e-9);
  }
}

}  // namespace
}  // namespace mar
