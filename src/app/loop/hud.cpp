#include "app/loop/hud.h"

#include <SDL.h>

#include <algorithm>

namespace mar {

void draw_hud(Canvas& canvas, double used_us, double budget_us, std::span<const DeviceState> devices) {
  SDL_Renderer* r = canvas.renderer();
  const int w = canvas.width() - 20;
  SDL_SetRenderDrawBlendMode(r, SDL_BLENDMODE_BLEND);
  SDL_SetRenderDrawColor(r, 0, 0, 0, 90);
  SDL_Rect bg{10, 10, w, 14};
  SDL_RenderFillRect(r, &bg);
  const double share = budget_us > 0 ? std::min(1.0, used_us / budget_us) : 1.0;
  SDL_SetRenderDrawColor(r, share < 0.5 ? 60 : 230, share < 0.8 ? 180 : 60, 60, 220);
  SDL_Rect bar{10, 10, int(w * share), 14};
  SDL_RenderFillRect(r, &bar);
  static constexpr uint8_t kColour[][3] = {{230, 170, 40},    // waiting
                                           {60, 180, 60},     // connected
                                           {220, 50, 50},     // unplugged
                                           {220, 50, 50},     // permission denied
                                           {140, 140, 140}};  // unavailable
  for (size_t i = 0; i < devices.size(); ++i) {
    const uint8_t* c = kColour[std::min(size_t(devices[i]), std::size(kColour) - 1)];
    SDL_SetRenderDrawColor(r, c[0], c[1], c[2], 230);
    SDL_Rect box{10 + int(i) * 18, 30, 14, 14};
    SDL_RenderFillRect(r, &box);
  }
}

}  // namespace mar
