#!/usr/bin/env bash
# Checks the C++ against the repo's .clang-format and .clang-tidy, or fixes it.
# CTest runs the two checks as lint.format and lint.tidy (label lint).
#
# Usage: scripts/lint.sh [--fix] [--format | --tidy] [--build DIR] [--jobs N] [FILE...]
#   (no option)   check formatting, then run clang-tidy; exit 1 on any finding
#   --fix         reformat in place and apply clang-tidy's fix-its (review the diff)
#   --format      clang-format only: every tracked C/C++ file (git ls-files)
#   --tidy        clang-tidy only: every project translation unit in the build's
#                 compile_commands.json and the project headers they include;
#                 generated IDL code and third-party headers are left out
#   --build DIR   build directory holding compile_commands.json
#                 (default: $MTC_BUILD_DIR, else <repo>/build; run scripts/build.sh first)
#   --jobs N      clang-tidy processes at once (default 2)
#   FILE...       only these files (repo-relative or absolute)
#   -h, --help    this text
# Exit codes: 0 clean, 1 findings or a tool missing, 2 usage error.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
usage() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "${BASH_SOURCE[0]}"; }
bad_usage() { echo "lint.sh: $1" >&2; usage >&2; exit 2; }

# Top-level folders holding our C++; anything else (the build tree with its
# generated IDL code, system and third-party headers) is not ours to lint.
project_dirs="core|qos|idl|dds|bridge|apps|examples|benchmarks|tests"

fix=0
do_format=1
do_tidy=1
build="${MTC_BUILD_DIR:-$root/build}"
jobs=2
files=()
while [ $# -gt 0 ]; do
  case "$1" in
    -h | --help) usage; exit 0 ;;
    --fix) fix=1; shift ;;
    --format) do_tidy=0; shift ;;
    --tidy) do_format=0; shift ;;
    --build | --jobs)
      [ $# -ge 2 ] || bad_usage "$1 needs a value"
      if [ "$1" = --build ]; then build="$2"; else jobs="$2"; fi
      shift 2 ;;
    --) shift; files+=("$@"); break ;;
    -*) bad_usage "unknown option '$1'" ;;
    *) files+=("$1"); shift ;;
  esac
done
[ "$do_format" -eq 1 ] || [ "$do_tidy" -eq 1 ] || bad_usage "--format and --tidy exclude each other"
[[ "$jobs" =~ ^[1-9][0-9]*$ ]] || bad_usage "--jobs takes a positive number, not '$jobs'"

need() {
  command -v "$1" >/dev/null 2>&1 && return 0
  echo "lint.sh: '$1' not found; install it with scripts/setup-deps.sh" >&2
  exit 1
}

