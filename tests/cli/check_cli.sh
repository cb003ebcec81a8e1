#!/usr/bin/env bash
# CTest check of one program's command line (label cli; cmake/MtcCliCheck.cmake
# registers one test per executable and tool script):
#   <program> --help                      exit 0, "usage" on stdout, no benchmark result
#   <program> --definitely-not-an-option  exit 2, a message on stderr, nothing on stdout
# each within MTC_CLI_CHECK_SECONDS (default 30; generous, as the machine may be
# busy: an answer takes well under a second). A program that starts a run
# instead fails: a short run by printing its result ({"benchmark":...) rather
# than a usage, a long one by being stopped at that limit. Every command the
# program's usage lists under "Commands:" (mtc watch, ...) is checked the same way.
#
# Usage: tests/cli/check_cli.sh <program>
# Runs inside the loopback-only namespace (CMake wraps it in netns-run.sh).
set -uo pipefail

usage() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "${BASH_SOURCE[0]}"; }

case "${1:-}" in
  -h | --help) usage; exit 0 ;;
  -*) echo "check_cli.sh: unknown option '$1'" >&2; usage >&2; exit 2 ;;
  "") echo "check_cli.sh: which program?" >&2; usage >&2; exit 2 ;;
esac
[ $# -eq 1 ] || { echo "check_cli.sh: one program only" >&2; usage >&2; exit 2; }
program="$1"
[ -x "$program" ] || { echo "FAIL: $program is missing or not executable" >&2; exit 1; }

limit="${MTC_CLI_CHECK_SECONDS:-30}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
failures=0

fail() {
  echo "FAIL: $*" >&2
  failures=$((failures + 1))
}

# run <args...>: the program with a deadline; sets rc, out, err, seconds.
run() {
  local start=$EPOCHREALTIME
  rc=0
  # timeout signals its whole process group: children the program started go too.
  timeout -k 2 "$limit" "$program" "$@" </dev/null >"$work/out" 2>"$work/err" || rc=$?
  seconds="$(awk -v a="$start" -v b="$EPOCHREALTIME" 'BEGIN { printf "%.2f", b - a }')"
  out="$(cat "$work/out")"
  err="$(cat "$work/err")"
}

show() {
  echo "  --- stdout ---" >&2
  head -c 2000 <<<"$out" >&2
  echo "  --- stderr ---" >&2
  head -c 2000 <<<"$err" >&2
}

# A result line of a benchmark ({"benchmark":...}, perhaps after the colour
# codes of Google Benchmark's table) means it ran.
ran_a_benchmark() { grep -Eq $'^(\e\\[[0-9;]*m)*\\{"benchmark"' <<<"$out"; }

check_help() {  # check_help <args before --help...>
  local what="${*:+$* }--help"
  run "$@" --help
  if [ "$rc" = 124 ] || [ "$rc" = 137 ]; then
    fail "'$what' still running after $limit s: it started a run"
  elif [ "$rc" != 0 ]; then
    fail "'$what' exited $rc, expected 0"
  elif ! grep -qi usage <<<"$out"; then
    fail "'$what' printed no usage on stdout"
  elif ran_a_benchmark; then
    fail "'$what' printed a benchmark result: it ran"
  else
    echo "ok: $what (exit 0, usage, ${seconds} s)"
    return 0
  fi
  show
  return 1
}

check_unknown_option() {  # check_unknown_option <args before the option...>
  local what="${*:+$* }--definitely-not-an-option"
  run "$@" --definitely-not-an-option
  if [ "$rc" = 124 ] || [ "$rc" = 137 ]; then
    fail "'$what' still running after $limit s: it started a run"
  elif [ "$rc" != 2 ]; then
    fail "'$what' exited $rc, expected 2 (usage error)"
  elif [ -z "$err" ]; then
    fail "'$what' said nothing on stderr"
  elif [ -n "$out" ]; then
    fail "'$what' wrote to stdout (a usage error belongs on stderr)"
  else
    echo "ok: $what (exit 2, ${seconds} s, stderr: $(head -n1 <<<"$err"))"
    return 0
  fi
  show
  return 1
}

# The first word of each line under "Commands:" up to the next blank line.
commands_in_usage() {
  awk '/^Commands:/ { inside = 1; next } inside && /^[[:space:]]*$/ { exit }
       inside { print $1 }' <<<"$1"
}

echo "checking $program"
if check_help; then
  help_text="$out"
  check_unknown_option
  if grep -q '^Commands:' <<<"$help_text"; then
    commands="$(commands_in_usage "$help_text")"
    [ -n "$commands" ] || fail "usage has a Commands: section but no command in it"
    for command in $commands; do
      check_help "$command"
      check_unknown_option "$command"
    done
  fi
else
  check_unknown_option
fi

if [ "$failures" -gt 0 ]; then
  echo "$failures check(s) failed for $program" >&2
  exit 1
fi
echo "all checks passed for $program"
