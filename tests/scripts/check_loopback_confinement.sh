#!/usr/bin/env bash
# The second layer of confinement: DDS stays on loopback by its transport
# configuration alone, not only because start.sh runs it in a loopback-only
# namespace (issue 12). Runs ./scripts/start.sh's cell and bridge (told that
# they are in a namespace already, so start.sh makes none) in a
# network namespace that also has a veth link to a second namespace, with a
# private address, a default route and the multicast range routed through it,
# so anything not meant for 127.0.0.1 would leave through that link. Checks
#  - every socket of mtc-cell and mtc-bridge (/proc/<pid>/fd against
#    /proc/<pid>/net/{udp,tcp,udp6,tcp6,unix,netlink}) is bound to 127.0.0.1
#    and, when connected, talks to 127.0.0.1 (or is a unix/netlink socket, or
#    one not bound yet, which has no address); no raw or packet socket;
#  - not one packet left through the veth while the cell ran handshakes
#    (its tx counter in /proc/net/dev), and that the counter does count a
#    datagram sent to the other end afterwards.
# The namespace has no multicast route on lo either: discovery must work by
# unicast on 127.0.0.1 alone.
#
# Usage: tests/scripts/check_loopback_confinement.sh <build dir> <DDS domain> <bridge port>
set -euo pipefail
usage() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "${BASH_SOURCE[0]}"; }
case "${1:-}" in
  -h | --help) usage; exit 0 ;;
  -*) echo "check_loopback_confinement.sh: unknown option '$1'" >&2; usage >&2; exit 2 ;;
esac
[ $# -eq 3 ] || { echo "check_loopback_confinement.sh: expected 3 arguments" >&2; usage >&2; exit 2; }
build="$1" domain="$2" port="$3"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"

if [ "${MTC_CONFINEMENT_NS:-}" != 1 ]; then
  # A namespace of our own, whichever namespace we are called from.
  flags=(-n)
  [ "$(id -u)" -eq 0 ] || flags=(-rn)
  MTC_CONFINEMENT_NS=1 exec unshare "${flags[@]}" -- "$0" "$@"
fi

# ------------------------------------------------- inside our own namespace
veth=mtcv0 peer_veth=mtcv1
log="$(mktemp)" state="$(mktemp -d)"
peer_pid="" start_pid=""
cleanup() {
  [ -n "$start_pid" ] && kill -TERM "$start_pid" 2>/dev/null && wait "$start_pid" 2>/dev/null
  [ -n "$peer_pid" ] && kill "$peer_pid" 2>/dev/null
  rm -rf "$log" "$state"
}
trap cleanup EXIT
# A ctest timeout or Ctrl-C ends the test through exit, so the cell stops too.
trap 'exit 1' TERM INT HUP
fail() {
  echo "FAIL: $*" >&2
  echo "---- start.sh output ----" >&2
  cat "$log" >&2
  exit 1
}

ip link set lo up
unshare -n sleep 600 &  # the second namespace, held open by this process
peer_pid=$!
for _ in $(seq 50); do
  [ "$(readlink /proc/$peer_pid/ns/net 2>/dev/null)" != "$(readlink /proc/self/ns/net)" ] && break
  sleep 0.05
done
ip link add "$veth" type veth peer name "$peer_veth" netns "$peer_pid"
# No IPv6 on the link: the kernel's own neighbour discovery would count as
# traffic that no process of ours sent.
echo 1 >/proc/sys/net/ipv6/conf/"$veth"/disable_ipv6
nsenter --net="/proc/$peer_pid/ns/net" sh -c "
  echo 1 >/proc/sys/net/ipv6/conf/$peer_veth/disable_ipv6
  ip addr add 10.213.0.2/24 dev $peer_veth && ip link set $peer_veth up"
ip addr add 10.213.0.1/24 dev "$veth"
ip link set "$veth" up
ip route add default via 10.213.0.2 dev "$veth"
ip route add 224.0.0.0/4 dev "$veth"

tx_packets() { awk -v d="$1:" '$1 == d { print $11 }' /proc/net/dev; }
tx_before="$(tx_packets "$veth")"
[ -n "$tx_before" ] || fail "no counters for $veth"

# MTC_IN_NETNS=1: start.sh runs the cell right here, next to the veth.
MTC_IN_NETNS=1 MTC_BUILD_DIR="$build" MTC_CELL_STATE_DIR="$state" "$root/scripts/start.sh" --no-build \
  --domain "$domain" --port "$port" --pace-ms 10 >"$log" 2>&1 &
start_pid=$!
timeout 60 grep -m1 -q "cycle 2 complete" <(tail -n +1 -f "$log") || fail "no cycle completed"
# The bridge has seen every device (it discovers them over DDS like the cell).
needles=('uuid="cell-machine"' 'uuid="cell-robot"' 'uuid="cell-feeder"')
deadline=$((SECONDS + 30)) current=""
has_all() { for n in "${needles[@]}"; do grep -q "$n" <<<"$current" || return 1; done; }
until has_all; do
  [ "$SECONDS" -lt "$deadline" ] || fail "the bridge did not list every device: $current"
  current="$(curl -sS --max-time 10 "http://127.0.0.1:$port/current")" || fail "no /current"
  has_all || sleep 0.2
done

# Prints "<kind> <local> <remote>" for socket inode $2 of process $1, as the
# kernel's tables for that process's namespace list it.
socket_entry() {
  local pid="$1" inode="$2" table
  for table in udp tcp udp6 tcp6; do
    awk -v t="$table" -v i="$inode" 'NR > 1 && $10 == i { print t, $2, $3; found = 1; exit }
      END { exit !found }' "/proc/$pid/net/$table" && return 0
  done
  for table in unix netlink raw raw6 packet icmp icmp6 udplite udplite6; do
    [ -r "/proc/$pid/net/$table" ] || continue
    awk -v i="$inode" 'NR > 1 { for (f = 1; f <= NF; ++f) if ($f == i) { found = 1; exit } }
      END { exit !found }' "/proc/$pid/net/$table" && { echo "$table"; return 0; }
  done
  # In no table: a socket never bound nor connected (the kernel lists inet
  # sockets once they have a port). It has no address and carries nothing;
  # should it bind later, the second round of checks sees where.
  echo "unbound"
}
# 127.0.0.1 (or ::1, or ::ffff:127.0.0.1); 0 remote = not connected.
loopback_v4=0100007F
is_loopback() {
  case "$1" in
    "$loopback_v4":*) return 0 ;;
    00000000000000000000000001000000:*) return 0 ;;
    0000000000000000FFFF00000100007F:*) return 0 ;;
  esac
  return 1
}
is_unconnected() { case "$1" in 00000000:0000 | 00000000000000000000000000000000:0000) return 0 ;; esac; return 1; }

