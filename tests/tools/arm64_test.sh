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
# Each program and each show is single-threaded under qemu-user: they run JOBS at a time (the
# cores), each into its own log, printed when it fails.
JOBS=${JOBS:-$(nproc)}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export arm qemu work
run_test() { # program [binfmt] -> prints one line; the log is kept in $work/NAME.log
  local t=$1 how="qemu-user" cmd=("$qemu" "$arm/tests/$1")
  [ "${2:-}" = binfmt ] && { how="qemu-user through binfmt_misc"; cmd=("$arm/tests/$1"); }
  local s=$SECONDS
  if "${cmd[@]}" --gtest_brief=1 >"$work/$t.log" 2>&1; then
    echo "== $t (arm64, $how): $(grep -o '[0-9]* tests\? from .* ran' "$work/$t.log" | grep -o '^[0-9]*') tests passed in $((SECONDS - s)) s"
  else
    echo "== $t (arm64, $how): FAILED"; cat "$work/$t.log"; touch "$work/$t.failed"
  fi
}
export -f run_test
{
  printf '%s\n' "${subset[@]}"
  for t in "${needs_binfmt[@]}"; do
    if [ "$binfmt" = yes ]; then printf '%s binfmt\n' "$t"
    else echo "== $t skipped: it starts arm64 programs itself, and binfmt_misc has no qemu-aarch64 here" >&2; fi
  done
} | xargs -P "$JOBS" -L1 bash -c 'run_test "$@"' _
failed=()
for f in "$work"/*.failed; do [ -e "$f" ] && failed+=("$(basename "$f" .failed)"); done

# The same show gives the same run_hash on both architectures, over 300 frames (the pinned
# demo hash is a 300-frame one). A show with hardware devices runs on the wall clock: its
# run_hash differs from run to run on one machine too, so it is played on both, not compared.
export native
compare_show() { # show file -> one line; "differs" or "failed" in $work/NAME.show on failure
  local f=$1 show; show=$(basename "$1" .toml)
  local a b
  hash_of() { # stats file, program and its runner...
    local stats=$1; shift
    "$@" run "$f" --headless --frames 300 --stats "$stats" >/dev/null 2>"$stats.err" || { cat "$stats.err"; return 1; }
    python3 -c 'import json,sys; j=json.load(open(sys.argv[1])); print(j["run_hash"] if j["clock"]["mode"] == "virtual" else "wall-clock")' "$stats"
  }
  a=$(hash_of "$work/$show.x86.json" "$native/marionette") || { echo "== show $show (x86-64): FAILED"; echo "$a"; echo failed >"$work/$show.show"; return; }
  b=$(hash_of "$work/$show.arm.json" "$qemu" "$arm/marionette") || { echo "== show $show (arm64): FAILED"; echo "$b"; echo failed >"$work/$show.show"; return; }
  if [ "$a" = wall-clock ] || [ "$b" = wall-clock ]; then
    echo "== show $show: played on both; not compared (it has hardware devices, so it runs on the wall clock)"
  elif [ "$a" = "$b" ]; then
    echo "== show $show: run_hash $a on x86-64 and arm64"
  else
    echo "== show $show: run_hash differs: x86-64 $a, arm64 $b"; echo differs >"$work/$show.show"
  fi
}
export -f compare_show
printf '%s\n' "$root"/config/shows/*.toml | xargs -P "$JOBS" -I{} bash -c 'compare_show "$1"' _ {}
mismatch=0
for f in "$work"/*.show; do
  [ -e "$f" ] || continue
  if [ "$(cat "$f")" = differs ]; then mismatch=1; else failed+=("show $(basename "$f" .show)"); fi
done
[ $mismatch -eq 0 ] || failed+=("run_hash across architectures")
if [ ${#failed[@]} -gt 0 ]; then
  printf 'arm64: failed: %s\n' "${failed[@]}" >&2
  exit 1
fi
echo "arm64: all passed"
