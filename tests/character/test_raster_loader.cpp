#include "character/load.h"
#include "character/raster_loader.h"
#include "geom/polygon.h"
#include "render/image.h"
#include "test_util.h"

#include <gtest/gtest.h>

namespace mar {
namespace {

// 64x64 RGBA: an opaque ring (with a hole) and a separate small square, transparent elsewhere.
std::shared_ptr<Texture> ring_image() {
  auto t = std::make_shared<Texture>();
  t->width = t->height = 64;
  t->rgba.assign(64 * 64 * 4, 0);
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) {
      const double d = std::hypot(x + 0.5 - 24, y + 0.5 - 32);
      const bool ring = d <= 20 && d >= 8;
      const bool square = x >= 50 && x < 60 && y >= 4 && y < 14;
      uint8_t* p = &t->rgba[(y * 64 + x) * 4];
      p[0] = static_cast<uint8_t>(x * 4);
      p[1] = static_cast<uint8_t>(y * 4);
      p[2] = 128;
      p[3] = (ring || square) ? 255 : 0;
    }
  }
  return t;
}

TEST(raster_character, OneTexturedShapePerRegionWithHoles) {
  auto img = ring_image();
  auto r = raster_character(img, {}, "ring.png");
  ASSERT_TRUE(r.ok()) << r.error;
  const Character& ch = *r.value;
  ASSERT_EQ(ch.shapes.size(), 2u);
  int with_hole = 0;
  for (const SubShape& s : ch.shapes) {
    EXPECT_TRUE(s.closed());
    EXPECT_EQ(s.fill.texture.get(), img.get());
    EXPECT_EQ(s.element, "region");
    if (s.contours.size() == 2) ++with_hole;
    // uv maps pixel coordinates to [0, 1]
    const Vec2 uv = s.fill.uv_from_point.apply(Vec2(32, 16));
    EXPECT_NEAR(uv.x(), 0.5, 1e-12);
    EXPECT_NEAR(uv.y(), 0.25, 1e-12);
  }
  EXPECT_EQ(with_hole, 1);
  EXPECT_TRUE(ch.warnings.empty());
}

TEST(raster_character, MaskSelectsFigureAndSizeMustMatch) {
  auto img = ring_image();
  std::vector<uint8_t> mask(64 * 64 * 4, 0);
  for (int y = 10; y < 30; ++y)
    for (int x = 10; x < 40; ++x) mask[(y * 64 + x) * 4 + 1] = 200;  // green = non-black
  auto r = raster_character(img, mask, "ring.png");
  ASSERT_TRUE(r.ok());
  ASSERT_EQ(r.value->shapes.size(), 1u);
  const Bounds b = r.value->shapes[0].bounds();
  EXPECT_NEAR(b.lo.x(), 10, 0.51);
  EXPECT_NEAR(b.hi.x(), 40, 0.51);
  auto bad = raster_character(img, std::vector<uint8_t>(16, 255), "ring.png");
  EXPECT_FALSE(bad.ok());
}

TEST(raster_character, OpaqueImageWithoutMaskWarns) {
  auto img = ring_image();
  for (size_t i = 3; i < img->rgba.size(); i += 4) img->rgba[i] = 255;
  auto r = raster_character(img, {}, "opaque.png");
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.value->shapes.size(), 1u);
  ASSERT_EQ(r.value->warnings.size(), 1u);
  EXPECT_NE(r.value->warnings[0].find("--mask"), std::string::npos);
}

TEST(load_character, PngFilesAndErrors) {
  auto img = ring_image();
  const std::string path = (test::temp_dir("raster") / "ring.png").string();
  ASSERT_EQ(write_png(path, Image{img->width, img->height, img->rgba}), "");
  auto r = load_character(path);
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_EQ(r.value->shapes.size(), 2u);
  auto bad_mask = load_character(path, LoadOptions{0.1, "/nonexistent/mask.png", 0.75, false, {}});
  EXPECT_FALSE(bad_mask.ok());
  const std::string junk = test::write_temp("junk.png", "\x89PNG\r\n\x1a\nnot really");
  auto j = load_character(junk);
  ASSERT_FALSE(j.ok());
  EXPECT_NE(j.error.find("junk.png"), std::string::npos);
}

