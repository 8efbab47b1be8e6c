// X11's part of a transparent window (kept apart: Xlib's headers define None, Bool, Status...).
#pragma once

struct SDL_Window;

namespace mar {

/// The id of an ARGB visual (depth 32, TrueColor) on the X display, for a window with an alpha
/// channel; 0 when there is no X display or it has none.
unsigned long x11_argb_visual();

/// The depth of an SDL window's X visual (32: it has an alpha channel); 0 when not on X11.
int x11_window_depth(SDL_Window* w);

/// Whether the X display ($DISPLAY) has no window manager (none has set the root's
/// _NET_SUPPORTING_WM_CHECK): nothing there turns a window fullscreen. False without X.
bool x11_without_window_manager();

}  // namespace mar
