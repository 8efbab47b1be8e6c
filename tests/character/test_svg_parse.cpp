#include "character/svg_parse.h"

#include <gtest/gtest.h>

namespace mar::svg {
namespace {

using K = PathCmd::Kind;

void expect_cmd(const PathCmd& c, K kind, Vec2 p) {
  EXPECT_EQ(c.kind, kind);
  EXPECT_NEAR((c.p - p).norm(), 0, 1e-9) << "got " << c.p.transpose() << " want " << p.transpose();
}

TEST(read_number, Grammar) {
  auto one = [](std::string_view s, size_t expect_pos) {
    size_t pos = 0;
    auto v = read_number(s, pos);
    EXPECT_EQ(pos, expect_pos) << s;
    return v.value_or(NAN);
  };
  EXPECT_DOUBLE_EQ(one("1e-3", 4), 1e-3);
  EXPECT_DOUBLE_EQ(one(".5.5", 2), 0.5);
  EXPECT_DOUBLE_EQ(one("-.5e2x", 5), -50);
  EXPECT_DOUBLE_EQ(one("+3", 2), 3);
  EXPECT_DOUBLE_EQ(one("10em", 2), 10);  // 'e' not followed by digits is not an exponent
  EXPECT_DOUBLE_EQ(one("7.", 2), 7);
  size_t pos = 0;
  EXPECT_FALSE(read_number("abc", pos));
  EXPECT_FALSE(read_number("-", pos));
  EXPECT_FALSE(read_number(".", pos));
}

TEST(parse_path, MoveLineAbsoluteAndRelative) {
  auto a = parse_path("M10 20 L30 40");
  ASSERT_EQ(a.cmds.size(), 2u);
  expect_cmd(a.cmds[0], K::Move, {10, 20});
  expect_cmd(a.cmds[1], K::Line, {30, 40});
  auto r = parse_path("m10 20 l5 5");
  expect_cmd(r.cmds[1], K::Line, {15, 25});
  EXPECT_TRUE(a.error.empty());
}

TEST(parse_path, ImplicitRepeats) {
  auto p = parse_path("M0 0 10 0 10 10");  // extra pairs after M are linetos
  ASSERT_EQ(p.cmds.size(), 3u);
  expect_cmd(p.cmds[1], K::Line, {10, 0});
  expect_cmd(p.cmds[2], K::Line, {10, 10});
  auto r = parse_path("m1 1 2 2 l1 0 1 0");
  ASSERT_EQ(r.cmds.size(), 4u);
  expect_cmd(r.cmds[1], K::Line, {3, 3});
  expect_cmd(r.cmds[3], K::Line, {5, 3});
  auto c = parse_path("M0 0 C1 1 2 2 3 3 4 4 5 5 6 6");
  ASSERT_EQ(c.cmds.size(), 3u);
  expect_cmd(c.cmds[2], K::Cubic, {6, 6});
}

TEST(parse_path, HorizontalVertical) {
  auto p = parse_path("M1 2 H10 V20 h-5 v-5");
  ASSERT_EQ(p.cmds.size(), 5u);
  expect_cmd(p.cmds[1], K::Line, {10, 2});
  expect_cmd(p.cmds[2], K::Line, {10, 20});
  expect_cmd(p.cmds[3], K::Line, {5, 20});
  expect_cmd(p.cmds[4], K::Line, {5, 15});
}

TEST(parse_path, CubicAndSmoothReflection) {
  auto p = parse_path("M0 0 C10 0 20 10 20 20 S30 40 40 40");
  ASSERT_EQ(p.cmds.size(), 3u);
  EXPECT_EQ(p.cmds[1].c1, Vec2(10, 0));
  EXPECT_EQ(p.cmds[1].c2, Vec2(20, 10));
  EXPECT_EQ(p.cmds[2].c1, Vec2(20, 30));  // reflection of (20,10) about (20,20)
  EXPECT_EQ(p.cmds[2].c2, Vec2(30, 40));
  auto rel = parse_path("m0 0 c10 0 20 10 20 20 s10 20 20 20");
  EXPECT_EQ(rel.cmds[2].c1, Vec2(20, 30));
  EXPECT_EQ(rel.cmds[2].c2, Vec2(30, 40));
  expect_cmd(rel.cmds[2], K::Cubic, {40, 40});
  auto lone = parse_path("M5 5 S10 10 20 5");  // no previous cubic: first control = current
  EXPECT_EQ(lone.cmds[1].c1, Vec2(5, 5));
}

TEST(parse_path, QuadraticAndSmoothReflection) {
  auto p = parse_path("M0 0 Q30 30 60 0 T120 0");
  ASSERT_EQ(p.cmds.size(), 3u);
  EXPECT_NEAR((p.cmds[1].c1 - Vec2(20, 20)).norm(), 0, 1e-12);  // p0 + 2/3 (q - p0)
  EXPECT_NEAR((p.cmds[1].c2 - Vec2(40, 20)).norm(), 0, 1e-12);
  // T reflects q = (30,30) about (60,0) -> (90,-30)
  EXPECT_NEAR((p.cmds[2].c1 - Vec2(60 + 2.0 / 3 * 30, -20)).norm(), 0, 1e-12);
  auto rel = parse_path("m0 0 q30 30 60 0 t60 0");
  EXPECT_NEAR((rel.cmds[2].c1 - p.cmds[2].c1).norm(), 0, 1e-12);
  expect_cmd(rel.cmds[2], K::Cubic, {120, 0});
}

TEST(parse_path, ArcsWithCompactFlags) {
  auto spaced = parse_path("M0 0 A50 50 0 0 1 100 0");
  auto compact = parse_path("M0 0a50 50 0 01100 0");
  ASSERT_TRUE(spaced.error.empty());
  ASSERT_TRUE(compact.error.empty()) << compact.error;
  ASSERT_EQ(spaced.cmds.size(), compact.cmds.size());
  for (size_t i = 0; i < spaced.cmds.size(); ++i) {
    EXPECT_NEAR((spaced.cmds[i].p - compact.cmds[i].p).norm(), 0, 1e-12);
  }
  expect_cmd(spaced.cmds.back(), K::Cubic, {100, 0});
  auto flat = flatten_path(spaced.cmds, Affine2::identity(), 0.05);
  ASSERT_EQ(flat.size(), 1u);
  for (const Vec2& p : flat[0].points) EXPECT_NEAR((p - Vec2(50, 0)).norm(), 50, 0.06);
  auto bad_flag = parse_path("M0 0 A50 50 0 2 1 100 0");
  EXPECT_FALSE(bad_flag.error.empty());
}

TEST(parse_path, CloseReturnsToStartAndNextCommandStartsThere) {
  auto p = parse_path("M10 10 L20 10 L20 20 Z l5 0");
  ASSERT_EQ(p.cmds.size(), 5u);
  expect_cmd(p.cmds[3], K::Close, {10, 10});
  expect_cmd(p.cmds[4], K::Line, {15, 10});
  auto flat = flatten_path(p.cmds, Affine2::identity(), 0.1);
  ASSERT_EQ(flat.size(), 2u);
  EXPECT_TRUE(flat[0].closed);
  EXPECT_FALSE(flat[1].closed);
  EXPECT_EQ(flat[1].points.front(), Vec2(10, 10));
}

TEST(parse_path, CompactNumbers) {
  auto p = parse_path("M.5.5L1e1-1e1l-.5-.5");
  ASSERT_TRUE(p.error.empty()) << p.error;
  ASSERT_EQ(p.cmds.size(), 3u);
  expect_cmd(p.cmds[0], K::Move, {0.5, 0.5});
  expect_cmd(p.cmds[1], K::Line, {10, -10});
  expect_cmd(p.cmds[2], K::Line, {9.5, -10.5});
  auto commas = parse_path("M 1,2,3,4");
  expect_cmd(commas.cmds[1], K::Line, {3, 4});
}

TEST(parse_path, ErrorsKeepWhatCameBefore) {
  auto missing = parse_path("M0 0 L10 10 L20");
  EXPECT_FALSE(missing.error.empty());
  EXPECT_EQ(missing.cmds.size(), 2u);
  EXPECT_EQ(missing.error_pos, 12u);
  auto no_move = parse_path("L10 10");
  EXPECT_FALSE(no_move.error.empty());
  EXPECT_TRUE(no_move.cmds.empty());
  auto unknown = parse_path("M0 0 X5 5");
  EXPECT_NE(unknown.error.find("unknown"), std::string::npos);
  EXPECT_EQ(unknown.cmds.size(), 1u);
  EXPECT_TRUE(parse_path("").cmds.empty());
  EXPECT_TRUE(parse_path("").error.empty());
}

TEST(parse_transform, EveryForm) {
  auto apply = [](std::string_view s, Vec2 p) { return parse_transform(s).value().apply(p); };
  EXPECT_EQ(apply("matrix(1 2 3 4 5 6)", {1, 1}), Vec2(1 + 3 + 5, 2 + 4 + 6));
  EXPECT_EQ(apply("translate(5)", {1, 1}), Vec2(6, 1));
  EXPECT_EQ(apply("translate(5,6)", {1, 1}), Vec2(6, 7));
  EXPECT_EQ(apply("scale(2)", {1, 3}), Vec2(2, 6));
  EXPECT_EQ(apply("scale(2 3)", {1, 1}), Vec2(2, 3));
  EXPECT_NEAR((apply("rotate(90)", {1, 0}) - Vec2(0, 1)).norm(), 0, 1e-12);
  EXPECT_NEAR((apply("rotate(90 10 10)", {10, 10}) - Vec2(10, 10)).norm(), 0, 1e-12);
  EXPECT_NEAR((apply("rotate(90 10 10)", {11, 10}) - Vec2(10, 11)).norm(), 0, 1e-12);
  EXPECT_NEAR((apply("skewX(45)", {0, 2}) - Vec2(2, 2)).norm(), 0, 1e-12);
  EXPECT_NEAR((apply("skewY(45)", {2, 0}) - Vec2(2, 2)).norm(), 0, 1e-12);
}

TEST(parse_transform, ListsComposeLeftToRight) {
  // translate(10) scale(2): scale first, then translate.
  EXPECT_EQ(parse_transform("translate(10) scale(2)")->apply({1, 1}), Vec2(12, 2));
  EXPECT_EQ(parse_transform("translate(10,20),scale(2)")->apply({1, 1}), Vec2(12, 22));
  EXPECT_EQ(parse_transform(" scale( 2 ) translate( 10 ) ")->apply({1, 1}), Vec2(22, 2));
  EXPECT_EQ(parse_transform("")->apply({3, 4}), Vec2(3, 4));
}

TEST(parse_transform, RejectsMalformed) {
  EXPECT_EQ(parse_transform("translate(10")->apply({1, 1}), Vec2(11, 1));  // (unclosed at the end: as librsvg)
  EXPECT_FALSE(parse_transform("translate(10 scale(2)"));
  EXPECT_FALSE(parse_transform("foo(1)"));
  EXPECT_FALSE(parse_transform("scale()"));
  EXPECT_FALSE(parse_transform("rotate(1 2)"));
  EXPECT_FALSE(parse_transform("matrix(1 2 3)"));
}

TEST(parse_points, PairsAndOddCount) {
  bool odd = false;
  auto p = parse_points("0,0 10,0 10 10 5", &odd);
  EXPECT_EQ(p.size(), 3u);
  EXPECT_TRUE(odd);
}

}  // namespace
}  // namespace mar::svg