check_sockets() {  # check_sockets <pid> <name>; prints the number of inet sockets
  local pid="$1" name="$2" fd target inode entry kind local_addr remote inet=0
  for fd in /proc/"$pid"/fd/*; do
    target="$(readlink "$fd" 2>/dev/null)" || continue
    case "$target" in socket:\[*\]) ;; *) continue ;; esac
    inode="${target#socket:[}" inode="${inode%]}"
    entry="$(socket_entry "$pid" "$inode")"
    read -r kind local_addr remote <<<"$entry"
    case "$kind" in
      unix | netlink | unbound) continue ;;
      udp | tcp | udp6 | tcp6)
        inet=$((inet + 1))
        is_loopback "$local_addr" || fail "$name ($pid) has a $kind socket bound to $local_addr (not 127.0.0.1)"
        is_unconnected "$remote" || is_loopback "$remote" ||
          fail "$name ($pid) has a $kind socket connected to $remote (not 127.0.0.1)"
        ;;
      *) fail "$name ($pid) has a $kind socket (inode $inode)" ;;
    esac
  done
  echo "$inet"
}

# Every process start.sh started, children of children included (mtc-cell
# runs each station as a process of its own).
descendants() {
  local child
  for child in $(pgrep -P "$1"); do
    echo "$child"
    descendants "$child"
  done
}
for round in 1 2; do
  cell_sockets=0 bridge_sockets=0 cell_processes=0 bridge_processes=0
  for pid in $(descendants "$start_pid"); do
    # By executable: the stations run as `/proc/self/exe --station ...`,
    # whose comm is "exe".
    name="$(basename "$(readlink /proc/"$pid"/exe 2>/dev/null)")" || continue
    case "$name" in
      mtc-cell)
        n="$(check_sockets "$pid" "$name")"
        cell_sockets=$((cell_sockets + n)) cell_processes=$((cell_processes + 1)) ;;
      mtc-bridge)
        n="$(check_sockets "$pid" "$name")"
        bridge_sockets=$((bridge_sockets + n)) bridge_processes=$((bridge_processes + 1)) ;;
    esac
  done
  # Not vacuous: the stations' DDS and the agent do use the network stack.
  [ "$bridge_processes" = 1 ] || fail "expected 1 mtc-bridge under start.sh, found $bridge_processes"
  [ "$cell_processes" -ge 1 ] || fail "no mtc-cell under start.sh"
  [ "$cell_sockets" -ge 2 ] || fail "the mtc-cell processes have only $cell_sockets inet sockets"
  [ "$bridge_sockets" -ge 3 ] || fail "mtc-bridge has only $bridge_sockets inet sockets"
  [ "$round" = 1 ] && timeout 60 grep -m1 -q "cycle 4 complete" <(tail -n +1 -f "$log")
done
grep -Eq "cycle 4 complete" "$log" || fail "the cell stopped making progress"
tx_after="$(tx_packets "$veth")"
[ "$tx_after" = "$tx_before" ] ||
  fail "$((tx_after - tx_before)) packets left through $veth while the cell ran"

kill -TERM "$start_pid"
rc=0
wait "$start_pid" || rc=$?
start_pid=""
[ "$rc" = 0 ] || fail "start.sh exit code $rc after SIGTERM"

# The counter does count: one datagram to the other end of the link.
echo probe >/dev/udp/10.213.0.2/9 || true
[ "$(tx_packets "$veth")" -gt "$tx_after" ] || fail "$veth counts no packets at all: check is blind"
echo "confined: $cell_processes mtc-cell processes with $cell_sockets inet sockets and" \
  "mtc-bridge with $bridge_sockets, all on" \
  "127.0.0.1; 0 packets through $veth (a probe datagram afterwards: counted)"
