#!/usr/bin/env bash
# The README's main command: builds the project, then runs the simulated cell
# (machine tool, robot, bar feeder: apps/cell) and the MTConnect bridge on
# this host. Open http://localhost:5000/ in a browser (the live page; /probe,
# /current, /sample as from any MTConnect agent).
#
# Usage:
#   ./scripts/start.sh [--no-build] [--port N] [--domain D] [cell options]
#                                      run the cell and the bridge (Ctrl-C stops both);
#                                      bridge port default 5000, DDS domain default 110
#   ./scripts/start.sh --query PATH    from another terminal: GET PATH from the running bridge
#
# Cell options go to mtc-cell: --cycles N, --duration S, --seed N, --fail-every K,
# --pace-ms MS, --comms-loss-every S, --heartbeat-ms MS, --missed-heartbeats N
# (the bridge gets these two as well), --threads (see `build/apps/mtc-cell --help`).
# DDS stays on this host by its transport configuration (qos::Transport::
# Loopback: UDP on 127.0.0.1 and shared memory, discovery by unicast on
# 127.0.0.1, no multicast) and the bridge listens on 127.0.0.1 only; no
# network namespace is needed (tests/scripts/check_loopback_confinement.sh).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${MTC_BUILD_DIR:-$root/build}"
# Where the running cell leaves its pid and its bridge port for --query (tests
# point MTC_CELL_STATE_DIR elsewhere so they never touch the state of a cell a
# person is running from the same build).
state="${MTC_CELL_STATE_DIR:-$build}"
pidfile="$state/mtc-cell.pid"  # this script, while it runs the cell
port_file="$state/mtc-cell.port"
domain=110                            # DDS domain of the cell (ids 100-119: cell and benchmarks)
port=5000

usage() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "${BASH_SOURCE[0]}"; }

