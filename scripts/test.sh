#!/usr/bin/env bash
# The README's test command: installs what is missing, builds, and runs the
# whole suite inside a loopback-only network namespace. Fails loudly: any
# failed, skipped or missing test makes the exit code non-zero.
#
# Usage: scripts/test.sh [--sanitize asan|tsan] [ctest selection] [-- any ctest options]
#   --sanitize asan         the suite built with clang, ASan+UBSan and the
#                           libFuzzer targets (default build dir build-asan);
#                           adds the short fuzz runs (label fuzz)
#   --sanitize tsan         the suite built with clang and TSan (build-tsan)
#                           Both leave out the 4-minute endurance run (label
#                           endurance) and the resident-memory bounds
#                           (AbuseMemory.*: the sanitizers' allocators keep
#                           freed memory on purpose); the ordinary run has them.
#   -R REGEX / -E REGEX     only / not the tests whose name matches
#   -L REGEX / -LE REGEX    only / not the tests whose label matches (cli, dds, ...)
#   --repeat MODE:N         e.g. until-fail:5
#   -V, -VV, -N             verbose, extra verbose, list only
# Environment: MTC_BUILD_DIR (default <repo>/build), MTC_TEST_JOBS (default 2),
# MTC_FUZZ_SECONDS (each fuzz run, default 45), MTC_TEST_SLOWDOWN (sanitizer
# runs: 2 for asan, 3 for tsan; tests/support/slowdown.hpp), MTC_TEST_MIDDLEWARE
# (cyclone: every Equipment, DomainObserver, tool process and cell station of
# the tests on Cyclone DDS, their raw peers still Fast DDS;
# tests/support/transport.hpp, apps/cell/test_cell.sh); the build is
# scripts/build.sh's (same configuration as ./scripts/start.sh).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

usage() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "${BASH_SOURCE[0]}"; }
# ctest ignores options it does not know and runs everything: check here.
ctest_args=()
sanitize=""
exclude_labels=""
exclude_names=""
while [ $# -gt 0 ]; do
  case "$1" in
    -h | --help) usage; exit 0 ;;
    --sanitize)
      case "${2:-}" in
        asan | tsan) sanitize="$2"; shift 2 ;;
        *) echo "test.sh: --sanitize needs asan or tsan" >&2; usage >&2; exit 2 ;;
      esac ;;
    -LE)
      [ $# -ge 2 ] || { echo "test.sh: $1 needs a value" >&2; usage >&2; exit 2; }
      exclude_labels="$2"; shift 2 ;;
    -E)
      [ $# -ge 2 ] || { echo "test.sh: $1 needs a value" >&2; usage >&2; exit 2; }
      exclude_names="$2"; shift 2 ;;
    -R | -L | --repeat)
      [ $# -ge 2 ] || { echo "test.sh: $1 needs a value" >&2; usage >&2; exit 2; }
      ctest_args+=("$1" "$2"); shift 2 ;;
    -V | -VV | -N) ctest_args+=("$1"); shift ;;
    --) shift; ctest_args+=("$@"); break ;;
    *) echo "test.sh: unknown option '$1'" >&2; usage >&2; exit 2 ;;
  esac
done

if [ -z "$sanitize" ]; then
  build="${MTC_BUILD_DIR:-$root/build}"
  [ -z "$exclude_labels" ] || ctest_args+=(-LE "$exclude_labels")
  [ -z "$exclude_names" ] || ctest_args+=(-E "$exclude_names")
  MTC_BUILD_DIR="$build" "$root/scripts/build.sh"
else
  build="${MTC_BUILD_DIR:-$root/build-$sanitize}"
  ctest_args+=(-LE "^endurance\$${exclude_labels:+|$exclude_labels}")
  # Left out, as they run none of our code under the sanitizer (they read
  # the source tree or drive cmake, clang-format, clang-tidy and python):
  # lint.format and lint.tidy (11 minutes of clang-tidy alone), the docs
  # checks of the README and docs/ (docs.vendor_example_runs runs the example
  # and stays), the transport guard and its self-test, and the check that
  # test.sh and start.sh share one build. The ordinary run has all of them.
  # AbuseMemory.* bounds resident memory, which ASan's quarantine and TSan's
  # allocator inflate on purpose.
  not_ours='^lint\.|^docs\.(layout_matches_tree|links_resolve|snippets_match_sources|dependencies_match_setup)$'
  not_ours+='|^scripts\.(transport_chosen|transport_guard_catches_planted_cases|test_then_start_share_one_build)$'
  ctest_args+=(-E "^AbuseMemory\\.|$not_ours${exclude_names:+|$exclude_names}")
  MTC_BUILD_DIR="$build" MTC_WERROR="${MTC_WERROR:-ON}" MTC_SANITIZE="$sanitize" \
    "$root/scripts/build.sh"
  # Reports fail the test that made them; suppressions (Fast DDS internals
  # only) carry their reasons in tests/sanitizers/.
  supp="$root/tests/sanitizers"
  # new_delete_type_mismatch=0: Fast DDS 2.9 frees an object that
  # StatisticsReaderImpl allocated (64 bytes) through a 56-byte type in
  # RTPSReader::~RTPSReader, inside libfastrtps, on every reader's deletion;
  # ASan has no suppression for this check other than turning it off.
  export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:new_delete_type_mismatch=0${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
  export LSAN_OPTIONS="suppressions=$supp/lsan.supp:print_suppressions=0${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
  export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
  export TSAN_OPTIONS="suppressions=$supp/tsan.supp:halt_on_error=1:second_deadlock_stack=1${TSAN_OPTIONS:+:$TSAN_OPTIONS}"
  # How much slower instrumented processes start and run, for the few test
  # waits that assume a process starts within a given time
  # (tests/support/slowdown.hpp); never applied to asserted bounds.
  case "$sanitize" in
    asan) export MTC_TEST_SLOWDOWN="${MTC_TEST_SLOWDOWN:-2}" ;;
    tsan) export MTC_TEST_SLOWDOWN="${MTC_TEST_SLOWDOWN:-3}" ;;
  esac
fi

# The schema tests validate against the official XSDs, which live outside
# the repository (tests/bridge/CMakeLists.txt, MTC_SCHEMA_DIR). Without them
# ~30 tests fail after the whole suite has run; a run of the whole suite
# (no -R/-L selection) says so at once instead, a selected run warns.
schema_dir="$(sed -n 's/^MTC_SCHEMA_DIR:PATH=//p' "$build/CMakeCache.txt" 2>/dev/null || true)"
if [ -n "$schema_dir" ] && [ ! -f "$schema_dir/MTConnectStreams_1.6_1.0.xsd" ]; then
  msg="the MTConnect XSDs are not in '$schema_dir' (MTC_SCHEMA_DIR): clone beside ../shared, or configure with -DMTC_SCHEMA_DIR=DIR"
  case " ${ctest_args[*]:-} " in
    *" -R "* | *" -L "* | *" -N "*) echo "test.sh: warning: $msg; the schema tests will fail" >&2 ;;
    *) echo "test.sh: error: $msg" >&2; exit 1 ;;
  esac
fi

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
