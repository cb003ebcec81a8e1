#!/usr/bin/env bash
# Installs the Debian bookworm packages the build, the tests and the tools
# need. Root installs with apt-get; anyone else gets the exact command to run.
#
# Usage: scripts/setup-deps.sh
set -euo pipefail

usage() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "${BASH_SOURCE[0]}"; }
case "${1:-}" in
  -h | --help) usage; exit 0 ;;
  "") ;;
  *) echo "setup-deps.sh: unknown option '$1'" >&2; usage >&2; exit 2 ;;
esac

PACKAGES=(
  build-essential cmake pkg-config
  libfastrtps-dev libfastcdr-dev fastddsgen fastdds-tools  # DDS, codegen, shm clean, discovery server
  libpugixml-dev                                           # XML in the bridge
  libboost-dev                                             # Boost.Beast/Asio HTTP (header-only)
  libssl-dev openssl                                       # DDS-Security checks, make-pki.sh
  libgtest-dev libgmock-dev libbenchmark-dev               # tests and benchmarks
  libxml2-utils                                            # xmllint schema checks
  iproute2 util-linux                                      # ip, unshare: loopback-only netns
  socat                                                    # start.sh --forward: HTTP into the netns
  curl wrk                                                 # HTTP checks and load
  python3                                                  # benchmark plots and summaries
  gnuplot-nox                                              # benchmarks/run.sh latency plots (PNG);
                                                           # bookworm has no matplotlib by default
  cyclonedds-tools                                         # ddsperf: Cyclone's round trip, the
                                                           # yardstick in mtc-bench-dds-latency;
                                                           # idlc for -DMTC_CYCLONE=ON
  cyclonedds-dev                                           # -DMTC_CYCLONE=ON: Cyclone DDS 0.10, the
                                                           # second middleware (interop tests)
  chromium                                                 # the live page's browser test (headless)
  clang-format clang-tidy                                  # lint.format, lint.tidy (scripts/lint.sh)
  clang libclang-rt-14-dev llvm                           # sanitizer builds, libFuzzer, symbolizer
)

missing=()
for pkg in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$pkg")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

if [ "$(id -u)" -ne 0 ]; then
  echo "error: missing packages: ${missing[*]}" >&2
  echo "install them as root with:" >&2
  echo "  apt-get update && apt-get install -y ${missing[*]}" >&2
  exit 1
fi

echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