// A PNG is 33 bytes of header away from declaring gigabytes: the size is checked from the
// header before anything is decoded, and the message names the file and the limit.
TEST(load_character, AnImageOverThePixelLimitIsRefusedFromItsHeader) {
  const auto png_header = [](uint32_t w, uint32_t h) {
    std::string s = "\x89PNG\r\n\x1a\n";
    s += std::string("\0\0\0\x0dIHDR", 8);
    for (uint32_t v : {w, h})
      for (int k = 3; k >= 0; --k) s += char((v >> (8 * k)) & 0xFF);
    s += std::string("\x08\x06\0\0\0", 5);
    s += std::string(4, '\0');  // CRC (stb_image does not check it)
    return s;
  };
  for (auto [w, h] : {std::pair{20000u, 100u}, std::pair{6000u, 6000u}}) {
    const std::string path = test::write_temp("huge.png", png_header(w, h));
    auto r = load_character(path);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error.find("huge.png"), std::string::npos) << r.error;
    EXPECT_NE(r.error.find(std::to_string(w) + "x" + std::to_string(h)), std::string::npos) << r.error;
    EXPECT_NE(r.error.find("8192 pixels a side and 16 million pixels"), std::string::npos) << r.error;
  }
  // Within the limit the same header is read on and fails as a truncated file instead.
  auto small = load_character(test::write_temp("small.png", png_header(64, 64)));
  ASSERT_FALSE(small.ok());
  EXPECT_EQ(small.error.find("the limit"), std::string::npos) << small.error;
}

// stb_image reads more than a character may hold; a PNM that fuzz_raster found reads outside
// its buffer in Debian 12's stb. Only PNG, JPEG, GIF and BMP reach the decoder.
TEST(decode_png, OnlyThePicturesACharacterMayHoldReachTheDecoder) {
  for (std::string_view bytes : {std::string_view("P5\n8 8\n255\n"), std::string_view("8BPS\0\1"),
                                  std::string_view("#?RADIANCE\n"), std::string_view("")}) {
    auto r = decode_png(bytes, "odd.img");
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error, "odd.img: not a PNG, JPEG, GIF or BMP image");
  }
  // A PNG's signature passes the check and fails as what it is, a truncated PNG.
  auto png = decode_png(std::string_view("\x89PNG\r\n\x1a\n", 8), "cut.png");
  ASSERT_FALSE(png.ok());
  EXPECT_EQ(png.error.find("not a PNG"), std::string::npos) << png.error;
}

TEST(load_character, CorpusChildDrawingWithMask) {
  if (!test::have_corpus()) GTEST_SKIP() << "corpus not present";
  const auto dir = test::corpus_dir() / "raster" / "animated-drawings" / "char1";
  LoadOptions o;
  o.mask_path = (dir / "mask.png").string();
  auto r = load_character((dir / "texture.png").string(), o);
  ASSERT_TRUE(r.ok()) << r.error;
  ASSERT_GE(r.value->shapes.size(), 1u);
  const SubShape& s = r.value->shapes[0];
  EXPECT_GT(s.points.size(), 50u);
  // The traced figure covers a sizeable part of the sheet.
  EXPECT_GT(std::abs(signed_area(std::span<const Vec2>(s.points.data(), static_cast<size_t>(s.contours[0].count)))),
            0.1 * r.value->width * r.value->height);
}

TEST(load_character, CorpusCutOutSheetWithRealAlpha) {
  if (!test::have_corpus()) GTEST_SKIP() << "corpus not present";
  auto r = load_character((test::corpus_dir() / "raster" / "godot-gbot" / "gBot.png").string());
  ASSERT_TRUE(r.ok()) << r.error;
  // Arm, forearm, body, head, jaw, legs: several separate cut-out parts.
  EXPECT_GE(r.value->shapes.size(), 6u);
}

}  // namespace
}  // namespace mar
