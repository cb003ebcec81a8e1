#!/usr/bin/env python3
"""Checks that keep README.md and docs/ true to the tree (CTest label docs).

Usage: docs/check_docs.py CHECK [--root DIR]

Checks:
  layout_matches_tree       every path in the README's layout table exists, and
                            every top-level folder tracked by git is in it
  links_resolve             every relative link in README.md and docs/*.md
                            points to an existing file or folder (anchors aside)
  snippets_match_sources    every code block after <!-- snippet: PATH --> equals
                            the lines between the [snippet] markers of PATH, and
                            every file under examples/ with markers is quoted
  dependencies_match_setup  the README's dependencies table names exactly the
                            packages scripts/setup-deps.sh installs

--root DIR: the repository (default: the folder above this script's).
Exit codes: 0 the check holds, 1 it does not (each problem printed), 2 usage.
"""

import argparse
import difflib
import fnmatch
import re
import subprocess
import sys
import textwrap
from pathlib import Path

SNIPPET_MARKERS = ("// [snippet]", "# [snippet]")
SNIPPET_REF = re.compile(r"<!--\s*snippet:\s*(\S+)\s*-->")
FENCE = re.compile(r"^\s*(```|~~~)")


def section(text, heading):
    """Lines of the `## heading` section of a markdown text (without the heading)."""
    lines = text.splitlines()
    for i, line in enumerate(lines):
        if line.strip() == "## " + heading:
            end = next((j for j in range(i + 1, len(lines)) if lines[j].startswith("## ")),
                       len(lines))
            return lines[i + 1:end]
    return None


def first_column_tokens(lines):
    """Backticked words of the first column of every table row in `lines`."""
    rows = [line for line in lines if line.lstrip().startswith("|")]
    tokens = []
    for row in rows[2:]:  # header and separator first
        cells = row.strip().strip("|").split("|")
        tokens.extend(re.findall(r"`([^`]+)`", cells[0]))
    return tokens


def readme_table(root, heading):
    text = (root / "README.md").read_text(encoding="utf-8")
    lines = section(text, heading)
    if lines is None:
        return None
    return first_column_tokens(lines)


def tracked_top_folders(root):
    """Top-level folders git tracks files in; without git, those on disk that
    .gitignore does not exclude."""
    try:
        out = subprocess.run(["git", "-C", str(root), "ls-files", "-z"], check=True,
                             capture_output=True).stdout.decode()
        return {p.split("/")[0] for p in out.split("\0") if "/" in p}
    except (OSError, subprocess.CalledProcessError):
        print("note: not a git checkout, listing the folders on disk instead")
    ignored = []
    gitignore = root / ".gitignore"
    if gitignore.exists():
        for line in gitignore.read_text().splitlines():
            line = line.strip()
            if line and not line.startswith("#"):
                ignored.append(line.strip("/"))
    return {p.name for p in root.iterdir()
            if p.is_dir() and p.name != ".git"
            and not any(fnmatch.fnmatch(p.name, pattern) for pattern in ignored)}


def check_layout(root):
    tokens = readme_table(root, "Layout")
    if not tokens:
        return ["README.md: no '## Layout' section with a table of `paths`"]
    problems = []
    for path in tokens:
        target = root / path
        if path.endswith("/") and not target.is_dir():
            problems.append(f"README.md layout: `{path}` is not a folder of the tree")
        elif not path.endswith("/") and not target.exists():
            problems.append(f"README.md layout: `{path}` does not exist")
    listed = {t.strip("/") for t in tokens if t.count("/") == 1 and t.endswith("/")}
    for folder in sorted(tracked_top_folders(root) - listed):
        problems.append(f"README.md layout: top-level folder `{folder}/` is not listed")
    if not problems:
        print(f"layout: {len(tokens)} paths exist, every top-level folder is listed")
    return problems


def markdown_files(root):
    return [root / "README.md"] + sorted((root / "docs").glob("*.md"))


def prose(text):
    """The text without fenced code blocks and inline code spans, lines kept."""
    kept, fenced = [], False
    for line in text.splitlines():
        if FENCE.match(line):
            fenced = not fenced
            kept.append("")
            continue
        kept.append("" if fenced else re.sub(r"`[^`]*`", "", line))
    return kept


LINK_PATTERNS = (
    re.compile(r"!?\[[^\]]*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)"),  # [text](target)
    re.compile(r"^\s*\[[^\]]+\]:\s*<?(\S+?)>?(?:\s|$)"),  # [label]: target
    re.compile(r"(?:src|href)\s*=\s*\"([^\"]+)\""),  # HTML
)


