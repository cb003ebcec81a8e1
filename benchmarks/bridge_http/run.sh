#!/usr/bin/env bash
# Runs the bridge HTTP benchmarks inside the loopback-only namespace and
# writes their JSON summaries to <build>/benchmarks/bridge_http.json.
#   benchmarks/bridge_http/run.sh [build-dir]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:-${MTC_BUILD_DIR:-$root/build}}"
bin="$build/benchmarks"
out="$bin/bridge_http.json"
for exe in mtc-bench-bridge-current mtc-bench-bridge-stream; do
  [ -x "$bin/$exe" ] || { echo "run.sh: $bin/$exe missing; build target ${exe//-/_}" >&2; exit 1; }
done
command -v wrk >/dev/null || { echo "run.sh: wrk not installed (apt-get install wrk)" >&2; exit 1; }
{
  "$root/scripts/netns-run.sh" "$bin/mtc-bench-bridge-current" --duration "${MTC_BENCH_SECONDS:-10}"
  "$root/scripts/netns-run.sh" "$bin/mtc-bench-bridge-stream" --samples "${MTC_BENCH_SAMPLES:-2000}"
  if [ -x "$bin/mtc-bench-bridge-dds-stream" ]; then
    fastdds shm clean >/dev/null 2>&1 || true
    "$root/scripts/netns-run.sh" "$bin/mtc-bench-bridge-dds-stream" --samples "${MTC_BENCH_SAMPLES:-1000}"
  fi
} | tee "$out"
echo "run.sh: summaries in $out" >&2
