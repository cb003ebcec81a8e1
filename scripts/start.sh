#!/usr/bin/env bash
# The README's main command: builds the project, then runs the main job inside
# a loopback-only network namespace.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${MTC_BUILD_DIR:-$root/build}"
"$root/scripts/build.sh"
exec "$root/scripts/netns-run.sh" "$build/apps/mtc-interaction-demo" "$@"
