#!/usr/bin/env bash
# The arm64 build under qemu-user (bash cmake/run.sh arm64): the named test subset, then the
# shows headless, whose run_hash must equal the x86-64 build's frame for frame.
#   tests/tools/arm64_test.sh NATIVE_BUILD ARM64_BUILD
#   tests/tools/arm64_test.sh --targets      (the test programs it runs, for the build)
set -euo pipefail

# The solvers, the decoders and the rest of the engine that needs no device, window or
# subprocess. The test programs that start ./marionette or re-execute themselves (the CLI,
# live-loop and device tests) need the kernel to start an arm64 program by itself
# (binfmt_misc): they run when it is registered and are named as skipped when it is not.
subset=(test_geom test_character test_render test_frame test_solve test_solve_alloc test_motion
        test_interp test_input test_firmware_sim test_backend_table)
needs_binfmt=(test_app_loop)
if [ "${1:-}" = --targets ]; then
  echo "${subset[@]}" "${needs_binfmt[@]}"
  exit 0
fi
native=$1 arm=$2
root=$(cd "$(dirname "$0")/../.." && pwd)
qemu=$(command -v qemu-aarch64-static || command -v qemu-aarch64)
file "$arm/marionette" | grep -q aarch64 || { echo "$arm/marionette is not an aarch64 program" >&2; exit 1; }
binfmt=no
if [ -r /proc/sys/fs/binfmt_misc/qemu-aarch64 ] && grep -q enabled /proc/sys/fs/binfmt_misc/qemu-aarch64; then
  binfmt=yes
fi
failed=()
for t in "${subset[@]}"; do
  echo "== $t (arm64, qemu-user)"
  "$qemu" "$arm/tests/$t" --gtest_brief=1 || failed+=("$t")
done
for t in "${needs_binfmt[@]}"; do
  if [ "$binfmt" = yes ]; then
    echo "== $t (arm64, qemu-user through binfmt_misc)"
    "$arm/tests/$t" --gtest_brief=1 || failed+=("$t")
  else
    echo "== $t skipped: it starts arm64 programs itself, and binfmt_misc has no qemu-aarch64 here"
  fi
done

# The same show gives the same run_hash on both architectures.
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
hash_of() { # program show -> run_hash
  local exe=$1 show=$2 out
  out=$("${@:3}" "$exe" run "$show" --headless --frames 600 --stats "$work/stats.json" 2>"$work/err") || {
    cat "$work/err" >&2; return 1; }
  # A show with hardware devices runs on the wall clock: its run_hash differs from run to run
  # on one machine too, so it is only played, not compared.
  python3 -c 'import json,sys; j=json.load(open(sys.argv[1])); print(j["run_hash"] if j["clock"]["mode"] == "virtual" else "wall-clock")' "$work/stats.json"
}
mismatch=0
for f in "$root"/config/shows/*.toml; do
  show=$(basename "$f" .toml)
  a=$(hash_of "$native/marionette" "$f") || { failed+=("show $show (x86-64)"); continue; }
  b=$(hash_of "$arm/marionette" "$f" "$qemu") || { failed+=("show $show (arm64)"); continue; }
  if [ "$a" = wall-clock ] || [ "$b" = wall-clock ]; then
    echo "== show $show: played on both; not compared (it has hardware devices, so it runs on the wall clock)"
  elif [ "$a" = "$b" ]; then
    echo "== show $show: run_hash $a on x86-64 and arm64"
  else
    echo "== show $show: run_hash differs: x86-64 $a, arm64 $b" >&2
    mismatch=1
  fi
done
[ $mismatch -eq 0 ] || failed+=("run_hash across architectures")
if [ ${#failed[@]} -gt 0 ]; then
  printf 'arm64: failed: %s\n' "${failed[@]}" >&2
  exit 1
fi
echo "arm64: all passed"
