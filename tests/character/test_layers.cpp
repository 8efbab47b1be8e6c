// A folder of PNG layers is a character, one textured part per layer: paint order from
// layers.toml or the file names, names from the files, and every bad layer (missing, unreadable,
// too big, another size, empty) left out with a warning naming its file.
#include "character/load.h"
#include "character/raster_loader.h"
#include "render/image.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace mar {
namespace {

namespace fs = std::filesystem;

// A w x h layer with an opaque disc (or nothing) at (cx, cy).
void write_layer(const fs::path& file, int w, int h, double cx, double cy, double r) {
  Image im{w, h, std::vector<std::uint8_t>(size_t(w) * size_t(h) * 4, 0)};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if ((x + 0.5 - cx) * (x + 0.5 - cx) + (y + 0.5 - cy) * (y + 0.5 - cy) < r * r) {
        std::uint8_t* p = &im.rgba[(size_t(y) * size_t(w) + size_t(x)) * 4];
        p[0] = 200, p[1] = 100, p[2] = 50, p[3] = 255;
      }
  ASSERT_EQ(write_png(file.string(), im), "");
}

std::string warnings_of(const Character& ch) {
  std::string all;
  for (const std::string& w : ch.warnings) all += w + "\n";
  return all;
}

TEST(Layers, TheOwlLoadsOnePartPerLayerInTheFilesOrder) {
  auto ch = load_character((test::characters_dir() / "owl").string());
  ASSERT_TRUE(ch.ok()) << ch.error;
  const Character& c = *ch.value;
  EXPECT_EQ(c.width, 300);
  EXPECT_EQ(c.height, 360);
  std::vector<std::string> ids;
  for (const SubShape& s : c.shapes) {
    ids.push_back(s.id);
    EXPECT_TRUE(s.fill.texture) << s.id;
    EXPECT_TRUE(s.closed()) << s.id;
  }
  EXPECT_EQ(ids, (std::vector<std::string>{"wing-left", "wing-right", "foot-left", "foot-right", "body", "ear-left", "ear-right", "head"}));
  EXPECT_EQ(c.layers.size(), 8u);
  EXPECT_TRUE(c.warnings.empty()) << warnings_of(c);
}

// layers.toml gives the order; numbers in names sort by value (9 before 10).
TEST(Layers, LayersTomlOrdersThemAndNumbersSortByValue) {
  const auto dir = test::temp_dir("layers-order");
  write_layer(dir / "10-a.png", 40, 30, 10, 15, 8);
  write_layer(dir / "9-b.png", 40, 30, 20, 15, 8);
  auto ch = load_character(dir.string());
  ASSERT_TRUE(ch.ok()) << ch.error;
  ASSERT_EQ(ch.value->shapes.size(), 2u);
  EXPECT_EQ(ch.value->shapes[0].id, "b");
  EXPECT_EQ(ch.value->shapes[1].id, "a");
  std::ofstream(dir / "layers.toml") << "order = [\"10-a.png\", \"9-b.png\"]\n";
  ch = load_character(dir.string());
  ASSERT_TRUE(ch.ok()) << ch.error;
  EXPECT_EQ(ch.value->shapes[0].id, "a");
  EXPECT_EQ(ch.value->shapes[1].id, "b");
  std::ofstream(dir / "layers.toml") << "order = [\"../x.png\"]\n";
  ch = load_character(dir.string());
  ASSERT_FALSE(ch.ok());
  EXPECT_NE(ch.error.find("layers.toml"), std::string::npos) << ch.error;
}

// Bad layers are left out, each with a warning naming its file; the rest still performs.
TEST(Layers, BadLayersAreLeftOutWithTheirNames) {
  const auto dir = test::temp_dir("layers-bad");
  write_layer(dir / "10-good.png", 40, 30, 20, 15, 8);
  write_layer(dir / "20-empty.png", 40, 30, 0, 0, 0);
  write_layer(dir / "30-other-size.png", 50, 30, 20, 15, 8);
  std::ofstream(dir / "40-garbage.png") << "this is not a PNG";
  // a header that declares 9000 x 9000 pixels: refused before anything is decoded
  {
    const unsigned char png[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R',
                                 0, 0, 0x23, 0x28, 0, 0, 0x23, 0x28, 8, 6, 0, 0, 0, 0, 0, 0, 0};
    std::ofstream(dir / "50-huge.png", std::ios::binary).write(reinterpret_cast<const char*>(png), sizeof png);
  }
  auto ch = load_character(dir.string());
  ASSERT_TRUE(ch.ok()) << ch.error;
  ASSERT_EQ(ch.value->shapes.size(), 1u);
  EXPECT_EQ(ch.value->shapes[0].id, "good");
  const std::string w = warnings_of(*ch.value);
  for (const char* name : {"20-empty.png", "30-other-size.png", "40-garbage.png", "50-huge.png"})
    EXPECT_NE(w.find(name), std::string::npos) << name << " not named in:\n" << w;
  EXPECT_NE(w.find("50x30"), std::string::npos) << w;
  // a layer layers.toml names that is not there
  std::ofstream(dir / "layers.toml") << "order = [\"10-good.png\", \"60-missing.png\"]\n";
  ch = load_character(dir.string());
  ASSERT_TRUE(ch.ok()) << ch.error;
  EXPECT_NE(warnings_of(*ch.value).find("60-missing.png"), std::string::npos) << warnings_of(*ch.value);
}

TEST(Layers, AFolderWithNoUsableLayerIsAnError) {
  const auto empty = test::temp_dir("layers-none");
  auto ch = load_character(empty.string());
  ASSERT_FALSE(ch.ok());
  EXPECT_NE(ch.error.find("no PNG layers"), std::string::npos) << ch.error;
  const auto bad = test::temp_dir("layers-all-bad");
  write_layer(bad / "1-empty.png", 20, 20, 0, 0, 0);
  ch = load_character(bad.string());
  ASSERT_FALSE(ch.ok());
  EXPECT_NE(ch.error.find("1-empty.png"), std::string::npos) << ch.error;
  auto masked = load_character((test::characters_dir() / "owl").string(), LoadOptions{0.1, "mask.png", 0.75, false, {}});
  EXPECT_FALSE(masked.ok());
}

}  // namespace
}  // namespace mar
