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

bool x11_without_window_manager() {
  Display* d = XOpenDisplay(nullptr);
  if (!d) return false;
  bool none = true;
  if (const Atom check = XInternAtom(d, "_NET_SUPPORTING_WM_CHECK", True); check != 0) {
    Atom type = 0;
    int format = 0;
    unsigned long n = 0, after = 0;
    unsigned char* data = nullptr;
    const int rc = XGetWindowProperty(d, DefaultRootWindow(d), check, 0, 1, False, AnyPropertyType, &type, &format, &n, &after, &data);
    none = rc != Success || n == 0;
    if (data) XFree(data);
  }
  XCloseDisplay(d);
  return none;
}

}  // namespace mar
