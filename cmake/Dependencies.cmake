# Every third-party library is an installed Debian package (see README and cmake/run.sh).
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(SDL2 REQUIRED)
find_package(pugixml REQUIRED)
find_package(CLI11 REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
find_package(tomlplusplus REQUIRED)
find_package(PkgConfig REQUIRED)
pkg_check_modules(STB REQUIRED IMPORTED_TARGET stb)
# SVG text: fonts as fontconfig picks them, shaped by HarfBuzz, outlines from FreeType.
pkg_check_modules(FONTS REQUIRED IMPORTED_TARGET freetype2 fontconfig harfbuzz)
# Text on the performer's overlays (the HUD), with a font from fonts-dejavu-core.
pkg_check_modules(SDL2TTF REQUIRED IMPORTED_TARGET SDL2_ttf)
# A transparent window on X11 needs an ARGB visual, found with Xlib before SDL opens the window.
pkg_check_modules(X11 REQUIRED IMPORTED_TARGET x11)
# systemd's notify and watchdog protocol (a show run as a service: src/app/loop/service.h).
pkg_check_modules(SYSTEMD REQUIRED IMPORTED_TARGET libsystemd)
# Device libraries: the real ones, each only when its backend is built (devices/).
if(MARIONETTE_WITH_USB_MIDI)
  pkg_check_modules(LIBUSB REQUIRED IMPORTED_TARGET libusb-1.0)
endif()
if(MARIONETTE_WITH_HID)
  pkg_check_modules(HIDAPI REQUIRED IMPORTED_TARGET hidapi-hidraw)
endif()
if(MARIONETTE_WITH_GPIO)
  pkg_check_modules(GPIOD REQUIRED IMPORTED_TARGET libgpiod)
endif()
if(MARIONETTE_WITH_TABLET)
  pkg_check_modules(EVDEV REQUIRED IMPORTED_TARGET libevdev)
endif()
if(MARIONETTE_WITH_ALSA)
  pkg_check_modules(ALSA REQUIRED IMPORTED_TARGET alsa)
endif()
# The virtual bench (marionette-simulate and the device tests); never the shipping program.
if(MARIONETTE_WITH_VBENCH)
  pkg_check_modules(UMOCKDEV REQUIRED IMPORTED_TARGET umockdev-1.0)
endif()
find_package(Threads REQUIRED)

# CGAL is used in exactly one translation unit (src/geom/triangulate.cpp).
set(CGAL_DO_NOT_WARN_ABOUT_CMAKE_BUILD_TYPE TRUE)
find_package(CGAL REQUIRED)

# liblo sends OSC out ([osc_out]: src/output/osc_out.h) and the OSC test messages (the OSC
# backend parses OSC itself: liblo's parser allocates and its pattern matcher backtracks
# exponentially).
pkg_check_modules(LIBLO REQUIRED IMPORTED_TARGET liblo)
if(MARIONETTE_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
if(MARIONETTE_BUILD_BENCH)
  find_package(benchmark REQUIRED)
endif()
# PipeWire video out ([output] pipewire = true: src/output/pipewire_out.h).
if(MARIONETTE_WITH_PIPEWIRE)
  pkg_check_modules(PIPEWIRE REQUIRED IMPORTED_TARGET libpipewire-0.3)
endif()
# Video takes (run/replay --video: src/output/video_out.h).
if(MARIONETTE_WITH_VIDEO)
  pkg_check_modules(LIBAV REQUIRED IMPORTED_TARGET libavcodec libavformat libavutil libswscale)
endif()
