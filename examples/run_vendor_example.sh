#!/usr/bin/env bash
# Runs the vendor example (examples/vendor/cnc.cpp, the README's snippet)
# against `mtc respond` playing the robot: the example must complete one
# MATERIAL_LOAD and exit 0, and the robot must have served it. Starts DDS:
# run it inside the loopback-only namespace (ctest does, via netns-run.sh).
#
# Usage: examples/run_vendor_example.sh <mtc-example-cnc> <mtc> <domain>
set -euo pipefail
usage() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "${BASH_SOURCE[0]}"; }
case "${1:-}" in
  -h | --help) usage; exit 0 ;;
  -*) echo "run_vendor_example.sh: unknown option '$1'" >&2; usage >&2; exit 2 ;;
esac
[ $# -eq 3 ] || { echo "run_vendor_example.sh: three arguments expected" >&2; usage >&2; exit 2; }
example="$1"
mtc="$2"
domain="$3"

# The robot serves one handshake, then exits; its first JSON line says it is up.
coproc ROBOT {
  exec "$mtc" respond --transport loopback --domain "$domain" --device robot-1 --interface mh1 \
    --service MATERIAL_LOAD --action-ms 50 --count 1 --json
}
robot_pid=$ROBOT_PID
exec {robot_out}<&"${ROBOT[0]}"  # bash drops ROBOT[] once the robot has exited
trap 'kill -TERM "$robot_pid" 2>/dev/null || true' EXIT
if ! read -r -t 30 first <&"$robot_out"; then
  echo "run_vendor_example.sh: mtc respond did not come up" >&2
  exit 1
fi
echo "robot: $first"

# The example waits up to 5 s for the robot to be READY, then requests.
"$example" --transport loopback --domain "$domain"

sed 's/^/robot: /' <&"$robot_out"
robot_rc=0
wait "$robot_pid" || robot_rc=$?
trap - EXIT
if [ "$robot_rc" -ne 0 ]; then
  echo "run_vendor_example.sh: mtc respond exited with $robot_rc" >&2
  exit 1
fi
