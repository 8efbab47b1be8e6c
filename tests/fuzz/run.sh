#!/usr/bin/env bash
# Runs the libFuzzer harnesses of a MARIONETTE_FUZZ build:
#   tests/fuzz/run.sh BUILD_DIR SECONDS [HARNESS...]
# SECONDS is each harness's time; RUNS=N also stops a harness after N executions; FORK=N runs
# each harness in libFuzzer's fork mode on N cores (a campaign: then JOBS=1 suits).
# Seeds come from config/ and the shared corpus (written into BUILD_DIR/fuzz/seeds at run
# time); what a run finds grows BUILD_DIR/fuzz/work/NAME, kept for the next run. Every input
# in tests/fuzz/regressions/NAME is run first. Harnesses run two at a time (JOBS). Prints one
# line per harness (executions, crashes) and fails when any harness found a crash, a leak, a
# timeout (TIMEOUT seconds, default 2: the harnesses carry ASan, UBSan and coverage, which make
# an input at a parser's limit several times slower than a Release build) or ran out of memory
# (2 GB); the failing input is kept in BUILD_DIR/fuzz/artifacts.
set -uo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BUILD=$(cd "$1" && pwd); SECONDS_EACH=$2; shift 2
JOBS=${JOBS:-$(nproc)}
CORPUS=${MARIONETTE_CORPUS_DIR:-$ROOT/../shared/corpus}
F=$BUILD/fuzz
mkdir -p "$F/seeds" "$F/work" "$F/artifacts" "$F/logs" "$F/recordings"

# A few recordings of simulated shows, when a plain build's program is there to make them.
PROGRAM=${MARIONETTE_PROGRAM:-$ROOT/build/marionette}
if [ -x "$PROGRAM" ] && [ -z "$(ls "$F/recordings" 2>/dev/null)" ]; then
  for show in nanokontrol2 knob_box pen_tablet gamepad; do
    "$PROGRAM" run "$ROOT/config/shows/$show.toml" --headless --frames 60 \
      --record "$F/recordings/$show.marrec" >/dev/null 2>&1 || true
  done
fi
python3 "$ROOT/tests/fuzz/seeds.py" "$ROOT" "$CORPUS" "$F/seeds" >/dev/null || exit 1

HARNESSES=("$@")
[ ${#HARNESSES[@]} -eq 0 ] && mapfile -t HARNESSES < <(cd "$BUILD/tests/fuzz" && ls fuzz_* | grep -v '\.' )

# The longest input each harness tries: a few times the largest input its parser accepts
# (SysEx 1,024 bytes, an OSC message 96 bytes, a HID descriptor 4,096 bytes and a report 8 KiB)
# or the largest shipped file (shows and profiles are 1-3 KB); 64 KB for SVG, recordings and
# rigs. Inputs grow toward it and a longer one only runs slower through the same code.
max_len_of() {
  case $1 in
    fuzz_osc|fuzz_color|fuzz_svg_values) echo 4096 ;;
    fuzz_midi|fuzz_usb_midi) echo 8192 ;;
    fuzz_hid|fuzz_show_toml|fuzz_device_profile|fuzz_timeline) echo 16384 ;;
    *) echo 65536 ;;
  esac
}

run_one() {
  local name=$1 exe=$BUILD/tests/fuzz/$1
  mkdir -p "$F/work/$name" "$F/seeds/$name"
  local reg=$ROOT/tests/fuzz/regressions/$name
  if [ -d "$reg" ] && ! "$exe" -timeout="$TIMEOUT" -rss_limit_mb=2048 "$reg"/* >"$F/logs/$name.regressions" 2>&1; then
    echo "$name: a regression input fails (see $F/logs/$name.regressions)"; return 1
  fi
  local started=$SECONDS
  "$exe" -max_total_time="$SECONDS_EACH" ${RUNS:+-runs=$RUNS} ${FORK:+-fork=$FORK} -timeout="$TIMEOUT" -rss_limit_mb=2048 \
    -max_len="$(max_len_of "$name")" -print_final_stats=1 -artifact_prefix="$F/artifacts/$name-" \
    "$F/work/$name" "$F/seeds/$name" >"$F/logs/$name.log" 2>&1
  local rc=$? took=$((SECONDS - started))
  local execs; execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$F/logs/$name.log" | grep -o '[0-9]*$')
  # Fork mode's parent prints its total as "#N: cov: ..." lines instead.
  [ -n "$FORK" ] && execs=$(grep -oE '^#[0-9]+: cov' "$F/logs/$name.log" | tail -1 | grep -oE '[0-9]+')
  if [ $rc -ne 0 ]; then
    echo "$name: FAILED after ${execs:-?} executions ($(grep -m1 -oE 'SUMMARY: [A-Za-z]+: [^ ]+ [^ ]*|ERROR: libFuzzer: [a-z-]+' "$F/logs/$name.log"))"
    echo "  log: $F/logs/$name.log; input: $(ls "$F/artifacts/$name-"* 2>/dev/null | head -1)"
    return 1
  fi
  local rate; rate=$(grep -o 'stat::average_exec_per_sec: *[0-9]*' "$F/logs/$name.log" | grep -o '[0-9]*$')
  [ -n "$FORK" ] && rate=$(( ${execs:-0} / (took > 0 ? took : 1) ))
  echo "$name: ${execs:-0} executions (${rate:-0}/s${FORK:+ on $FORK cores}, ${took} s), 0 crashes"
}
RUNS=${RUNS:-}
FORK=${FORK:-}
TIMEOUT=${TIMEOUT:-2}
export -f run_one max_len_of; export BUILD F ROOT SECONDS_EACH RUNS FORK TIMEOUT
printf '%s\n' "${HARNESSES[@]}" | xargs -P "$JOBS" -I{} bash -c 'run_one {}' | tee "$F/summary.txt"