case "${1:-}" in
  -h|--help) usage; exit 0 ;;
  --query)
    path="${2:-/current}"
    case "$path" in /*) ;; *) path="/$path" ;; esac
    pid="$(cat "$pidfile" 2>/dev/null || true)"
    if [ -z "$pid" ] || ! kill -0 "$pid" 2>/dev/null; then
      echo "start.sh: no cell is running (start one with ./scripts/start.sh)" >&2
      exit 1
    fi
    [ -r "$port_file" ] && port="$(cat "$port_file")"
    exec curl -sS --fail-with-body --max-time 10 "http://127.0.0.1:${port}${path}" ;;
  # The cell used to run in a private network namespace that this option
  # stepped into; it runs on the host now, so any terminal will do.
  --enter)
    echo "start.sh: --enter is gone: the cell runs on this host; use curl or" \
      "$build/apps/mtc (DDS domain $domain) from any terminal" >&2
    exit 2 ;;
esac

# ---------------------------------------------------------------- run
build_first=1
cell_args=()
# The bridge's observer must use the cell's lease: a reader whose lease is
# shorter than the writers' does not match them (and Fast DDS detects loss
# with the reader's own lease). Both default to the runtime's timing
# (qos::Timing), so the flags are handed to the bridge only when given.
bridge_timing=()
usage_error() { echo "start.sh: $*" >&2; usage >&2; exit 2; }
need_value() { [ $# -ge 2 ] || usage_error "$1 needs a value"; }
while [ $# -gt 0 ]; do
  case "$1" in
    -h | --help) usage; exit 0 ;;
    --no-build) build_first=0; shift ;;
    --heartbeat-ms | --missed-heartbeats)
      need_value "$@"; bridge_timing+=("$1" "$2"); cell_args+=("$1" "$2"); shift 2 ;;
    --port) need_value "$@"; port="$2"; shift 2 ;;
    --domain) need_value "$@"; domain="$2"; shift 2 ;;
    # mtc-cell checks the values; an unknown option stops here, before a build.
    --cycles | --duration | --seed | --fail-every | --pace-ms | --comms-loss-every)
      need_value "$@"; cell_args+=("$1" "$2"); shift 2 ;;
    --threads) cell_args+=("$1"); shift ;;
    *) usage_error "unknown option '$1'" ;;
  esac
done

if [ "$build_first" = 1 ]; then
  "$root/scripts/build.sh"
fi
# SHM segments of a cell killed earlier would only confuse the new one.
fastdds shm clean >/dev/null 2>&1 || true

cell="$build/apps/mtc-cell"
bridge="$build/apps/mtc-bridge"
bridge_log="$build/mtc-bridge.log"
[ -x "$cell" ] || { echo "start.sh: $cell is not built" >&2; exit 1; }

bridge_pid=""
cell_pid=""
cleanup() {
  [ -n "$cell_pid" ] && kill -TERM "$cell_pid" 2>/dev/null || true
  if [ -n "$bridge_pid" ] && kill -0 "$bridge_pid" 2>/dev/null; then
    kill -TERM "$bridge_pid" 2>/dev/null || true
    for _ in $(seq 50); do kill -0 "$bridge_pid" 2>/dev/null || break; sleep 0.1; done
    kill -KILL "$bridge_pid" 2>/dev/null || true
    wait "$bridge_pid" 2>/dev/null || true
  fi
  rm -f "$pidfile" "$port_file"
}
trap cleanup EXIT
echo $$ >"$pidfile"
echo "$port" >"$port_file"

if [ -x "$bridge" ]; then
  # Same heartbeat as the cell, so the bridge matches the stations' writers
  # and declares a device lost when the stations would.
  # 127.0.0.1 only: the agent is for this host's browser, not the network.
  "$bridge" --domain-ids "$domain" --server-ip 127.0.0.1 --port "$port" "${bridge_timing[@]}" \
    >"$bridge_log" 2>&1 &
  bridge_pid=$!
  # Wait until the agent answers (it also needs no device yet to answer).
  for _ in $(seq 100); do
    curl -s -o /dev/null --max-time 1 "http://127.0.0.1:$port/probe" && break
    kill -0 "$bridge_pid" 2>/dev/null || break
    sleep 0.1
  done
  if ! kill -0 "$bridge_pid" 2>/dev/null; then
    echo "start.sh: the bridge did not start; its log ($bridge_log):" >&2
    tail -n 20 "$bridge_log" >&2
    exit 1
  fi
else
  echo "start.sh: $bridge is not built; running the cell without the MTConnect bridge" >&2
fi

cat <<EOF
================================================================================
 mtconnect-dds simulated cell: machine tool + robot + bar feeder on DDS domain $domain
 (DDS on this host only: UDP on 127.0.0.1 and shared memory).
 MTConnect agent (mtc-bridge), open in a browser on this host:
   http://localhost:$port/          live page of every device and handshake
   http://localhost:$port/probe  /current  /sample
   (log: $bridge_log)
 From another terminal:
   ./scripts/start.sh --query /current               # current values of every data item
   ./scripts/start.sh --query '/sample?count=50'     # the last handshakes as they happened
   $build/apps/mtc watch --domain $domain            # the DDS side, live
 Stop with Ctrl-C.
================================================================================
EOF

# The cell runs as a background job so that SIGINT/SIGTERM reach this shell's
# trap at once; the trap hands them on and the loop waits for a clean exit.
"$cell" --domain "$domain" "${cell_args[@]}" &
cell_pid=$!
trap 'kill -TERM "$cell_pid" 2>/dev/null || true' INT TERM
rc=0
while :; do
  rc=0
  wait "$cell_pid" || rc=$?
  kill -0 "$cell_pid" 2>/dev/null || break
done
# A wait cut short by the trap says 130/143; bash still knows the real status.
if [ "$rc" -gt 128 ]; then
  rc=0
  wait "$cell_pid" || rc=$?
fi
cell_pid=""
echo "start.sh: cell stopped (exit code $rc)"
exit "$rc"
