#!/usr/bin/env bash
# The README's test command: installs what is missing, builds, and runs the
# whole suite inside a loopback-only network namespace. Fails loudly: any
# failed, skipped or missing test makes the exit code non-zero.
#
# Usage: scripts/test.sh [ctest selection] [-- any ctest options]
#   -R REGEX / -E REGEX     only / not the tests whose name matches
#   -L REGEX / -LE REGEX    only / not the tests whose label matches (cli, dds, ...)
#   --repeat MODE:N         e.g. until-fail:5
#   -V, -VV, -N             verbose, extra verbose, list only
# Environment: MTC_BUILD_DIR (default <repo>/build), MTC_TEST_JOBS (default 2);
# the build is scripts/build.sh's (same configuration as ./scripts/start.sh).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${MTC_BUILD_DIR:-$root/build}"

usage() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "${BASH_SOURCE[0]}"; }
# ctest ignores options it does not know and runs everything: check here.
ctest_args=()
while [ $# -gt 0 ]; do
  case "$1" in
    -h | --help) usage; exit 0 ;;
    -R | -E | -L | -LE | --repeat)
      [ $# -ge 2 ] || { echo "test.sh: $1 needs a value" >&2; usage >&2; exit 2; }
      ctest_args+=("$1" "$2"); shift 2 ;;
    -V | -VV | -N) ctest_args+=("$1"); shift ;;
    --) shift; ctest_args+=("$@"); break ;;
    *) echo "test.sh: unknown option '$1'" >&2; usage >&2; exit 2 ;;
  esac
done

"$root/scripts/build.sh"

# Stale shared-memory segments of killed participants would confuse SHM
# transport tests; clear those of earlier runs.
fastdds shm clean >/dev/null 2>&1 || true

log="$build/ctest-output.log"
set +e
"$root/scripts/netns-run.sh" ctest --test-dir "$build" --output-on-failure \
  --no-tests=error -j "${MTC_TEST_JOBS:-2}" --timeout 600 "${ctest_args[@]}" 2>&1 | tee "$log"
status=${PIPESTATUS[0]}
set -e
if [ "$status" -ne 0 ]; then
  echo "test.sh: ctest failed (exit $status)" >&2
  exit "$status"
fi
# GoogleTest prints "[  SKIPPED ]" for skipped tests and ctest counts
# "Not Run"; either means something did not run, which is a failure here.
if grep -qE '\[  SKIPPED \]|Not Run|\*\*\*Skipped' "$log"; then
  echo "test.sh: some tests were skipped; a run that skips is a failed run" >&2
  exit 1
fi
