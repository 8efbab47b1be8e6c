#!/usr/bin/env bash
# The soak (`bash cmake/run.sh soak`): hours of a show squeezed into minutes.
#   tests/tools/soak.sh BUILD_DIR [FRAMES]     (FRAMES default 1,000,000)
# 1. tests/data/shows/soak.toml (every simulated device looping, a pen grabbing) headless for
#    FRAMES frames on the virtual clock, as fast as the machine goes; its RSS is read from /proc
#    every 2 s: growth after a 10 s warm-up must stay within 1 MB, and the frame thread must not
#    allocate after warm-up.
# 2. A deterministic section (20,000 frames) before and after: the same run_hash.
# 3. Every hot-pluggable backend class unplugged and replugged 1,000 times during a show
#    (test_devices LiveHotplug, MARIONETTE_HOTPLUG_CYCLES=1000).
# 4. 1,000,000 random handle target sets per example rig (bench_extreme).
# Prints one line per part and fails when any part fails.
set -uo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BUILD=$(cd "$1" && pwd); FRAMES=${2:-1000000}
SHOW=$ROOT/tests/data/shows/soak.toml
OUT=$BUILD/soak; mkdir -p "$OUT"
fail=0

section() { "$BUILD/marionette" run "$SHOW" --headless --frames 20000 --stats "$OUT/$1.json" >/dev/null 2>&1 &&
  python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['run_hash'])" "$OUT/$1.json"; }
h1=$(section section_before)

"$BUILD/marionette" run "$SHOW" --headless --frames "$FRAMES" --stats "$OUT/long.json" >"$OUT/long.log" 2>&1 &
pid=$!
start=$(date +%s); : >"$OUT/rss.txt"
while kill -0 "$pid" 2>/dev/null; do
  rss=$(awk '/VmRSS/ {print $2}' "/proc/$pid/status" 2>/dev/null) && echo "$(( $(date +%s) - start )) $rss" >>"$OUT/rss.txt"
  sleep 2
done
wait "$pid"; rc=$?
read -r growth first last samples < <(awk '$1 >= 10 { if (!n++) first = $2; if ($2 > max) max = $2; last = $2 }
  END { print max - first, first, last, n }' "$OUT/rss.txt")
python3 - "$OUT/long.json" "$rc" "${growth:-0}" "${first:-0}" "${samples:-0}" "$(( $(date +%s) - start ))" <<'PY' || fail=1
import json, sys
j = json.load(open(sys.argv[1])); rc, growth, first, samples, secs = map(int, sys.argv[2:7])
ok = rc == 0 and j["heap_allocations_after_warmup"] == 0 and growth <= 1024 and samples > 0
f = j["stages_us"]["frame"]
print(f"long run: {j['frames']} frames in {secs} s, RSS {first} kB after warm-up, growth {growth} kB "
      f"({samples} samples), allocations after warm-up {j['heap_allocations_after_warmup']}, "
      f"overruns {j['overruns']}, frame p50 {f['p50']:.0f} us p99 {f['p99']:.0f} us, "
      f"grabs {j['grabs']['count']}, events mapped {j['events']['mapped']} -> {'ok' if ok else 'FAILED'}")
sys.exit(0 if ok else 1)
PY

h2=$(section section_after)
if [ -n "$h1" ] && [ "$h1" = "$h2" ]; then echo "deterministic section: run_hash $h1 before and after -> ok"
else echo "deterministic section: run_hash $h1 before, $h2 after -> FAILED"; fail=1; fi

if MARIONETTE_HOTPLUG_CYCLES=${HOTPLUG_CYCLES:-1000} "$BUILD/tests/test_devices" --gtest_filter='*LiveHotplug*' >"$OUT/hotplug.log" 2>&1; then
  grep -h '\[ measure \]' "$OUT/hotplug.log" | sed 's/^\[ measure \] /hotplug /; s/$/ -> ok/'
else echo "hotplug: FAILED (see $OUT/hotplug.log)"; grep -h '\[ measure \]' "$OUT/hotplug.log"; fail=1; fi

if "$BUILD/tests/bench/bench_extreme" --sets "${EXTREME_SETS:-1000000}" >"$OUT/extreme.log" 2>&1 &&
   ! grep -q 'non-finite [1-9]' "$OUT/extreme.log"; then sed 's/^/extreme: /' "$OUT/extreme.log"
else echo "extreme: FAILED (see $OUT/extreme.log)"; fail=1; fi
exit $fail
