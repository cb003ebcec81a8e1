#!/usr/bin/env bash
# Runs the bridge HTTP benchmarks (mtc-bench-bridge-current, -stream, -abuse,
# -fanout, -replay and, when built, -dds-stream) inside the loopback-only namespace; their JSON
# summaries, one line each, go to stdout and to <build>/benchmarks/bridge_http.json.
# -dds-stream runs four times: as mtc-bridge ships (Fast DDS, the observer handing values
# to the agent on the receive thread), with the observer's dispatch thread instead
# (InlineSteps = no), with the device's inline steps too, and (in a build with
# MTC_CYCLONE) over Cyclone DDS with inline steps: issue 9 section 5's path.
#
# Usage: benchmarks/bridge_http/run.sh [build-dir]
#   build-dir  default $MTC_BUILD_DIR, else <repo>/build
# Environment: MTC_BENCH_SECONDS (wrk run, default 10), MTC_BENCH_SAMPLES
# (streaming samples, default 2000; 1000 for -dds-stream), MTC_BENCH_ABUSE_SECONDS
# (well-behaved requests per abuse, default 4), MTC_BENCH_NO_ABUSE=1 (skip the
# abuse run), MTC_BENCH_FANOUT_CLIENTS / _FEEDS (default 1000 / 100),
# MTC_BENCH_REPLAY_HOURS (hours of the cell's traffic replayed, default 4).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
usage() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "${BASH_SOURCE[0]}"; }
case "${1:-}" in
  -h | --help) usage; exit 0 ;;
  -*) echo "run.sh: unknown option '$1'" >&2; usage >&2; exit 2 ;;
esac
[ $# -le 1 ] || { echo "run.sh: one build directory at most" >&2; usage >&2; exit 2; }
build="${1:-${MTC_BUILD_DIR:-$root/build}}"
bin="$build/benchmarks"
out="$bin/bridge_http.json"
for exe in mtc-bench-bridge-current mtc-bench-bridge-stream mtc-bench-bridge-abuse \
  mtc-bench-bridge-fanout mtc-bench-bridge-replay; do
  [ -x "$bin/$exe" ] || { echo "run.sh: $bin/$exe missing; build target ${exe//-/_}" >&2; exit 1; }
done
command -v wrk >/dev/null || { echo "run.sh: wrk not installed (apt-get install wrk)" >&2; exit 1; }
{
  "$root/scripts/netns-run.sh" "$bin/mtc-bench-bridge-current" --duration "${MTC_BENCH_SECONDS:-10}"
  "$root/scripts/netns-run.sh" "$bin/mtc-bench-bridge-stream" --samples "${MTC_BENCH_SAMPLES:-2000}"
  if [ "${MTC_BENCH_NO_ABUSE:-0}" != 1 ]; then
    "$root/scripts/netns-run.sh" "$bin/mtc-bench-bridge-abuse" --seconds "${MTC_BENCH_ABUSE_SECONDS:-4}"
  fi
  "$root/scripts/netns-run.sh" "$bin/mtc-bench-bridge-fanout" \
    --clients "${MTC_BENCH_FANOUT_CLIENTS:-1000}" --feeds "${MTC_BENCH_FANOUT_FEEDS:-100}"
  "$root/scripts/netns-run.sh" "$bin/mtc-bench-bridge-replay" --hours "${MTC_BENCH_REPLAY_HOURS:-4}"
  if [ -x "$bin/mtc-bench-bridge-dds-stream" ]; then
    fastdds shm clean >/dev/null 2>&1 || true
    dds_stream=("$root/scripts/netns-run.sh" "$bin/mtc-bench-bridge-dds-stream"
      --samples "${MTC_BENCH_SAMPLES:-1000}")
    "${dds_stream[@]}"
    "${dds_stream[@]}" --observer-steps dispatch
    "${dds_stream[@]}" --inline-steps
    if grep -q '^MTC_CYCLONE:BOOL=ON$' "$build/CMakeCache.txt"; then
      "${dds_stream[@]}" --inline-steps --middleware cyclone
    fi
  fi
} | tee "$out"
echo "run.sh: summaries in $out" >&2
