#include "render/x11_visual.h"

#include <SDL2/SDL_syswm.h>
#include <X11/Xlib.h>
#include <X11/Xutil.h>

namespace mar {

unsigned long x11_argb_visual() {
  Display* d = XOpenDisplay(nullptr);
  if (!d) return 0;
  XVisualInfo vi{};
  const unsigned long id = XMatchVisualInfo(d, DefaultScreen(d), 32, TrueColor, &vi) ? vi.visualid : 0;
  XCloseDisplay(d);
  return id;
}

int x11_window_depth(SDL_Window* w) {
  SDL_SysWMinfo info;
  SDL_VERSION(&info.version);
  if (!SDL_GetWindowWMInfo(w, &info) || info.subsystem != SDL_SYSWM_X11) return 0;
  XWindowAttributes a{};
  if (!XGetWindowAttributes(info.info.x11.display, info.info.x11.window, &a)) return 0;
  return a.depth;
}

}  // namespace mar
