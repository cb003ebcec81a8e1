#!/usr/bin/env bash
# Runs a command inside a private network namespace whose only interface is
# loopback, with multicast routed to lo so DDS discovery works there and
# nowhere else. Root uses `unshare -n`; others try a user namespace. Inside
# one already (MTC_IN_NETNS=1), it runs the command as it is.
#
# Usage: scripts/netns-run.sh <command> [args...]
set -euo pipefail

usage() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "${BASH_SOURCE[0]}"; }
case "${1:-}" in
  -h | --help) usage; exit 0 ;;
  "") echo "netns-run.sh: no command given" >&2; usage >&2; exit 2 ;;
  -*) echo "netns-run.sh: unknown option '$1'" >&2; usage >&2; exit 2 ;;
esac

if [ "${MTC_IN_NETNS:-}" = "1" ]; then
  exec "$@"
fi

setup='ip link set lo up && ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo'
if [ "$(id -u)" -eq 0 ]; then
  unshare_flags=(-n)
else
  unshare_flags=(-rn)
fi

# The inner shell checks that loopback really is the only interface before
# running anything, so a failed isolation can never leak traffic.
exec unshare "${unshare_flags[@]}" -- bash -c '
  set -euo pipefail
  '"$setup"'
  others=$(ip -o link show | awk -F": " "{print \$2}" | grep -v "^lo$" || true)
  if [ -n "$others" ]; then
    echo "netns-run: refusing to run, interfaces besides lo: $others" >&2
    exit 97
  fi
  export MTC_IN_NETNS=1
  exec "$@"
' netns-run "$@"
