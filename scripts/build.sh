#!/usr/bin/env bash
# Configures and builds the project into <repo>/build (or $MTC_BUILD_DIR), after
# installing any missing package (scripts/setup-deps.sh).
#
# Usage: scripts/build.sh
# Environment: MTC_BUILD_DIR (default <repo>/build), MTC_BUILD_TYPE (default
# RelWithDebInfo), MTC_WERROR (default ON: warnings are errors),
# MTC_SANITIZE=asan (clang, ASan+UBSan, with the libFuzzer targets) or tsan
# (clang, TSan): a sanitizer build (cmake/MtcSanitizers.cmake); MTC_FUZZ_SECONDS
# (default 45): each fuzz run of an asan build (ctest label fuzz); MTC_CYCLONE
# (default ON for a GCC build, OFF for a sanitizer build): the Cyclone DDS types,
# QoS mapping and interop tests (label interop). On by default so that the
# test command, and with it CI, checks the wire between Fast DDS and Cyclone;
# off under the sanitizers because Debian's libddsc is not instrumented (TSan
# cannot see its synchronisation; the interop tests run none of our code that
# the GCC phase does not).
# A build folder that is already configured keeps its configuration unless
# MTC_BUILD_TYPE, MTC_WERROR or MTC_CYCLONE is set: the test command (scripts/test.sh) and
# the main command (scripts/start.sh) both build through here, and a switch
# that differed between them would make the second recompile everything.
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
config=()
configured=0
[ -f "$build/CMakeCache.txt" ] && configured=1
if [ -n "${MTC_BUILD_TYPE:-}" ] || [ "$configured" = 0 ]; then
  config+=(-DCMAKE_BUILD_TYPE="${MTC_BUILD_TYPE:-RelWithDebInfo}")
fi
if [ -n "${MTC_WERROR:-}" ] || [ "$configured" = 0 ]; then
  config+=(-DMTC_WERROR="${MTC_WERROR:-ON}")
fi
if [ -n "${MTC_CYCLONE:-}" ] || [ "$configured" = 0 ]; then
  cyclone_default=ON
  [ -n "${MTC_SANITIZE:-}" ] && cyclone_default=OFF
  config+=(-DMTC_CYCLONE="${MTC_CYCLONE:-$cyclone_default}")
fi
# Sanitizer builds use clang (CXX is read only when a build directory is
# first configured, so a rerun keeps its cache and objects).
case "${MTC_SANITIZE:-}" in
  "") ;;
  asan) export CXX=clang++
    config+=(-DMTC_SANITIZE=address -DMTC_FUZZ=ON -DMTC_FUZZ_SECONDS="${MTC_FUZZ_SECONDS:-45}") ;;
  tsan) export CXX=clang++
    config+=(-DMTC_SANITIZE=thread) ;;
  *) echo "build.sh: MTC_SANITIZE must be asan or tsan, not '$MTC_SANITIZE'" >&2; exit 2 ;;
esac
cmake -S "$root" -B "$build" "${config[@]}" >/dev/null
cmake --build "$build" -j "$(nproc)"
