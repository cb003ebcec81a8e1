#!/usr/bin/env bash
# Runs the two-machine example (examples/two_machines: one robot serving two
# machines through two explicitly paired interfaces) with the MTConnect
# bridge: every load of both machines completes, the bridge lists the three
# devices with the robot's two interfaces, and its /probe and /current
# validate against the MTConnect schemas. Starts DDS: run it inside the
# loopback-only namespace (ctest does, via netns-run.sh).
#
# Usage: examples/run_two_machines.sh <example> <mtc-bridge> <domain> <port> <schema dir>
set -euo pipefail
usage() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "${BASH_SOURCE[0]}"; }
case "${1:-}" in
  -h | --help) usage; exit 0 ;;
  -*) echo "run_two_machines.sh: unknown option '$1'" >&2; usage >&2; exit 2 ;;
esac
[ $# -eq 5 ] || { echo "run_two_machines.sh: five arguments expected" >&2; usage >&2; exit 2; }
example="$1" bridge="$2" domain="$3" port="$4" schemas="$5"
work="$(mktemp -d)"
bridge_pid="" example_pid=""
cleanup() {
  for pid in $example_pid $bridge_pid; do kill -TERM "$pid" 2>/dev/null || true; done
  wait 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT
fail() {
  echo "FAIL: $*" >&2
  for f in "$work"/*.log; do echo "---- $f" >&2; tail -n 30 "$f" >&2; done
  exit 1
}

"$bridge" --transport loopback --domain-ids "$domain" --port "$port" >"$work/bridge.log" 2>&1 &
bridge_pid=$!
for _ in $(seq 100); do
  curl -s -o /dev/null --max-time 1 "http://127.0.0.1:$port/probe" && break
  sleep 0.1
done
# --hold-ms: the devices stay alive while the bridge is asked about them.
# The log exists before tail follows it: the background redirect may not.
: >"$work/example.log"
"$example" --domain "$domain" --cycles 3 --hold-ms 60000 >"$work/example.log" 2>&1 &
example_pid=$!
timeout 60 grep -m1 -q "loads COMPLETE" <(tail -n +1 -f "$work/example.log") ||
  fail "the example did not finish its cycles"
grep -q "two machines: 6 of 6 loads COMPLETE" "$work/example.log" || fail "not every load completed"

# The bridge learns the devices from their announcements: poll until all
# three (and the robot's two interfaces) are there, or 30 s pass.
has_all() {
  for needle in 'uuid="robot-1"' 'uuid="machine-a"' 'uuid="machine-b"' 'to machine A' 'to machine B'; do
    grep -q "$needle" "$work/probe.xml" || return 1
  done
}
deadline=$((SECONDS + 30))
: >"$work/probe.xml"
until has_all; do
  [ "$SECONDS" -lt "$deadline" ] || fail "the bridge's probe lacks a device or interface"
  curl -sS --max-time 10 "http://127.0.0.1:$port/probe" >"$work/probe.xml" || fail "no /probe"
  has_all || sleep 0.2
done
curl -sS --max-time 10 "http://127.0.0.1:$port/current" >"$work/current.xml" || fail "no /current"
loads="$(grep -o '<MaterialLoad[^>]*>[A-Z_]*<' "$work/current.xml" | grep -c 'READY<' || true)"
[ "$loads" -ge 4 ] || fail "expected 4 MaterialLoad items READY (2 requests, 2 responses), saw $loads"

# Validate against the schema of the version the bridge speaks.
for doc in probe:Devices current:Streams; do
  file="$work/${doc%%:*}.xml" kind="${doc##*:}"
  version="$(grep -o "urn:mtconnect.org:MTConnect$kind:[0-9.]*" "$file" | head -n1 | sed 's/.*://')"
  xsd="$schemas/MTConnect${kind}_${version}_1.0.xsd"
  [ -r "$xsd" ] || fail "no schema $xsd for /${doc%%:*}"
  xmllint --noout --schema "$xsd" "$file" 2>"$work/xmllint.log" || fail "/${doc%%:*} does not validate"
done
echo "two machines: 6 loads COMPLETE; /probe (3 devices, robot with 2 interfaces) and /current" \
  "valid against MTConnect $version"