# The files given on the command line, as absolute paths.
given=()
for f in "${files[@]}"; do
  case "$f" in
    /*) given+=("$f") ;;
    *) given+=("$PWD/$f") ;;
  esac
done

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# Every C/C++ file of the project: the tracked ones when this is a git
# checkout (CI runs on a clean clone), else a glob over the project folders.
source_files() {
  if [ ${#given[@]} -gt 0 ]; then
    printf '%s\n' "${given[@]}"
  elif git -C "$root" rev-parse --is-inside-work-tree >/dev/null 2>&1; then
    git -C "$root" ls-files -z -- '*.cpp' '*.hpp' '*.h' '*.cc' '*.cxx' '*.hh' '*.c' |
      while IFS= read -r -d '' f; do [ -f "$root/$f" ] && echo "$root/$f"; done
  else
    local d
    for d in ${project_dirs//|/ }; do
      [ -d "$root/$d" ] && find "$root/$d" -type f \( -name '*.cpp' -o -name '*.hpp' \
        -o -name '*.h' -o -name '*.cc' -o -name '*.cxx' -o -name '*.hh' -o -name '*.c' \)
    done
  fi
}

run_format() {
  need clang-format
  local list
  mapfile -t list < <(source_files)
  [ ${#list[@]} -gt 0 ] || { echo "lint.sh: no C/C++ files found" >&2; exit 1; }
  if [ "$fix" -eq 1 ]; then
    clang-format -i --style=file "${list[@]}"
    echo "lint.sh: clang-format: reformatted ${#list[@]} files in place"
    return 0
  fi
  if clang-format --dry-run -Werror --style=file "${list[@]}"; then
    echo "lint.sh: clang-format: ${#list[@]} files clean"
    return 0
  fi
  echo "lint.sh: clang-format: files above differ from .clang-format;" \
    "fix with scripts/lint.sh --fix --format" >&2
  return 1
}

# The project's translation units in the compile database, each once; with
# FILE arguments only those among them.
tidy_units() {
  python3 - "$build/compile_commands.json" "$root" "$project_dirs" "$@" <<'EOF'
import json, os, re, sys
db, root, dirs, wanted = sys.argv[1], os.path.realpath(sys.argv[2]), sys.argv[3], sys.argv[4:]
ours = re.compile("^" + re.escape(root) + "/(" + dirs + ")/")
wanted = {os.path.realpath(w) for w in wanted}
seen = set()
for entry in json.load(open(db)):
    path = os.path.realpath(os.path.join(entry["directory"], entry["file"]))
    if ours.match(path) and path not in seen and (not wanted or path in wanted):
        seen.add(path)
        print(path)
EOF
}

run_tidy() {
  need clang-tidy
  need python3
  if [ ! -f "$build/compile_commands.json" ]; then
    echo "lint.sh: no $build/compile_commands.json; build first (scripts/build.sh)" \
      "or name the build directory with --build" >&2
    exit 1
  fi
  local units
  mapfile -t units < <(tidy_units "${given[@]}")
  [ ${#units[@]} -gt 0 ] || { echo "lint.sh: no translation units to check in $build" >&2; exit 1; }

  # Anchored at the checkout, so the build tree's generated IDL headers stay out
  # even when a folder name such as idl/ appears in their path.
  local roots
  roots="$(printf '%s\n%s\n' "$root" "$(cd "$root" && pwd -P)" | sort -u |
    sed 's/[][\.*^$+?(){}|]/\\&/g' | paste -sd '|')"
  export LINT_HEADER_FILTER="^(${roots})/(${project_dirs})/"
  export LINT_BUILD="$build" LINT_WORK="$work" LINT_FIX="$fix"
  local started=$SECONDS status=0
  printf '%s\0' "${units[@]}" | xargs -0 -n 1 -P "$jobs" bash -c '
    unit="$1"
    fixes=()
    if [ "$LINT_FIX" -eq 1 ]; then
      fixes=(--export-fixes="$LINT_WORK/$(printf %s "$unit" | md5sum | cut -c1-16).yaml")
    fi
    # clang-tidy counts the warnings it suppressed in system headers; only
    # the findings are worth printing.
    out="$(clang-tidy -p "$LINT_BUILD" --quiet --header-filter="$LINT_HEADER_FILTER" \
      --warnings-as-errors="*" "${fixes[@]}" "$unit" 2>&1)" && rc=0 || rc=$?
    out="$(printf "%s\n" "$out" | grep -vE "^[0-9]+ warnings? generated\.$" || true)"
    [ -z "$out" ] || printf "%s\n" "$out"
    [ "$rc" -eq 0 ] || echo "$unit" >>"$LINT_WORK/failed"
    exit 0
  ' lint-tidy || status=$?
  local failed=0
  [ -f "$work/failed" ] && failed=$(wc -l <"$work/failed")
  echo "lint.sh: clang-tidy: ${#units[@]} translation units, $failed with findings," \
    "$((SECONDS - started)) s"
  if [ "$fix" -eq 1 ] && compgen -G "$work/*.yaml" >/dev/null; then
    local apply
    apply="$(command -v clang-apply-replacements || command -v clang-apply-replacements-14 || true)"
    [ -n "$apply" ] || { echo "lint.sh: clang-apply-replacements not found" >&2; return 1; }
    # One pass over all exported fixes: a header fixed from several
    # translation units gets each edit once.
    "$apply" --format --style=file "$work"
    echo "lint.sh: clang-tidy: fixes applied; rerun scripts/lint.sh for what is left"
    return 0
  fi
  [ "$status" -eq 0 ] && [ "$failed" -eq 0 ]
}

result=0
if [ "$do_format" -eq 1 ]; then
  run_format || result=1
fi
if [ "$do_tidy" -eq 1 ]; then
  run_tidy || result=1
fi
exit "$result"
