#!/usr/bin/env bash
# The README's two commands share one build (issue 12): after the test
# command (scripts/test.sh) has built a folder, the main command's build
# (scripts/build.sh, which scripts/start.sh runs first) must find nothing to
# do. Runs scripts/build.sh as a person would (no MTC_* switches set) on a
# built folder and fails if it compiles, links or generates anything.
#
# Usage: tests/scripts/check_shared_build.sh <build dir>
set -euo pipefail
usage() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "${BASH_SOURCE[0]}"; }
case "${1:-}" in
  -h | --help) usage; exit 0 ;;
  "" | -*) echo "check_shared_build.sh: expected a build dir" >&2; usage >&2; exit 2 ;;
esac
build="$1"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
[ -f "$build/CMakeCache.txt" ] || { echo "check_shared_build.sh: $build is not configured" >&2; exit 2; }

log="$(mktemp)"
trap 'rm -f "$log"' EXIT
env -u MTC_WERROR -u MTC_BUILD_TYPE MTC_BUILD_DIR="$build" "$root/scripts/build.sh" >"$log" 2>&1 || {
  echo "FAIL: scripts/build.sh failed on an already built folder" >&2
  cat "$log" >&2
  exit 1
}
if grep -Eq 'Building |Linking |Generating ' "$log"; then
  echo "FAIL: scripts/build.sh rebuilt part of a folder scripts/test.sh had built:" >&2
  grep -E 'Building |Linking |Generating ' "$log" | head -n 20 >&2
  echo "($(grep -Ec 'Building |Linking ' "$log") compile/link steps)" >&2
  exit 1
fi
echo "scripts/build.sh on the built folder: nothing to do ($(grep -c 'Built target' "$log") targets up to date)"
