#include "app/loop/hud.h"

#include <gtest/gtest.h>

namespace mar {
namespace {

// Premultiplied RGBA of pixel (x, y).
std::array<int, 4> pixel(Canvas& c, int x, int y) {
  const auto px = c.read_premultiplied();
  const size_t i = (size_t(y) * size_t(c.width()) + size_t(x)) * 4;
  return {px[i], px[i + 1], px[i + 2], px[i + 3]};
}

TEST(Hud, TheBudgetBarAndDeviceBoxesShowWhatTheyReport) {
  auto c = Canvas::offscreen(200, 60);
  ASSERT_TRUE(c.ok()) << c.error;
  Canvas& canvas = **c.value;
  canvas.clear(Rgba{255, 255, 255, 255});
  const DeviceState states[] = {DeviceState::Connected, DeviceState::Unplugged, DeviceState::Unavailable};
  draw_hud(canvas, 0.9 * 16666, 16666, states);  // 90 % of the budget: a red bar
  const auto bar = pixel(canvas, 12, 15), rest = pixel(canvas, 182, 15);  // bar ends at 10 + 0.9 x 180
  EXPECT_GT(bar[0], bar[1] + 60) << "over 80 % is red";
  EXPECT_LT(rest[0], 255) << "the bar's background is drawn";
  const auto ok = pixel(canvas, 15, 36), gone = pixel(canvas, 33, 36), grey = pixel(canvas, 51, 36);
  EXPECT_GT(ok[1], ok[0] + 60) << "connected is green";
  EXPECT_GT(gone[0], gone[1] + 100) << "unplugged is red";
  EXPECT_LT(std::abs(grey[0] - grey[1]), 10) << "unavailable is grey";
  canvas.clear(Rgba{255, 255, 255, 255});
  draw_hud(canvas, 0.1 * 16666, 16666, {});
  const auto low = pixel(canvas, 12, 15), unused = pixel(canvas, 100, 15);
  EXPECT_GT(low[1], low[0] + 60) << "under half the budget is green";
  EXPECT_LT(unused[1], low[1]) << "the bar is 10 % long";
}

}  // namespace
}  // namespace mar
