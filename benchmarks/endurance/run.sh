#!/usr/bin/env bash
# usage: benchmarks/endurance/run.sh [--minutes M] [--out DIR] [--interval S] [--no-build]
#        benchmarks/endurance/run.sh --idle N [--minutes M] [--out DIR] [--interval S] [--no-build]
#
# Endurance benchmarks inside the loopback-only network namespace (not CI;
# the 4-minute CI test is tests/endurance; see benchmarks/endurance/README.md).
#   without --idle: the cell + bridge at their defaults for M minutes (default
#       30): DIR/endurance.json, endurance.png, endurance-cell.log, -bridge.log
#   --idle N: mtc-bench-idle, an equipment with N interfaces and its
#       counterpart idling for M minutes (default 10): DIR/idle-N.json, .png
# DIR defaults to bench-results/ (gitignored); --interval: sampling period in
# seconds (default 10). Exit code 0 when every verdict passes, 1 when one
# fails, 2 on a usage error.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${MTC_BUILD_DIR:-$root/build}"
out="${MTC_BENCH_RESULTS:-$root/bench-results}"
here="$root/benchmarks/endurance"

usage() { sed -n '2,13p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; }

minutes="" interval=10 idle="" build_first=1
while [ $# -gt 0 ]; do
  case "$1" in
    -h|--help) usage; exit 0 ;;
    --no-build) build_first=0; shift; continue ;;
    --minutes|--out|--interval|--idle)
      [ $# -ge 2 ] || { echo "run.sh: $1 needs a value" >&2; usage >&2; exit 2; } ;;
    *) echo "run.sh: unknown option $1" >&2; usage >&2; exit 2 ;;
  esac
  case "$1" in
    --minutes) minutes="$2" ;;
    --out) out="$2" ;;
    --interval) interval="$2" ;;
    --idle) idle="$2" ;;
  esac
  shift 2
done
number='^[0-9]+([.][0-9]+)?$'
if [ -n "$minutes" ] && ! [[ "$minutes" =~ $number ]]; then
  echo "run.sh: --minutes takes a number of minutes" >&2; exit 2
fi
if ! [[ "$interval" =~ ^[0-9]+$ ]] || [ "$interval" -lt 1 ]; then
  echo "run.sh: --interval takes whole seconds >= 1" >&2; exit 2
fi
if [ -n "$idle" ] && ! [[ "$idle" =~ ^[0-9]+$ ]]; then
  echo "run.sh: --idle takes a number of interfaces" >&2; exit 2
fi

[ "$build_first" = 1 ] && "$root/scripts/build.sh"
mkdir -p "$out"
# Segments left by a killed participant would confuse the SHM transport.
fastdds shm clean >/dev/null 2>&1 || true

if [ -z "$idle" ]; then
  exec "$root/scripts/netns-run.sh" python3 "$here/endurance.py" --build "$build" \
    --minutes "${minutes:-30}" --interval "$interval" --out "$out"
fi

seconds="$(python3 -c "print(round(float('${minutes:-10}') * 60))")"
rc=0
"$root/scripts/netns-run.sh" "$build/benchmarks/mtc-bench-idle" --interfaces "$idle" \
  --duration "$seconds" --interval "$interval" --out "$out/idle-$idle.json" >/dev/null || rc=$?
[ "$rc" = 2 ] && exit 2
if [ -s "$out/idle-$idle.json" ]; then
  python3 "$here/plot.py" "$out/idle-$idle.json" "$out/idle-$idle.png" &&
    echo "plot: $out/idle-$idle.png"
  echo "summary: $out/idle-$idle.json"
fi
exit "$rc"
