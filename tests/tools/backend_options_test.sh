#!/usr/bin/env bash
# Each backend is a CMake option: configure a build with some left out, build only the
# device layer's table test there and check that the left-out ones say "not built".
set -euo pipefail
src=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
cmake -S "$src" -B "$dir" -DCMAKE_BUILD_TYPE=Release -DMARIONETTE_BUILD_BENCH=OFF \
  -DMARIONETTE_WITH_HID=OFF -DMARIONETTE_WITH_GPIO=OFF -DMARIONETTE_WITH_OSC=OFF >/dev/null
cmake --build "$dir" --target test_backend_table -j 2 >/dev/null
MARIONETTE_EXPECT_NOT_BUILT=hid,gpio,osc "$dir/tests/test_backend_table"
