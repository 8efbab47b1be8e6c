#!/usr/bin/env bash
# One entry point for a fresh Debian 12 machine:
#   bash cmake/run.sh demo   -- install what is missing, build, run the demo (window or PNG files)
#   bash cmake/run.sh test   -- install what is missing, build, run all tests (plain + ASan/UBSan)
#   bash cmake/run.sh bench  -- build and run the benchmarks
#   bash cmake/run.sh fuzz   -- build the libFuzzer harnesses (clang) and run each for long
#                               (FUZZ_SECONDS each, default 600, or 10 million executions)
#   bash cmake/run.sh soak   -- 1,000,000 frames of every simulated device, 1,000 replugs per
#                               backend class, 1,000,000 extreme target sets per rig
#   bash cmake/run.sh tsan   -- the device and live-loop tests under ThreadSanitizer (clang)
#   bash cmake/run.sh arm64  -- cross-build for 64-bit ARM (a Raspberry Pi), run the tests that
#                               need no device under qemu-user and compare the shows' run_hash
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
JOBS=${JOBS:-$(nproc)}

PACKAGES=(cmake g++ pkg-config
  libsdl2-dev libsdl2-image-dev libsdl2-ttf-dev fonts-dejavu-core libfreetype-dev libfontconfig-dev libharfbuzz-dev libx11-dev librsvg2-dev libstb-dev libcgal-dev libeigen3-dev libtomlplusplus-dev
  libcli11-dev libspdlog-dev libpugixml-dev libgtest-dev libbenchmark-dev nlohmann-json3-dev
  libgpiod-dev gpiod libhidapi-dev libusb-1.0-0-dev umockdev libumockdev-dev
  libevdev-dev liblo-dev librtmidi-dev libasound2-dev libsystemd-dev xvfb xauth xdotool openbox espeak-ng
  libpipewire-0.3-dev pipewire wireplumber dbus gstreamer1.0-pipewire gstreamer1.0-tools gstreamer1.0-plugins-good
  libavcodec-dev libavformat-dev libavutil-dev libswscale-dev ffmpeg liblo-tools
  clang libclang-rt-14-dev python3
  openclipart-svg librsvg2-bin)

install_deps() {
  # Installed for this machine's architecture: `bash cmake/run.sh arm64` may have put the arm64
  # build of a -dev package in place of the native one.
  local missing=() arch
  arch=$(dpkg --print-architecture)
  for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status} ${Architecture}\n' "$p" 2>/dev/null | grep -qE "^install ok installed ($arch|all)$" ||
      missing+=("$p:$arch")
  done
  apt_install "${missing[@]}"
}

