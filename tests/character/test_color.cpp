#include "character/color.h"

#include <gtest/gtest.h>

namespace mar {
namespace {

void expect_rgb(std::string_view text, double r, double g, double b, float a = 1.0f) {
  auto c = parse_color(text);
  ASSERT_TRUE(c) << text;
  EXPECT_NEAR(c->r * 255, r, 0.51) << text;
  EXPECT_NEAR(c->g * 255, g, 0.51) << text;
  EXPECT_NEAR(c->b * 255, b, 0.51) << text;
  EXPECT_NEAR(c->a, a, 1e-3) << text;
}

TEST(parse_color, HexForms) {
  expect_rgb("#abc", 0xaa, 0xbb, 0xcc);
  expect_rgb("#A0B1C2", 0xa0, 0xb1, 0xc2);
  expect_rgb("  #000000 ", 0, 0, 0);
  expect_rgb("#ff000080", 255, 0, 0, 128 / 255.0f);
  EXPECT_FALSE(parse_color("#abcd1"));
  EXPECT_FALSE(parse_color("#ggg"));
}

TEST(parse_color, RgbFunction) {
  expect_rgb("rgb(10, 20, 30)", 10, 20, 30);
  expect_rgb("rgb(100%, 50%, 0%)", 255, 127.5, 0);
  expect_rgb("RGB(300, -5, 0)", 255, 0, 0);  // clamped
  expect_rgb("rgba(0, 0, 255, 0.5)", 0, 0, 255, 0.5f);
  expect_rgb("rgb(1 2 3)", 1, 2, 3);
  EXPECT_FALSE(parse_color("rgb(1, 2)"));
  EXPECT_FALSE(parse_color("rgb(a, b, c)"));
}

TEST(parse_color, NamedColours) {
  expect_rgb("red", 255, 0, 0);
  expect_rgb("CornflowerBlue", 100, 149, 237);
  expect_rgb("yellowgreen", 154, 205, 50);
  expect_rgb("aliceblue", 240, 248, 255);
  expect_rgb("grey", 128, 128, 128);
  EXPECT_FALSE(parse_color("notacolour"));
  EXPECT_FALSE(parse_color(""));
}

TEST(color_hex, RoundTrips) {
  EXPECT_EQ(color_hex(*parse_color("#12ab9f")), "#12ab9f");
}

}  // namespace
}  // namespace mar
