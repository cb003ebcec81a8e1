#!/usr/bin/env bash
# Handshakes under packet loss (issue 10): `mtc respond` and `mtc request`,
# both losing the same share of their sent DATA submessages (Fast DDS's test
# transport, every n-th: this kernel has no netem), run N MATERIAL_LOAD
# handshakes per loss rate. Checks that every handshake COMPLETED, in order,
# none missing, and prints one JSON object with the latency percentiles the
# requester measured (request ACTIVE to the response's COMPLETE seen; the
# responder acts at once: --action-ms 0).
#
# Usage: benchmarks/comms_loss/packet_loss.sh [options]
#   --build DIR        build directory with apps/mtc (default <repo>/build)
#   --count N          handshakes per loss rate (default 200)
#   --percents LIST    loss rates in %, comma-separated (default 0,10,30)
#   --domain D         DDS domain (default 117)
#   -h, --help         this text
# Runs inside scripts/netns-run.sh (loopback only). Exit 1 when a handshake
# did not complete or came out of order.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
usage() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "${BASH_SOURCE[0]}"; }

build="$root/build"
count=200
percents=0,10,30
domain=117
need() { [ $# -ge 2 ] || { echo "packet_loss.sh: $1 needs a value" >&2; usage >&2; exit 2; }; }
number() { [[ "$2" =~ ^[0-9]+$ ]] || { echo "packet_loss.sh: $1 wants a number, got '$2'" >&2; exit 2; }; }
while [ $# -gt 0 ]; do
  case "$1" in
    -h | --help) usage; exit 0 ;;
    --build) need "$@"; build=$2; shift 2 ;;
    --count) need "$@"; number "$1" "$2"; count=$2; shift 2 ;;
    --percents)
      need "$@"
      [[ "$2" =~ ^[0-9]+(,[0-9]+)*$ ]] || { echo "packet_loss.sh: --percents wants p,p,..." >&2; exit 2; }
      percents=$2; shift 2 ;;
    --domain) need "$@"; number "$1" "$2"; domain=$2; shift 2 ;;
    *) echo "packet_loss.sh: unknown option '$1'" >&2; usage >&2; exit 2 ;;
  esac
done
mtc="$build/apps/mtc"
[ -x "$mtc" ] || { echo "packet_loss.sh: no $mtc (build first, or --build DIR)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# One loss rate, inside the namespace: the responder serves exactly `count`
# handshakes; the requester's JSON lines are kept for the check.
cat >"$work/pair.sh" <<'EOF'
set -euo pipefail
mtc=$1 domain=$2 count=$3 percent=$4 out=$5
common=(--domain "$domain" --json --drop-percent "$percent")
"$mtc" respond --transport loopback "${common[@]}" --device machine-1 --interface mh --service MATERIAL_LOAD \
  --counterpart robot-1 --count "$count" --action-ms 0 >"$out.respond" 2>&1 &
responder=$!
"$mtc" request --transport loopback "${common[@]}" --device robot-1 --interface mh --service MATERIAL_LOAD \
  --counterpart machine-1 --count "$count" --timeout 30s >"$out.request" 2>"$out.request.err" || true
wait "$responder" || true
EOF

runs=()
status=0
IFS=, read -r -a rates <<<"$percents"
for p in "${rates[@]}"; do
  fastdds shm clean >/dev/null 2>&1 || true
  start=$EPOCHREALTIME
  # transport-guard: pair.sh gives both its commands --transport loopback.
  "$root/scripts/netns-run.sh" bash "$work/pair.sh" "$mtc" "$domain" "$count" "$p" "$work/run-$p"
  run=$(python3 - "$work/run-$p.request" "$p" "$count" "$start" "$EPOCHREALTIME" <<'EOF'
import json, sys
path, percent, count = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
wall = float(sys.argv[5]) - float(sys.argv[4])
outcomes, summary = [], {}
for line in open(path):
    try:
        event = json.loads(line)
    except ValueError:
        continue
    if event.get("event") == "outcome":
        outcomes.append(event)
    elif event.get("event") == "summary":
        summary = event
numbers = [o["handshake"] for o in outcomes]
complete = sum(1 for o in outcomes if o["result"] == "COMPLETE")
print(json.dumps({"drop_percent": percent, "handshakes": count, "completed": complete,
                  "in_order": numbers == list(range(1, count + 1)),
                  "p50_ms": summary.get("p50_ms"), "p99_ms": summary.get("p99_ms"),
                  "max_ms": summary.get("max_ms"), "wall_s": round(wall, 1)}))
EOF
)
  echo "packet_loss.sh: $p % loss: $run" >&2
  python3 -c 'import json,sys; r=json.loads(sys.argv[1]); sys.exit(0 if r["completed"]==r["handshakes"] and r["in_order"] else 1)' "$run" || status=1
  runs+=("$run")
done

joined=$(IFS=,; echo "${runs[*]}")
load=$(cut -d' ' -f1-3 /proc/loadavg)
printf '{"benchmark":"packet_loss","cores":%d,"load":"%s","runs":[%s]}\n' "$(nproc)" "$load" "$joined"
exit "$status"
