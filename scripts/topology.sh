#!/usr/bin/env bash
# A cell of "hosts" for multi-host tests: named network namespaces (each with
# its own /dev/shm, as separate machines have) joined by veth pairs to one
# Linux bridge device, with private addresses 10.77.0.0/24 that exist only
# inside the loopback-only sandbox of scripts/netns-run.sh. Refuses to run
# outside it, so it can never touch the host's interfaces.
#
# Usage:
#   scripts/topology.sh make DIR NAME...     create the bridge and one namespace per NAME
#   scripts/topology.sh exec DIR NAME CMD... run CMD inside NAME's namespaces
#   scripts/topology.sh link DIR NAME up|down  plug / pull NAME's cable (bridge side)
#   scripts/topology.sh addr DIR NAME        print NAME's address
#   scripts/topology.sh teardown DIR         remove everything `make` created
# DIR is a state directory (created by make) holding the namespace holders' pids.
# Addresses: the n-th NAME gets 10.77.0.(10+n); its interface is eth0, with
# multicast (DDS discovery) routed to it.
set -euo pipefail

usage() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "${BASH_SOURCE[0]}"; }
die_usage() { echo "topology.sh: $1" >&2; usage >&2; exit 2; }

bridge_dev=mtcbr0
subnet_prefix=10.77.0

require_sandbox() {
  if [ "${MTC_IN_NETNS:-}" != "1" ]; then
    echo "topology.sh: run me inside scripts/netns-run.sh (MTC_IN_NETNS=1)" >&2
    exit 2
  fi
}

holder_pid() {
  local pid
  pid=$(cat "$1/$2.pid" 2>/dev/null) || { echo "topology.sh: no node '$2' in $1" >&2; exit 2; }
  echo "$pid"
}

make_node() {
  local dir=$1 name=$2 index=$3 pid
  # The holder owns a network and a mount namespace; a private tmpfs on
  # /dev/shm keeps Fast DDS's shared memory per "host".
  unshare -n -m --propagation private -- \
    bash -c 'mount -t tmpfs -o size=64m tmpfs /dev/shm && exec sleep infinity' </dev/null >/dev/null 2>&1 &
  pid=$!
  echo "$pid" >"$dir/$name.pid"
  # Wait until the holder is in its own network namespace with /dev/shm mounted.
  for _ in $(seq 200); do
    if [ "$(readlink /proc/"$pid"/ns/net)" != "$(readlink /proc/self/ns/net)" ] &&
      nsenter -t "$pid" -m -- grep -q ' /dev/shm tmpfs' /proc/mounts 2>/dev/null; then
      break
    fi
    sleep 0.01
  done
  ip link add "mh-$name" type veth peer name "mhi-$name"
  ip link set "mhi-$name" netns "$pid"
  ip link set "mh-$name" master "$bridge_dev" up
  nsenter -t "$pid" -n -- bash -c "
    ip link set lo up
    ip link set mhi-$name name eth0
    ip addr add $subnet_prefix.$((10 + index))/24 dev eth0
    ip link set eth0 multicast on up
    ip route add 224.0.0.0/4 dev eth0"
}

cmd_make() {
  local dir=$1; shift
  [ $# -ge 1 ] || die_usage "make needs at least one NAME"
  mkdir -p "$dir"
  printf '%s\n' "$@" >"$dir/nodes"
  ip link add "$bridge_dev" type bridge
  ip link set "$bridge_dev" up
  local index=0 name
  for name in "$@"; do
    make_node "$dir" "$name" "$index"
    index=$((index + 1))
  done
}

cmd_teardown() {
  local dir=$1 name pid
  [ -f "$dir/nodes" ] || return 0
  while read -r name; do
    if pid=$(cat "$dir/$name.pid" 2>/dev/null); then
      # Whatever still runs in the node (a test that lost track of a child)
      # goes with it: every process there was started through `exec`.
      local ns p
      ns=$(readlink "/proc/$pid/ns/net" 2>/dev/null) || ns=""
      for p in /proc/[0-9]*; do
        if [ -n "$ns" ] && [ "$(readlink "$p/ns/net" 2>/dev/null)" = "$ns" ]; then
          kill -KILL "${p#/proc/}" 2>/dev/null || true
        fi
      done
    fi
    ip link del "mh-$name" 2>/dev/null || true
    rm -f "$dir/$name.pid"
  done <"$dir/nodes"
  ip link del "$bridge_dev" 2>/dev/null || true
  rm -f "$dir/nodes"
}

cmd_addr() {
  local dir=$1 name=$2 index
  index=$(grep -nx -- "$name" "$dir/nodes" | cut -d: -f1) || { echo "topology.sh: no node '$name'" >&2; exit 2; }
  echo "$subnet_prefix.$((9 + index))"
}

case "${1:-}" in
  -h | --help) usage; exit 0 ;;
  make) [ $# -ge 3 ] || die_usage "make needs DIR and NAME..."; require_sandbox; shift; cmd_make "$@" ;;
  teardown) [ $# -eq 2 ] || die_usage "teardown needs DIR"; require_sandbox; cmd_teardown "$2" ;;
  addr) [ $# -eq 3 ] || die_usage "addr needs DIR NAME"; cmd_addr "$2" "$3" ;;
  exec)
    [ $# -ge 4 ] || die_usage "exec needs DIR NAME CMD..."
    require_sandbox
    pid=$(holder_pid "$2" "$3"); shift 3
    exec nsenter -t "$pid" -n -m -- "$@" ;;
  link)
    [ $# -eq 4 ] || die_usage "link needs DIR NAME up|down"
    require_sandbox
    case "$4" in up | down) ;; *) die_usage "link state must be up or down, got '$4'" ;; esac
    holder_pid "$2" "$3" >/dev/null
    ip link set "mh-$3" "$4" ;;
  "") die_usage "no command given" ;;
  *) die_usage "unknown command '$1'" ;;
esac
