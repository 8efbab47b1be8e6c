#!/usr/bin/env bash
# `cmake --install` into a temporary prefix: the binary, device profiles, udev rule and the
# example characters, rigs and shows land in standard places, and the installed program,
# run away from the source and build trees, finds its data there.
set -euo pipefail
build=$1
prefix=$(mktemp -d)
trap 'rm -rf "$prefix"' EXIT
cmake --install "$build" --prefix "$prefix" >/dev/null
test -x "$prefix/bin/marionette"
test -x "$prefix/bin/marionette-simulate"
# The shipping program does not link the virtual bench; --simulate hands over to its sibling.
# (ldd into a file: `ldd | grep -q` under pipefail fails when grep stops reading early.)
ldd "$prefix/bin/marionette" > "$prefix/ldd.txt"
if grep -q umockdev "$prefix/ldd.txt"; then echo "bin/marionette links umockdev:"; cat "$prefix/ldd.txt"; exit 1; fi
ldd "$prefix/bin/marionette-simulate" > "$prefix/ldd.txt"
grep -q umockdev "$prefix/ldd.txt" || { echo "bin/marionette-simulate should carry the bench"; exit 1; }
test -f "$prefix/lib/udev/rules.d/70-marionette.rules"
test -f "$prefix/lib/systemd/system/marionette-kiosk.service"
# The hardware watchdog drop-in: systemd keeps /dev/watchdog within the Raspberry Pi's 15 s.
wd="$prefix/share/marionette/systemd/marionette-watchdog.conf"
sec=$(sed -n 's/^RuntimeWatchdogSec=\([0-9]*\)s$/\1/p' "$wd")
[ -n "$sec" ] && [ "$sec" -gt 0 ] && [ "$sec" -le 15 ] || { echo "$wd: RuntimeWatchdogSec must be 1..15 s"; exit 1; }
grep -qx '\[Manager\]' "$wd" || { echo "$wd: no [Manager] section"; exit 1; }
for d in characters rigs shows devices; do
  test -n "$(ls "$prefix/share/marionette/$d")" || { echo "empty: share/marionette/$d"; exit 1; }
done
cd "$prefix"
export MARIONETTE_CORPUS_DIR=/nonexistent
"$prefix/bin/marionette" devices --json > devices.json
grep -q "\"data_dir\": \"$prefix/share/marionette\"" devices.json || { echo "data_dir is not the installed one:"; grep data_dir devices.json; exit 1; }
"$prefix/bin/marionette" inspect "$prefix/share/marionette/characters/boy.svg" --rig "$prefix/share/marionette/rigs/boy.toml" > inspect.txt
grep -q "joints:" inspect.txt
"$prefix/bin/marionette" run "$prefix/share/marionette/shows/demo.toml" --headless --frames 30 --stats stats.json > run.txt 2> run.err
grep -q '"frames": 30' stats.json
if [ -s run.err ]; then echo "the installed demo printed:"; cat run.err; exit 1; fi
echo "installed into a temporary prefix: binary, profiles, udev rule, service and watchdog drop-in, characters, rigs, shows; the program finds them"
