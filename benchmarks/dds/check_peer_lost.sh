#!/usr/bin/env bash
# ctest benchmarks.dds_latency_peer_lost: every raw Fast DDS series of
# mtc-bench-dds-latency must end, with its lost round trips counted as
# timeouts, when its ponger quits in the middle of the series (a forked one
# kills itself, --peer-quits-after). Before the series gave up after five
# timeouts in a row, a dead peer held the run for a reply timeout per round
# trip left (over 10 minutes once); ctest's TIMEOUT is the bound here.
#
# Usage (inside scripts/netns-run.sh): check_peer_lost.sh BENCH_BINARY OUT_DIR
#   BENCH_BINARY   build/benchmarks/mtc-bench-dds-latency
#   OUT_DIR        where dds_latency_peer_lost.json goes
#   -h, --help     this text
set -euo pipefail
usage() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "${BASH_SOURCE[0]}"; }
case "${1:-}" in
  -h | --help) usage; exit 0 ;;
  -*) echo "check_peer_lost.sh: unknown option '$1'" >&2; usage >&2; exit 2 ;;
esac
[ $# -eq 2 ] || { echo "check_peer_lost.sh: BENCH_BINARY and OUT_DIR expected" >&2; usage >&2; exit 2; }
bench="$1"
out="$2/dds_latency_peer_lost.json"
mkdir -p "$2"
samples=200
"$bench" --only raw --samples "$samples" --warmup 20 --rounds 1 --cyclone-seconds 0 \
  --reply-timeout-ms 200 --peer-quits-after 60 --out "$out" >/dev/null
python3 - "$out" "$samples" <<'PY'
import json, sys
doc = json.load(open(sys.argv[1]))
samples = int(sys.argv[2])
raw = [s for s in doc["series"] if s["name"].startswith("raw_fastdds")]
bad = []
for s in raw:
    # 40 timed echoes at most, then timeouts for the rest: each series both
    # measured something and counted what it lost.
    if s["timeouts"] == 0 or s["count"] == 0 or s["count"] + s["timeouts"] != samples:
        bad.append("%s: count %d, timeouts %d" % (s["name"], s["count"], s["timeouts"]))
if len(raw) != 6 or bad:
    sys.exit("expected 6 raw series, each cut short with its losses counted: %d series; %s"
             % (len(raw), "; ".join(bad)))
print("%d raw series ended after their peer quit: %s" % (
    len(raw), ", ".join("%s %d+%d" % (s["name"], s["count"], s["timeouts"]) for s in raw)))
PY
