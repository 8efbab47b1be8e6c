// x_capture OUT.png: the X display's root window ($DISPLAY), as the screen shows it, into a PNG
// (what a kiosk visitor sees; the kiosk tests judge its pixels, not the program's log).
#include <X11/Xlib.h>
#include <X11/Xutil.h>
#include <stb/stb_image_write.h>

#include <cstdio>
#include <vector>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: x_capture OUT.png\n");
    return 2;
  }
  Display* d = XOpenDisplay(nullptr);
  if (!d) {
    std::fprintf(stderr, "x_capture: no X display\n");
    return 1;
  }
  const Window root = DefaultRootWindow(d);
  XWindowAttributes a{};
  XGetWindowAttributes(d, root, &a);
  XImage* img = XGetImage(d, root, 0, 0, unsigned(a.width), unsigned(a.height), AllPlanes, ZPixmap);
  if (!img) {
    std::fprintf(stderr, "x_capture: cannot read the screen\n");
    return 1;
  }
  std::vector<unsigned char> rgb(size_t(a.width) * size_t(a.height) * 3);
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const unsigned long p = XGetPixel(img, x, y);
      unsigned char* o = &rgb[(size_t(y) * size_t(a.width) + size_t(x)) * 3];
      o[0] = (unsigned char)((p & img->red_mask) >> 16);
      o[1] = (unsigned char)((p & img->green_mask) >> 8);
      o[2] = (unsigned char)(p & img->blue_mask);
    }
  XDestroyImage(img);
  XCloseDisplay(d);
  return stbi_write_png(argv[1], a.width, a.height, 3, rgb.data(), a.width * 3) ? 0 : 1;
}
