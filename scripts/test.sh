#!/usr/bin/env bash
# The README's test command: installs what is missing, builds, and runs the
# whole suite inside a loopback-only network namespace. Fails loudly: any
# failed, skipped or missing test makes the exit code non-zero.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${MTC_BUILD_DIR:-$root/build}"

MTC_WERROR="${MTC_WERROR:-ON}" "$root/scripts/build.sh"

# Stale shared-memory segments of killed participants would confuse SHM
# transport tests; clear those of earlier runs.
fastdds shm clean >/dev/null 2>&1 || true

log="$build/ctest-output.log"
set +e
"$root/scripts/netns-run.sh" ctest --test-dir "$build" --output-on-failure \
  --no-tests=error -j "${MTC_TEST_JOBS:-2}" --timeout 600 "$@" 2>&1 | tee "$log"
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
