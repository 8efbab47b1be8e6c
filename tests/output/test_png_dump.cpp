// --dump-frames off the frame thread (output/png_dump.h): what is pushed is written as
// frame_NNNNNN.png by the writer's thread, straight alpha and box-filtered like the dumps before
// it; pushing allocates nothing; on the wall clock a full ring drops (counted) and never waits; a
// folder that cannot be written is said with the file's name and later frames are counted.
#include "output/png_dump.h"
#include "alloc_counter.h"
#include "render/image.h"
#include "test_util.h"

#include <gtest/gtest.h>

namespace mar {
namespace {

TEST(PngDump, WritesEachPushedFrameFromItsOwnThread) {
  const auto dir = test::temp_dir("png_dump");
  std::vector<uint8_t> px(32 * 16 * 4);
  {
    PngDump d(dir.string(), 32, 16, 2, true, 4);  // supersampled 2x: 16x8 files
    const long before = test::allocation_count();
    for (int f = 0; f < 40; ++f) {
      for (size_t i = 0; i < px.size(); i += 4) px[i] = uint8_t(f), px[i + 1] = 0, px[i + 2] = 0, px[i + 3] = 255;
      d.push(px.data(), 32 * 4, uint64_t(f * 3), 0);
    }
    EXPECT_EQ(test::allocation_count() - before, 0) << "push allocates nothing";
    d.flush();
    EXPECT_EQ(d.written(), 40u);
    EXPECT_EQ(d.dropped(), 0u);
    EXPECT_TRUE(d.error().empty());
  }
  auto img = read_png_image((dir / "frame_000117.png").string());  // frame 39 was pushed as number 117
  ASSERT_TRUE(img.ok()) << img.error;
  EXPECT_EQ(img.value->width, 16);
  EXPECT_EQ(img.value->height, 8);
  EXPECT_EQ(img.value->rgba[0], 39);
  EXPECT_EQ(img.value->rgba[3], 255);
}

TEST(PngDump, OnTheWallClockAFullRingDropsAndAnUnwritableFolderIsSaid) {
  std::vector<uint8_t> px(256 * 256 * 4, 255);
  {
    PngDump d(test::temp_dir("png_fast").string(), 256, 256, 1, false, 2);
    for (int f = 0; f < 200; ++f) d.push(px.data(), 256 * 4, uint64_t(f), 0);  // faster than PNG encoding
    d.flush();
    EXPECT_EQ(d.written() + d.dropped(), 200u);
    EXPECT_GT(d.dropped(), 0u);
    EXPECT_EQ(d.waits(), 0u) << "the show never waits";
  }
  PngDump bad("/nonexistent-dir/frames", 8, 8, 1, true);
  for (int f = 0; f < 5; ++f) bad.push(px.data(), 8 * 4, uint64_t(f), 0);
  bad.flush();
  EXPECT_NE(bad.error().find("/nonexistent-dir/frames/frame_000000.png"), std::string::npos) << bad.error();
  EXPECT_EQ(bad.written(), 0u);
  EXPECT_EQ(bad.dropped(), 5u);
}

}  // namespace
}  // namespace mar
