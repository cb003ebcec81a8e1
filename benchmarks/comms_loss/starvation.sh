#!/usr/bin/env bash
# False comms-loss alarms of the simulated cell under CPU starvation (issue 10):
# runs mtc-cell (three station processes, no injected failure, no freeze) while
# N busy-loop processes of the same niceness compete for the cores, once per
# heartbeat period, and counts the LOST lines (every one is a false alarm:
# nothing is frozen or killed) and the heartbeats the executor watchdog withheld
# ("withheld" diagnostics). Prints one JSON object on stdout.
#
# Usage: benchmarks/comms_loss/starvation.sh [options]
#   --build DIR         build directory with apps/mtc-cell (default <repo>/build)
#   --busy N            busy-loop processes (default 4 x the cores: a 4x overload)
#   --seconds S         cell run per heartbeat (default 120)
#   --heartbeats LIST   heartbeat periods in ms, comma-separated (default 100,50,20)
#   --missed N          missed heartbeats before a loss (default 3)
#   --no-rt             put the stations' SCHED_FIFO threads (the heartbeat
#                       threads, when the runtime got real-time priority) back
#                       to SCHED_OTHER, to see what the priority buys
#   --domain D          DDS domain (default 118)
#   --log-dir DIR       keep each cell log there (default a temporary folder)
#   -h, --help          this text
# Runs the cell inside scripts/netns-run.sh. Run it niced on a shared machine
# (nice -n 19): the busy loops inherit the niceness, so the overload is
# relative to the cell.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
usage() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "${BASH_SOURCE[0]}"; }

build="$root/build"
busy=$((4 * $(nproc)))
seconds=120
heartbeats=100,50,20
missed=3
rt=1
domain=118
log_dir=""
need() { [ $# -ge 2 ] || { echo "starvation.sh: $1 needs a value" >&2; usage >&2; exit 2; }; }
number() { [[ "$2" =~ ^[0-9]+$ ]] || { echo "starvation.sh: $1 wants a number, got '$2'" >&2; exit 2; }; }
while [ $# -gt 0 ]; do
  case "$1" in
    -h | --help) usage; exit 0 ;;
    --build) need "$@"; build=$2; shift 2 ;;
    --busy) need "$@"; number "$1" "$2"; busy=$2; shift 2 ;;
    --seconds) need "$@"; number "$1" "$2"; seconds=$2; shift 2 ;;
    --heartbeats)
      need "$@"
      [[ "$2" =~ ^[0-9]+(,[0-9]+)*$ ]] || { echo "starvation.sh: --heartbeats wants ms,ms,..." >&2; exit 2; }
      heartbeats=$2; shift 2 ;;
    --missed) need "$@"; number "$1" "$2"; missed=$2; shift 2 ;;
    --no-rt) rt=0; shift ;;
    --domain) need "$@"; number "$1" "$2"; domain=$2; shift 2 ;;
    --log-dir) need "$@"; log_dir=$2; shift 2 ;;
    *) echo "starvation.sh: unknown option '$1'" >&2; usage >&2; exit 2 ;;
  esac
done
cell="$build/apps/mtc-cell"
[ -x "$cell" ] || { echo "starvation.sh: no $cell (build first, or --build DIR)" >&2; exit 2; }
if [ -z "$log_dir" ]; then
  log_dir=$(mktemp -d)
  trap 'rm -rf "$log_dir"' EXIT
fi
mkdir -p "$log_dir"

busy_pids=()
stop_busy() {
  for p in "${busy_pids[@]}"; do kill "$p" 2>/dev/null || true; done
  busy_pids=()
}
trap 'stop_busy' INT TERM

# Every SCHED_FIFO thread of the cell's stations back to SCHED_OTHER, until
# the cell ends (threads appear as the stations start).
demote_realtime() {
  local cell_pid=$1
  while kill -0 "$cell_pid" 2>/dev/null; do
    for tid in $(ps -eLo tid=,cls=,args= | awk '$2 == "FF" && /mtc-cell --station/ {print $1}'); do
      chrt -o -p 0 "$tid" 2>/dev/null || true
    done
    sleep 1
  done
}

runs=()
IFS=, read -r -a periods <<<"$heartbeats"
for hb in "${periods[@]}"; do
  log="$log_dir/cell-$hb-ms.log"
  for ((i = 0; i < busy; ++i)); do
    sh -c 'while :; do :; done' &
    busy_pids+=($!)
  done
  fastdds shm clean >/dev/null 2>&1 || true
  "$root/scripts/netns-run.sh" "$cell" --transport loopback --domain "$domain" --duration "$seconds" --fail-every 0 \
    --heartbeat-ms "$hb" --missed-heartbeats "$missed" >"$log" 2>&1 &
  cell_pid=$!
  demoter=""
  if [ "$rt" = 0 ]; then
    demote_realtime "$cell_pid" &
    demoter=$!
  fi
  status=0
  wait "$cell_pid" || status=$?
  [ -z "$demoter" ] || wait "$demoter" || true
  stop_busy
  echo "starvation.sh: heartbeat $hb ms x $missed, $busy busy loops, ${seconds} s: exit $status" >&2
  counts=$(python3 "$root/benchmarks/endurance/cell_log.py" "$log")
  # Each withholding appears twice: on stderr at once, and as a diagnostic
  # once the executor runs again; the second is counted.
  withheld=$(grep "withheld" "$log" | grep -vc "said at once" || true)
  runs+=("$(python3 - "$hb" "$missed" "$status" "$counts" "$withheld" <<'EOF'
import json, sys
hb, missed, status, counts = int(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3]), json.loads(sys.argv[4])
withheld = int(sys.argv[5])
print(json.dumps({"heartbeat_ms": hb, "missed_heartbeats": missed, "lease_ms": hb * missed,
                  "cell_exit": status, "false_alarms": counts["false_alarms"],
                  "handshakes": counts["handshakes_completed"],
                  "other_failures": counts["other_failures"],
                  "heartbeats_withheld": withheld,
                  "false_alarm_lines": [a["line"] for a in counts["false_alarm_lines"][:3]]}))
EOF
)")
done

joined=$(IFS=,; echo "${runs[*]}")
printf '{"benchmark":"starvation","cores":%d,"busy_loops":%d,"seconds":%d,"realtime_heartbeat":%s,"runs":[%s]}\n' \
  "$(nproc)" "$busy" "$seconds" "$([ "$rt" = 1 ] && echo true || echo false)" "$joined"
