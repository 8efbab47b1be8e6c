# Cross-building for 64-bit ARM (a Raspberry Pi 4 or 5 on Debian 12 or Raspberry Pi OS) on a
# Debian x86-64 machine: Debian's cross compiler (crossbuild-essential-arm64) and the :arm64
# development packages installed beside the native ones (multiarch). `bash cmake/run.sh arm64`
# installs both, builds with this file and runs the tests under qemu-user.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
# Multiarch: the arm64 libraries and their CMake and pkg-config files are in
# /usr/lib/aarch64-linux-gnu, the headers shared in /usr/include.
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)
# aarch64-pkgconfig/ holds what a -dev package that is not co-installable would give.
set(ENV{PKG_CONFIG_LIBDIR}
    "/usr/lib/aarch64-linux-gnu/pkgconfig:/usr/share/pkgconfig:${CMAKE_CURRENT_LIST_DIR}/aarch64-pkgconfig")
set(ENV{PKG_CONFIG_PATH} "")
# Test executables (and gtest's discovery at build time) run through the emulator.
find_program(MARIONETTE_QEMU_AARCH64 NAMES qemu-aarch64-static qemu-aarch64 REQUIRED)
set(CMAKE_CROSSCOMPILING_EMULATOR "${MARIONETTE_QEMU_AARCH64}")
# Never pick an x86-64 library by mistake.
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
