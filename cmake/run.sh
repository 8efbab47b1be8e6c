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
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
JOBS=${JOBS:-$(nproc)}

PACKAGES=(cmake g++ pkg-config
  libsdl2-dev libsdl2-image-dev libsdl2-ttf-dev fonts-dejavu-core libx11-dev librsvg2-dev libstb-dev libcgal-dev libeigen3-dev libtomlplusplus-dev
  libcli11-dev libspdlog-dev libpugixml-dev libgtest-dev libbenchmark-dev nlohmann-json3-dev
  libgpiod-dev gpiod libhidapi-dev libusb-1.0-0-dev umockdev libumockdev-dev
  libevdev-dev liblo-dev librtmidi-dev libasound2-dev libsystemd-dev xvfb xauth xdotool espeak-ng
  libpipewire-0.3-dev pipewire wireplumber dbus gstreamer1.0-pipewire gstreamer1.0-tools gstreamer1.0-plugins-good
  libavcodec-dev libavformat-dev libavutil-dev libswscale-dev ffmpeg liblo-tools
  clang libclang-rt-14-dev python3)

install_deps() {
  local missing=()
  for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  if [ "$(id -u)" -ne 0 ]; then
    echo "missing Debian packages: ${missing[*]}" >&2
    echo "run as root, or: sudo apt-get install -y ${missing[*]}" >&2
    exit 1
  fi
  echo "installing: ${missing[*]}"
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

build() { # dir, target ('all' for everything), extra cmake args...
  local dir=$1 target=$2; shift 2
  cmake -S "$ROOT" -B "$dir" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
  cmake --build "$dir" -j "$JOBS" --target "$target"
}

build_fuzz() { # the harnesses: clang, libFuzzer, ASan+UBSan, in build-fuzz/
  CC=clang CXX=clang++ cmake -S "$ROOT" -B "$ROOT/build-fuzz" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMARIONETTE_FUZZ=ON \
    -DMARIONETTE_BUILD_TESTS=OFF -DMARIONETTE_BUILD_BENCH=OFF >/dev/null
  cmake --build "$ROOT/build-fuzz" -j "$JOBS" --target fuzzers
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
    build "$ROOT/build-asan" all -DMARIONETTE_BUILD_TESTS=ON -DMARIONETTE_SANITIZE=ON -DMARIONETTE_BUILD_BENCH=OFF
    (cd "$ROOT/build-asan" && ctest --output-on-failure --no-tests=error -j "$JOBS" -LE measure)
    # Every parser of outside input under libFuzzer for a short while (and its regression inputs).
    build_fuzz
    JOBS=$JOBS bash "$ROOT/tests/fuzz/run.sh" "$ROOT/build-fuzz" "${FUZZ_SECONDS:-20}"
    ;;
  fuzz)
    install_deps
    build_fuzz
    RUNS=${RUNS:-10000000} JOBS=$JOBS bash "$ROOT/tests/fuzz/run.sh" "$ROOT/build-fuzz" "${FUZZ_SECONDS:-600}" "${@:2}"
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
    echo "usage: bash cmake/run.sh demo|test|bench|fuzz|soak|tsan" >&2
    exit 2
    ;;
esac
