#!/usr/bin/env bash
# `./scripts/start.sh --forward` (opt-in) lets a browser on the host reach the
# bridge, while the cell and the bridge stay inside start.sh's loopback-only
# namespace. The "host" here is a private namespace of the test's own, so
# nothing of this reaches the real host. Checks
#  - start.sh makes a namespace of its own: no mtc-cell or mtc-bridge process
#    shares the "host"'s namespace, and the bridge's port does not answer on
#    the "host" before the forward;
#  - with the forward, GET /current on the "host" at 127.0.0.1 answers the
#    bridge's document, with every device of the cell;
#  - the forward listens on 127.0.0.1 only, and the "host" has no UDP socket
#    at all (DDS never crosses; the forward is TCP to one port);
#  - the forward ends by itself when the cell stops.
#
# Usage: tests/scripts/check_http_forward.sh <build dir> <DDS domain> <bridge port>
set -euo pipefail
usage() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "${BASH_SOURCE[0]}"; }
case "${1:-}" in
  -h | --help) usage; exit 0 ;;
  -*) echo "check_http_forward.sh: unknown option '$1'" >&2; usage >&2; exit 2 ;;
esac
[ $# -eq 3 ] || { echo "check_http_forward.sh: expected 3 arguments" >&2; usage >&2; exit 2; }
build="$1" domain="$2" port="$3"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"

if [ "${MTC_FORWARD_HOST_NS:-}" != 1 ]; then
  # The "host": a namespace of our own, whichever namespace we are called from.
  flags=(-n)
  [ "$(id -u)" -eq 0 ] || flags=(-rn)
  MTC_FORWARD_HOST_NS=1 exec unshare "${flags[@]}" -- "$0" "$@"
fi

# ------------------------------------------------ inside the "host" namespace
ip link set lo up
log="$(mktemp)" forward_log="$(mktemp)" state="$(mktemp -d)"
start_pid="" forward_pid=""
cleanup() {
  [ -n "$forward_pid" ] && kill -TERM "$forward_pid" 2>/dev/null && wait "$forward_pid" 2>/dev/null
  [ -n "$start_pid" ] && kill -TERM "$start_pid" 2>/dev/null && wait "$start_pid" 2>/dev/null
  rm -rf "$log" "$forward_log" "$state"
}
trap cleanup EXIT
# A ctest timeout or Ctrl-C ends the test through exit, so the cell stops too.
trap 'exit 1' TERM INT HUP
fail() {
  echo "FAIL: $*" >&2
  echo "---- start.sh output ----" >&2
  cat "$log" >&2
  echo "---- start.sh --forward output ----" >&2
  cat "$forward_log" >&2
  exit 1
}

# start.sh as a person runs it: not yet in a namespace (ctest's netns-run.sh
# sets MTC_IN_NETNS=1, which would keep the cell here), so it makes its own.
env -u MTC_IN_NETNS MTC_BUILD_DIR="$build" MTC_CELL_STATE_DIR="$state" "$root/scripts/start.sh" \
  --no-build --domain "$domain" --port "$port" --pace-ms 10 >"$log" 2>&1 &
start_pid=$!
timeout 60 grep -m1 -q "cycle 1 complete" <(tail -n +1 -f "$log") || fail "no cycle completed"

host_ns="$(readlink /proc/self/ns/net)"
descendants() {
  local child
  for child in $(pgrep -P "$1"); do
    echo "$child"
    descendants "$child"
  done
}
ddsprocs=0
for pid in $(descendants "$start_pid"); do
  name="$(basename "$(readlink /proc/"$pid"/exe 2>/dev/null)")" || continue
  case "$name" in
    mtc-cell | mtc-bridge)
      ddsprocs=$((ddsprocs + 1))
      [ "$(readlink /proc/"$pid"/ns/net)" != "$host_ns" ] ||
        fail "$name ($pid) runs in the host's namespace" ;;
  esac
done
[ "$ddsprocs" -ge 2 ] || fail "found $ddsprocs mtc-cell/mtc-bridge processes under start.sh"
if curl -sS -o /dev/null --max-time 2 "http://127.0.0.1:$port/probe" 2>/dev/null; then
  fail "the bridge answers on the host without a forward"
fi

env -u MTC_IN_NETNS MTC_BUILD_DIR="$build" MTC_CELL_STATE_DIR="$state" "$root/scripts/start.sh" \
  --forward >"$forward_log" 2>&1 &
forward_pid=$!
timeout 30 grep -m1 -q "now reaches the bridge" <(tail -n +1 -f "$forward_log") ||
  fail "the forward did not start"

# The bridge learns each device from its announcement: poll until all three
# are in /current (or 30 s pass). The listener may take a moment after the
# message: connection failures count as "not yet" until the deadline.
needles=('uuid="cell-machine"' 'uuid="cell-robot"' 'uuid="cell-feeder"' '<MTConnectStreams')
has_all() { for n in "${needles[@]}"; do grep -q "$n" <<<"$current" || return 1; done; }
current="" deadline=$((SECONDS + 30))
until has_all; do
  [ "$SECONDS" -lt "$deadline" ] || fail "no complete /current through the forward: $current"
  current="$(curl -sS --max-time 10 "http://127.0.0.1:$port/current" 2>&1)" || true
  has_all || sleep 0.2
done

# What the "host" side has open: one TCP listener on 127.0.0.1:<port>, no UDP.
listeners="$(ss -Hltn)"
grep -q "127.0.0.1:$port " <<<"$listeners" || fail "no listener on 127.0.0.1:$port: $listeners"
others="$(grep -v "127.0.0.1:$port " <<<"$listeners" || true)"
[ -z "$others" ] || fail "other listeners on the host side: $others"
udp="$(ss -Huan)"
[ -z "$udp" ] || fail "UDP sockets on the host side (DDS must stay inside): $udp"

kill -TERM "$start_pid"
rc=0
wait "$start_pid" || rc=$?
start_pid=""
[ "$rc" = 0 ] || fail "start.sh exit code $rc after SIGTERM"
rc=0
timeout 30 tail --pid="$forward_pid" -f /dev/null || fail "the forward outlived the cell by 30 s"
wait "$forward_pid" || rc=$?
forward_pid=""
[ "$rc" = 0 ] || fail "the forward's exit code $rc after the cell stopped"
grep -q "the cell stopped; forward closed" "$forward_log" || fail "no message when the cell stopped"
echo "forward: GET /current on the host side answered through 127.0.0.1:$port with" \
  "${#needles[@]} expected parts; $ddsprocs DDS processes in start.sh's namespace, no UDP socket" \
  "on the host side; the forward closed with the cell"
