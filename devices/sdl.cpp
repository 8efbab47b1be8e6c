// SDL input in window mode: the mouse and touch screens over the show window, and SDL game
// controllers (any pad SDL's controller database knows, here or over Bluetooth). State is
// read each frame and each change is a wire record (SdlControl: what, index, value, range);
// input/sdl_decoder.cpp gives them the HID usages a hidraw device would (X/Y, tip switch,
// buttons), so the same bindings work.
#include "devices/backends.h"
#include "devices/util.h"

#include <SDL.h>

#include <atomic>
#include <cstring>

namespace mar {
namespace {

std::atomic<bool> g_window{false};

class SdlBackend final : public Backend {
 public:
  SdlBackend(const DeviceSpec& s, uint16_t source) : Backend(s, source) {
    if (spec_.sdl == "gamepad" && !SDL_WasInit(SDL_INIT_GAMECONTROLLER)) SDL_InitSubSystem(SDL_INIT_GAMECONTROLLER);
  }
  ~SdlBackend() override { close(); }
  DeviceState open() override;
  void close() override {
    if (pad_) SDL_GameControllerClose(pad_);
    pad_ = nullptr;
  }
  bool poll(int64_t now_ns, WireSink& out) override;

 private:
  void put(int64_t t, SdlWhat what, int index, int32_t v, int32_t lo, int32_t hi, int32_t& last, WireSink& out) {
    if (v == last) return;
    last = v;
    emit(sdl_record(t, what, uint8_t(index), v, lo, hi, source_), out);
  }
  SDL_GameController* pad_ = nullptr;
  SDL_JoystickID id_ = -1;
  int32_t last_[64];
};

DeviceState SdlBackend::open() {
  std::memset(last_, 0x80, sizeof last_);  // nothing seen yet: every first value is reported
  config_ = DecoderConfig{};
  config_.kind = WireKind::SdlControl;
  if (spec_.sdl == "mouse" || spec_.sdl == "touch") {
    if (!g_window.load()) {
      problem_ = "the " + spec_.sdl + " is read over the show window: run with a display (not --headless)";
      return DeviceState::Unavailable;
    }
    identity_ = spec_.sdl == "mouse" ? "SDL mouse" : "SDL touch";
    problem_.clear();
    return DeviceState::Connected;
  }
  if (spec_.sdl != "gamepad") {
    problem_ = "sdl = '" + spec_.sdl + "': expected mouse, touch or gamepad";
    return DeviceState::Unavailable;
  }
  for (int i = 0; i < SDL_NumJoysticks(); ++i) {
    if (!SDL_IsGameController(i)) continue;
    const char* name = SDL_GameControllerNameForIndex(i);
    if (!spec_.product.empty() && (!name || !std::strstr(name, spec_.product.c_str()))) continue;
    if (spec_.vid >= 0 && SDL_JoystickGetDeviceVendor(i) != spec_.vid) continue;
    if (spec_.pid >= 0 && SDL_JoystickGetDeviceProduct(i) != spec_.pid) continue;
    if (!(pad_ = SDL_GameControllerOpen(i))) continue;
    id_ = SDL_JoystickInstanceID(SDL_GameControllerGetJoystick(pad_));
    identity_ = std::string("SDL game controller '") + (name ? name : "?") + "'";
    problem_.clear();
    return DeviceState::Connected;
  }
  problem_ = "no game controller" + (spec_.product.empty() ? std::string() : " named '" + spec_.product + "'");
  return DeviceState::Waiting;
}

bool SdlBackend::poll(int64_t t, WireSink& out) {
  if (pad_) {
    SDL_GameControllerUpdate();
    if (!SDL_GameControllerGetAttached(pad_)) return false;
    for (int a = 0; a < SDL_CONTROLLER_AXIS_MAX; ++a) {
      const bool trigger = a >= SDL_CONTROLLER_AXIS_TRIGGERLEFT;
      put(t, SdlWhat::PadAxis, a, SDL_GameControllerGetAxis(pad_, SDL_GameControllerAxis(a)), trigger ? 0 : -32768, 32767,
          last_[a], out);
    }
    for (int b = 0; b < SDL_CONTROLLER_BUTTON_MAX; ++b)
      put(t, SdlWhat::PadButton, b, SDL_GameControllerGetButton(pad_, SDL_GameControllerButton(b)), 0, 1, last_[8 + b], out);
    return true;
  }
  if (!g_window.load()) return false;
  if (spec_.sdl == "mouse") {
    SDL_Window* w = SDL_GetMouseFocus();
    if (!w) return true;
    int x = 0, y = 0, ww = 1, wh = 1;
    const uint32_t buttons = SDL_GetMouseState(&x, &y);
    SDL_GetWindowSize(w, &ww, &wh);
    put(t, SdlWhat::MouseX, 0, x, 0, ww - 1, last_[0], out);
    put(t, SdlWhat::MouseY, 0, y, 0, wh - 1, last_[1], out);
    put(t, SdlWhat::MouseButton, 0, (buttons & SDL_BUTTON_LMASK) != 0, 0, 1, last_[2], out);
    put(t, SdlWhat::MouseButton, 1, (buttons & SDL_BUTTON_RMASK) != 0, 0, 1, last_[3], out);
    return true;
  }
  if (SDL_GetNumTouchDevices() == 0) return true;
  const SDL_TouchID id = SDL_GetTouchDevice(0);
  const int fingers = SDL_GetNumTouchFingers(id);
  if (fingers > 0)
    if (SDL_Finger* f = SDL_GetTouchFinger(id, 0)) {
      put(t, SdlWhat::TouchX, 0, int32_t(f->x * 65535), 0, 65535, last_[0], out);
      put(t, SdlWhat::TouchY, 0, int32_t(f->y * 65535), 0, 65535, last_[1], out);
    }
  put(t, SdlWhat::Touching, 0, fingers > 0, 0, 1, last_[2], out);
  return true;
}

}  // namespace

void sdl_input_window(bool open) { g_window = open; }

std::unique_ptr<Backend> make_sdl_backend(const DeviceSpec& s, uint16_t source) {
  return std::make_unique<SdlBackend>(s, source);
}

BackendReport discover_sdl(const std::vector<ProfileId>&) {
  BackendReport r{"sdl", "ok", {}};
  if (SDL_InitSubSystem(SDL_INIT_GAMECONTROLLER) != 0) return {"sdl", std::string("SDL: ") + SDL_GetError(), {}};
  for (int i = 0; i < SDL_NumJoysticks(); ++i) {
    if (!SDL_IsGameController(i)) continue;
    FoundDevice f;
    f.backend = "sdl";
    const char* name = SDL_GameControllerNameForIndex(i);
    f.identity = devutil::vid_pid(SDL_JoystickGetDeviceVendor(i), SDL_JoystickGetDeviceProduct(i)) + " game controller '" +
                 (name ? name : "?") + "'";
    f.status = "available";
    r.found.push_back(f);
  }
  SDL_QuitSubSystem(SDL_INIT_GAMECONTROLLER);
  return r;
}

}  // namespace mar
