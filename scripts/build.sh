#!/usr/bin/env bash
# Configures and builds the project into <repo>/build (or $MTC_BUILD_DIR), after
# installing any missing package (scripts/setup-deps.sh).
#
# Usage: scripts/build.sh
# Environment: MTC_BUILD_DIR (default <repo>/build), MTC_BUILD_TYPE (default
# RelWithDebInfo), MTC_WERROR=ON to make warnings errors (default OFF).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
usage() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "${BASH_SOURCE[0]}"; }
case "${1:-}" in
  -h | --help) usage; exit 0 ;;
  "") ;;
  *) echo "build.sh: unknown option '$1'" >&2; usage >&2; exit 2 ;;
esac
build="${MTC_BUILD_DIR:-$root/build}"
"$root/scripts/setup-deps.sh"
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE="${MTC_BUILD_TYPE:-RelWithDebInfo}" \
  -DMTC_WERROR="${MTC_WERROR:-OFF}" >/dev/null
cmake --build "$build" -j "$(nproc)"
