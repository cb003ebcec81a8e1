#!/usr/bin/env bash
# Configures and builds the project into ./build (or $MTC_BUILD_DIR).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${MTC_BUILD_DIR:-$root/build}"
"$root/scripts/setup-deps.sh"
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE="${MTC_BUILD_TYPE:-RelWithDebInfo}" \
  -DMTC_WERROR="${MTC_WERROR:-OFF}" >/dev/null
cmake --build "$build" -j "$(nproc)"