apt_install() { # packages (the missing ones; none: nothing to do)
  [ $# -eq 0 ] && return 0
  if [ "$(id -u)" -ne 0 ]; then
    echo "missing Debian packages: $*" >&2
    echo "run as root, or: sudo apt-get install -y $*" >&2
    exit 1
  fi
  echo "installing: $*"
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "$@" >/dev/null
}

# The arm64 libraries beside the native ones (Debian multiarch), the cross compiler and qemu-user.
ARM64_PACKAGES=(libsdl2-dev libsdl2-ttf-dev libfreetype-dev libfontconfig-dev libharfbuzz-dev libx11-dev libstb-dev libcgal-dev libtomlplusplus-dev libspdlog-dev
  libpugixml-dev libgtest-dev libgpiod-dev libhidapi-dev libusb-1.0-0-dev libevdev-dev
  liblo7 libasound2-dev libsystemd-dev libpipewire-0.3-dev libavcodec-dev libavformat-dev libavutil-dev
  libswscale-dev)
install_arm64_deps() {
  local missing=()
  for p in crossbuild-essential-arm64 qemu-user-static file "${ARM64_PACKAGES[@]/%/:arm64}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ] && [ "$(id -u)" -eq 0 ]; then
    dpkg --print-foreign-architectures | grep -qx arm64 || dpkg --add-architecture arm64
  fi
  apt_install "${missing[@]}"
}

# Lets the kernel start an arm64 program by itself through qemu (the tests that start
# ./marionette or re-execute themselves need it); nothing happens where it cannot be done.
register_binfmt() {
  local conf=/usr/lib/binfmt.d/qemu-aarch64.conf dir=/proc/sys/fs/binfmt_misc
  [ -e "$dir/qemu-aarch64" ] && return 0
  [ "$(id -u)" -eq 0 ] && [ -r "$conf" ] || return 0
  [ -e "$dir/register" ] || mount -t binfmt_misc binfmt_misc "$dir" 2>/dev/null || return 0
  grep -v '^#' "$conf" > "$dir/register" 2>/dev/null || true
}

build() { # dir, target ('all' for everything), extra cmake args...
  local dir=$1 target=$2; shift 2
  cmake -S "$ROOT" -B "$dir" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
  cmake --build "$dir" -j "$JOBS" --target "$target"
}

# The checked build, in build-sanitize/: clang with ASan and UBSan, and libFuzzer's coverage
# everywhere, so one compilation serves both the sanitizer test suite and the fuzz harnesses.
# The library at -O2 with line tables (stack traces name the line; at -O1 the sanitized suite
# ran 2.5 times longer), the test code at -O1 (tests/CMakeLists.txt). A folder configured with
# another compiler starts over.
build_checked() { # target
  local dir=$ROOT/build-sanitize
  if [ -f "$dir/CMakeCache.txt" ] && ! grep -q '^CMAKE_CXX_COMPILER:.*clang++' "$dir/CMakeCache.txt"; then
    rm -rf "$dir"
  fi
  CC=clang CXX=clang++ cmake -S "$ROOT" -B "$dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -gline-tables-only" \
    -DMARIONETTE_SANITIZE=ON -DMARIONETTE_FUZZ=ON -DMARIONETTE_BUILD_TESTS=ON -DMARIONETTE_BUILD_BENCH=OFF >/dev/null
  cmake --build "$dir" -j "$JOBS" --target "$1"
}

cmd=${1:-}
case "$cmd" in
  demo)
    install_deps
    # Builds only the program; the folder's test and benchmark settings are left as they
    # are, so demo and test share build/ in either order.
    build "$ROOT/build" marionette
    cd "$ROOT/build" && exec ./marionette run "$ROOT/config/shows/demo.toml"
    ;;
  test)
    install_deps
    # Tests are switched on explicitly (a folder configured otherwise is corrected), and a
    # ctest that finds no test fails.
    build "$ROOT/build" all -DMARIONETTE_BUILD_TESTS=ON -DMARIONETTE_BUILD_BENCH=ON
    (cd "$ROOT/build" && ctest --output-on-failure --no-tests=error -j "$JOBS")
    build_checked all
    (cd "$ROOT/build-sanitize" && ctest --output-on-failure --no-tests=error -j "$JOBS" -LE measure)
    # Every parser of outside input under libFuzzer for a short while (and its regression inputs).
    JOBS=$JOBS bash "$ROOT/tests/fuzz/run.sh" "$ROOT/build-sanitize" "${FUZZ_SECONDS:-20}"
    ;;
  fuzz)
    install_deps
    build_checked fuzzers
    # A campaign: one harness at a time, in libFuzzer's fork mode on every core.
    RUNS=${RUNS:-10000000} FORK=${FORK:-$JOBS} JOBS=1 bash "$ROOT/tests/fuzz/run.sh" "$ROOT/build-sanitize" "${FUZZ_SECONDS:-600}" "${@:2}"
    ;;
  soak)
    install_deps
    build "$ROOT/build" all -DMARIONETTE_BUILD_TESTS=ON -DMARIONETTE_BUILD_BENCH=ON
    bash "$ROOT/tests/tools/soak.sh" "$ROOT/build" "${SOAK_FRAMES:-1000000}"
    ;;
  tsan)
    install_deps
    CC=clang CXX=clang++ cmake -S "$ROOT" -B "$ROOT/build-tsan" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMARIONETTE_TSAN=ON \
      -DMARIONETTE_BUILD_TESTS=ON -DMARIONETTE_BUILD_BENCH=OFF >/dev/null
    cmake --build "$ROOT/build-tsan" -j "$JOBS" --target test_devices test_live test_app_loop marionette
    # ignore_noninstrumented_modules: glib (umockdev's bench thread) synchronises with futexes
    # ThreadSanitizer cannot see, so its own strlen/memcpy calls looked like races; accesses in
    # our (instrumented) code are all still checked, and so is every pthread lock.
    export TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1 ignore_noninstrumented_modules=1 ${TSAN_OPTIONS:-}"
    "$ROOT/build-tsan/tests/test_devices"
    "$ROOT/build-tsan/tests/test_app_loop"
    "$ROOT/build-tsan/tests/test_live" --gtest_filter='Live.*:LiveAttract.*:LiveRandom.*'
    ;;
  arm64)
    install_deps
    install_arm64_deps
    register_binfmt
    # The x86-64 program, for the run_hash comparison.
    build "$ROOT/build" marionette
    # The program and the tests that run under qemu (tests/tools/arm64_test.sh), without the
    # virtual bench: Debian 12's libumockdev-dev cannot be installed for two architectures at
    # once, and the native one is the test command's (liblo-dev neither: the toolchain's
    # aarch64-pkgconfig/ links the arm64 liblo7 with the native headers). Tests are discovered when ctest runs,
    # not while building (that would start each under qemu).
    cmake -S "$ROOT" -B "$ROOT/build-arm64" -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_TOOLCHAIN_FILE="$ROOT/cmake/toolchains/aarch64-linux-gnu.cmake" -DMARIONETTE_WITH_VBENCH=OFF \
      -DMARIONETTE_BUILD_TESTS=ON -DMARIONETTE_BUILD_BENCH=OFF -DCMAKE_GTEST_DISCOVER_TESTS_DISCOVERY_MODE=PRE_TEST >/dev/null
    cmake --build "$ROOT/build-arm64" -j "$JOBS" --target marionette $(bash "$ROOT/tests/tools/arm64_test.sh" --targets)
    bash "$ROOT/tests/tools/arm64_test.sh" "$ROOT/build" "$ROOT/build-arm64"
    ;;
  bench)
    install_deps
    build "$ROOT/build" all -DMARIONETTE_BUILD_BENCH=ON
    # bench_render measures the OpenGL window too: under Xvfb (Mesa) when there is no display.
    for b in "$ROOT"/build/tests/bench/bench_*; do
      if [ "$(basename "$b")" = bench_render ] && [ -z "${DISPLAY:-}" ] && command -v xvfb-run >/dev/null; then
        xvfb-run -a -s '-screen 0 1920x1080x24' "$b"
      else
        "$b"
      fi
    done
    ;;
  *)
    echo "usage: bash cmake/run.sh demo|test|bench|fuzz|soak|tsan|arm64" >&2
    exit 2
    ;;
esac
