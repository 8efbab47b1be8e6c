#!/usr/bin/env bash
# Runs a command against a private PipeWire daemon (docs: PLATFORM's recipe): its own D-Bus
# session (WirePlumber, which links streams, needs one), a fresh XDG_RUNTIME_DIR, pipewire and
# wireplumber started before the command and stopped after it. The daemon's pid is in
# MARIONETTE_PIPEWIRE_PID (a test may kill it). Exits with the command's status.
#   bash tests/tools/with_pipewire.sh CMD [ARGS...]
set -uo pipefail
for tool in dbus-run-session pipewire wireplumber pw-cli; do
  command -v "$tool" >/dev/null || { echo "with_pipewire: $tool is missing (Debian packages dbus, pipewire, wireplumber)" >&2; exit 77; }
done
if [ -z "${MARIONETTE_PIPEWIRE_SESSION:-}" ]; then
  export MARIONETTE_PIPEWIRE_SESSION=1
  exec dbus-run-session -- bash "$0" "$@"
fi
XDG_RUNTIME_DIR=$(mktemp -d)
chmod 700 "$XDG_RUNTIME_DIR"
export XDG_RUNTIME_DIR
unset PIPEWIRE_REMOTE
pipewire >"$XDG_RUNTIME_DIR/pipewire.log" 2>&1 &
pw=$!
for _ in $(seq 100); do [ -S "$XDG_RUNTIME_DIR/pipewire-0" ] && break; sleep 0.1; done
wireplumber >"$XDG_RUNTIME_DIR/wireplumber.log" 2>&1 &
wp=$!
# WirePlumber is ready when its client shows in the graph.
for _ in $(seq 100); do timeout 2 pw-cli ls Client 2>/dev/null | grep -q -i wireplumber && break; sleep 0.1; done
sleep 0.5
export MARIONETTE_PIPEWIRE_PID=$pw
"$@"
rc=$?
kill "$wp" "$pw" 2>/dev/null
wait "$wp" "$pw" 2>/dev/null
if [ $rc -ne 0 ] && [ -n "${MARIONETTE_PIPEWIRE_LOGS:-}" ]; then tail -20 "$XDG_RUNTIME_DIR"/*.log >&2; fi
rm -rf "$XDG_RUNTIME_DIR"
exit $rc