def check_links(root):
    problems, count = [], 0
    for md in markdown_files(root):
        for number, line in enumerate(prose(md.read_text(encoding="utf-8")), 1):
            for pattern in LINK_PATTERNS:
                for target in pattern.findall(line):
                    if re.match(r"^[a-zA-Z][a-zA-Z0-9+.-]*:", target) or target.startswith("#"):
                        continue  # a URL, mailto:, or an anchor in the same page
                    path = target.split("#")[0].split("?")[0]
                    base = root if path.startswith("/") else md.parent
                    count += 1
                    if not (base / path.lstrip("/")).exists():
                        where = md.relative_to(root)
                        problems.append(f"{where}:{number}: link to '{target}': no such file")
    if not problems:
        print(f"links: {count} relative links in {len(markdown_files(root))} pages resolve")
    return problems


def snippet_region(path):
    """The dedented lines between the two [snippet] markers of `path`."""
    lines = path.read_text(encoding="utf-8").splitlines()
    marks = [i for i, line in enumerate(lines) if line.strip() in SNIPPET_MARKERS]
    if len(marks) != 2:
        return None
    body = "\n".join(lines[marks[0] + 1:marks[1]])
    return [line.rstrip() for line in textwrap.dedent(body).splitlines()]


def quoted_snippets(md):
    """(line number, PATH, code block lines) for each <!-- snippet: PATH -->."""
    lines = md.read_text(encoding="utf-8").splitlines()
    found = []
    for i, line in enumerate(lines):
        ref = SNIPPET_REF.search(line)
        if not ref:
            continue
        start = next((j for j in range(i + 1, len(lines)) if lines[j].strip()), None)
        if start is None or not FENCE.match(lines[start]):
            found.append((i + 1, ref.group(1), None))
            continue
        end = next((j for j in range(start + 1, len(lines)) if FENCE.match(lines[j])), len(lines))
        found.append((i + 1, ref.group(1), [x.rstrip() for x in lines[start + 1:end]]))
    return found


def check_snippets(root):
    problems, quoted = [], set()
    for md in markdown_files(root):
        where = md.relative_to(root)
        for number, ref, block in quoted_snippets(md):
            source = root / ref
            quoted.add(source.resolve())
            if block is None:
                problems.append(f"{where}:{number}: no code block follows the snippet marker")
                continue
            if not source.is_file():
                problems.append(f"{where}:{number}: snippet source {ref} does not exist")
                continue
            region = snippet_region(source)
            if region is None:
                problems.append(f"{ref}: needs exactly two [snippet] marker lines")
            elif region != block:
                diff = difflib.unified_diff(region, block, ref, f"{where}:{number}", lineterm="")
                problems.append(f"{where}:{number}: the quoted snippet differs from {ref}:\n" +
                                "\n".join(diff))
    for source in sorted((root / "examples").rglob("*")):
        if source.is_file() and source.resolve() not in quoted:
            text = source.read_text(encoding="utf-8", errors="replace")
            if any(marker in text for marker in SNIPPET_MARKERS):
                problems.append(f"{source.relative_to(root)}: has [snippet] markers, "
                                "but no page quotes it")
    if not problems:
        print(f"snippets: {len(quoted)} quoted sources match their markers")
    return problems


def setup_packages(root):
    text = (root / "scripts" / "setup-deps.sh").read_text(encoding="utf-8")
    match = re.search(r"^PACKAGES=\((.*?)^\)", text, re.S | re.M)
    if not match:
        return None
    words = []
    for line in match.group(1).splitlines():
        words.extend(line.split("#")[0].split())
    return set(words)


def check_dependencies(root):
    installed = setup_packages(root)
    if installed is None:
        return ["scripts/setup-deps.sh: no PACKAGES=( ... ) list found"]
    tokens = readme_table(root, "Dependencies")
    if not tokens:
        return ["README.md: no '## Dependencies' section with a table of `packages`"]
    listed = set(tokens)
    problems = [f"README.md dependencies: `{p}` is installed by scripts/setup-deps.sh "
                "but not listed" for p in sorted(installed - listed)]
    problems += [f"README.md dependencies: `{p}` is listed but scripts/setup-deps.sh "
                 "does not install it" for p in sorted(listed - installed)]
    if not problems:
        print(f"dependencies: the README lists the {len(installed)} packages setup-deps.sh installs")
    return problems


CHECKS = {
    "layout_matches_tree": check_layout,
    "links_resolve": check_links,
    "snippets_match_sources": check_snippets,
    "dependencies_match_setup": check_dependencies,
}


class Parser(argparse.ArgumentParser):
    def error(self, message):
        self.print_usage(sys.stderr)
        print(f"check_docs.py: {message}", file=sys.stderr)
        sys.exit(2)


def main():
    parser = Parser(prog="check_docs.py", description=__doc__.split("\n\n")[0],
                    epilog=__doc__.split("\n\n", 1)[1],
                    formatter_class=argparse.RawDescriptionHelpFormatter, usage=None)
    parser.add_argument("check", choices=sorted(CHECKS), metavar="CHECK")
    parser.add_argument("--root", type=Path, default=Path(__file__).resolve().parent.parent)
    args = parser.parse_args()
    root = args.root.resolve()
    if not (root / "README.md").is_file():
        parser.error(f"{root} has no README.md")
    problems = CHECKS[args.check](root)
    for problem in problems:
        print(problem, file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
