#!/usr/bin/env bash
# Fuzzes the bridge's and the runtime's inputs with libFuzzer (clang): the
# HTTP request, the XPath path filter, the Devices file, the bridge config and
# received DDS samples (tests/fuzz/README.md). Builds the fuzz targets with
# ASan+UBSan (MTC_FUZZ=ON) and runs each for a while; a crash, leak, timeout
# or broken invariant fails the run and leaves the input under
# <build>/tests/fuzz/runs/<name>/ (copy it to tests/fuzz/regressions/<name>/
# once fixed). CI runs the same targets as ctest label "fuzz" from
# `scripts/test.sh --sanitize asan`.
#
# Usage: scripts/fuzz.sh [--seconds N] [NAME...]
#        scripts/fuzz.sh --run FUZZER SEEDS WORKDIR SECONDS [LIBFUZZER OPTION...]
#   --seconds N   how long each target runs (default 60)
#   NAME          only these targets (http_request path_filter devices_file
#                 bridge_config dds_samples; default all)
#   --run         one run of one built target (what each ctest "fuzz" test
#                 does): reads SEEDS, writes new inputs and findings to
#                 WORKDIR, prints "fuzz.sh: NAME: N execs ..." and fails on a
#                 finding or when nothing ran
# Environment: MTC_BUILD_DIR (default <repo>/build-asan).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
usage() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "${BASH_SOURCE[0]}"; }
all_targets=(http_request path_filter devices_file bridge_config dds_samples)

run_one() {  # run_one FUZZER SEEDS WORKDIR SECONDS [OPTIONS...]
  local fuzzer="$1" seeds="$2" work="$3" seconds="$4"
  shift 4
  local name
  name="$(basename "$fuzzer")"
  name="${name#fuzz_}"
  [ -x "$fuzzer" ] || { echo "fuzz.sh: $fuzzer is not a built fuzz target" >&2; exit 2; }
  [ -d "$seeds" ] || { echo "fuzz.sh: no seed directory $seeds" >&2; exit 2; }
  [[ "$seconds" =~ ^[1-9][0-9]*$ ]] || { echo "fuzz.sh: SECONDS must be a positive integer" >&2; exit 2; }
  rm -rf "$work"
  mkdir -p "$work/corpus"
  local log="$work/fuzz.log" status=0
  # -timeout: an input that takes 10 s is a finding (the path filter's budget
  # is 1 s even under ASan); -error_exitcode makes every finding exit 77.
  "$fuzzer" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -error_exitcode=77 -timeout_exitcode=77 -artifact_prefix="$work/" "$@" \
    "$work/corpus" "$seeds" >"$log" 2>&1 || status=$?
  local execs
  execs="$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)"
  if [ "$status" -ne 0 ]; then
    tail -n 60 "$log" >&2
    echo "fuzz.sh: $name: FAILED (exit $status); input(s) in $work:" >&2
    ls "$work" | grep -E '^(crash|leak|timeout|oom|slow-unit)-' >&2 || true
    exit 1
  fi
  if [ -z "$execs" ] || [ "$execs" -eq 0 ]; then
    tail -n 20 "$log" >&2
    echo "fuzz.sh: $name: no input was run" >&2
    exit 1
  fi
  echo "fuzz.sh: $name: $execs execs in ${seconds} s, corpus $(ls "$work/corpus" | wc -l) new + $(ls "$seeds" | wc -l) seed inputs"
}

seconds=60
names=()
while [ $# -gt 0 ]; do
  case "$1" in
    -h | --help) usage; exit 0 ;;
    --run)
      [ $# -ge 5 ] || { echo "fuzz.sh: --run needs FUZZER SEEDS WORKDIR SECONDS" >&2; usage >&2; exit 2; }
      shift
      run_one "$@"
      exit 0 ;;
    --seconds)
      [ $# -ge 2 ] && [[ "$2" =~ ^[1-9][0-9]*$ ]] ||
        { echo "fuzz.sh: --seconds needs a positive integer" >&2; usage >&2; exit 2; }
      seconds="$2"; shift 2 ;;
    -*) echo "fuzz.sh: unknown option '$1'" >&2; usage >&2; exit 2 ;;
    *)
      [[ " ${all_targets[*]} " == *" $1 "* ]] ||
        { echo "fuzz.sh: no fuzz target '$1' (${all_targets[*]})" >&2; exit 2; }
      names+=("$1"); shift ;;
  esac
done
[ ${#names[@]} -gt 0 ] || names=("${all_targets[@]}")

build="${MTC_BUILD_DIR:-$root/build-asan}"
"$root/scripts/setup-deps.sh"
# The compiler only when the folder is new: naming it again on a configured
# folder may make cmake drop its cache, and a changed MTC_WERROR recompiles
# the tree (scripts/build.sh keeps a configuration the same way).
config=(-DMTC_SANITIZE=address -DMTC_FUZZ=ON)
[ -f "$build/CMakeCache.txt" ] || config+=(-DCMAKE_CXX_COMPILER=clang++)
if [ -n "${MTC_WERROR:-}" ] || [ ! -f "$build/CMakeCache.txt" ]; then
  config+=(-DMTC_WERROR="${MTC_WERROR:-ON}")
fi
cmake -S "$root" -B "$build" "${config[@]}" >/dev/null
cmake --build "$build" -j "$(nproc)" --target "${names[@]/#/fuzz_}"
for name in "${names[@]}"; do
  dict=()
  [ -f "$root/tests/fuzz/dict/$name.dict" ] && dict=(-dict="$root/tests/fuzz/dict/$name.dict")
  run_one "$build/tests/fuzz/fuzz_$name" "$root/tests/fuzz/corpus/$name" \
    "$build/tests/fuzz/runs/$name" "$seconds" "${dict[@]}"
done
