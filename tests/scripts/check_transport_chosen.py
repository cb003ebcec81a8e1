#!/usr/bin/env python3
"""Fails when a test, benchmark, example or script leaves the DDS transport to
its default (issue 10). The runtime and the tools default to the network
(Fast DDS's builtin UDPv4 + SHM); whatever runs in CI chooses loopback, or the
network on purpose (tests/multihost), and says so where it builds options or
starts a tool. A source scan, rule by rule:

  C++   - a variable of type EquipmentOptions, DomainObserverOptions or
          ParticipantConfig declared without an initialiser (`T name;`,
          `T name{};`, `T name = {};`) must be given `name.transport = ...`
          (or be handed to a function named *transport*) before its block
          closes;
        - a temporary `T{}` / `T()` of those types, or `participant_qos({})`,
          is refused (nothing can choose its transport);
        - a function that names a tool's path (a macro that CMake defines as
          $<TARGET_FILE:mtc|mtc-bridge|mtc_cell>, or a constant set from one)
          must contain "--transport" or call with_loopback_transport().
  shell - a command that runs `$mtc`, `$cell`, `$bridge` (or a variable set to
          a path ending in /mtc, /mtc-cell, /mtc-bridge, or such a path itself)
          must pass --transport (or --help).
  Python - a list that starts with such a path (os.path.join(..., "mtc-cell"))
          must contain "--transport" (or "--help").

A line (C++: the line itself or the one above; for the tool rule, anywhere in
the function or the comment above it) holding `transport-guard: <reason>` is
exempt, for the few places that mean the default (the tests of the defaults)
or never start DDS.

Usage: check_transport_chosen.py [--root DIR] [--self-test] [FILE...]
  --root DIR   the checkout to scan (default: the one holding this script)
  --self-test  scan the planted cases in tests/scripts/transport_guard/ instead:
               every line marked `expect-finding` must be reported and no other
               (the guard seen red on purpose, and precise)
  FILE...      scan only these files; a trailing .in is dropped to pick the
               language (x.cpp.in is C++)
Exit codes: 0 every transport chosen (self-test: as planted), 1 findings (one
line each) or a self-test mismatch, 2 usage error.
"""
import ast
import os
import re
import shlex
import sys

TYPES = ("EquipmentOptions", "DomainObserverOptions", "ParticipantConfig")
TOOLS = ("mtc", "mtc-cell", "mtc-bridge")
TOOL_TARGETS = ("mtc", "mtc-bridge", "mtc_cell")
SHELL_TOOL_VARS = {"mtc", "cell", "bridge"}
WAIVER = "transport-guard:"
# Folders whose sources run DDS in CI or for a user of the repo.
SCAN_DIRS = ("tests", "benchmarks", "examples", "scripts", "apps", ".ci")
CPP_EXT = (".cpp", ".hpp", ".h")
FIXTURES = os.path.join("tests", "scripts", "transport_guard")


def usage(out):
    """--help: the whole text; a usage error: the Usage part only."""
    out.write(__doc__ if out is sys.stdout else __doc__[__doc__.index("Usage:"):])


# ------------------------------------------------------------------ C++

def blank_comments_and_strings(text):
    """The text with comments blanked and string/char literal contents
    replaced by spaces (quotes kept), same length, so offsets and line
    numbers stay. Literals are returned separately: (start, end, text)."""
    out = list(text)
    literals = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            for k in range(i, j):
                out[k] = " "
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            for k in range(i, j):
                if out[k] != "\n":
                    out[k] = " "
            i = j
        elif text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            m = re.match(r'R"([^(\s]*)\(', text[i:])
            if not m:
                i += 1
                continue
            end = text.find(")" + m.group(1) + '"', i)
            end = n if end < 0 else end + len(m.group(1)) + 2
            literals.append((i, end, text[i:end]))
            for k in range(i + 1, end - 1):
                if out[k] != "\n":
                    out[k] = " "
            i = end
        elif c in "\"'":
            if c == "'" and i > 0 and text[i - 1].isalnum():  # digit separator 1'000
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            j = min(j + 1, n)
            literals.append((i, j, text[i:j]))
            for k in range(i + 1, j - 1):
                out[k] = " "
            i = j
        else:
            i += 1
    return "".join(out), literals


def blocks(code):
    """Every brace block as (open, close, is_namespace), open/close offsets
    of its braces; is_namespace for `namespace x {` and `extern "C" {`."""
    found, stack = [], []
    for i, c in enumerate(code):
        if c == "{":
            head = code[max(0, i - 200):i]
            is_ns = re.search(r'(\bnamespace(\s+[\w:]+)?|\bextern\s+"\s*")\s*$', head) is not None
            stack.append((i, is_ns))
        elif c == "}" and stack:
            start, is_ns = stack.pop()
            found.append((start, i, is_ns))
    return found


def innermost(blocks_, pos):
    best = None
    for start, end, is_ns in blocks_:
        if start < pos <= end and (best is None or start > best[0]):
            best = (start, end, is_ns)
    return best


def function_block(blocks_, pos):
    """The outermost block around pos that is not a namespace (a function, or
    the class holding it)."""
    best = None
    for start, end, is_ns in blocks_:
        if start < pos <= end and not is_ns and (best is None or start < best[0]):
            best = (start, end, is_ns)
    return best


def line_of(text, pos):
    return text.count("\n", 0, pos) + 1


def waived(lines, line_no):
    here = lines[line_no - 1]
    above = lines[line_no - 2] if line_no >= 2 else ""
    return WAIVER in here or WAIVER in above


def tool_macros(root):
    """Macros CMake defines as a tool's path: NAME="$<TARGET_FILE:mtc>"."""
    names = set()
    pattern = re.compile(r'(\w+)="?\$<TARGET_FILE:(%s)>' % "|".join(map(re.escape, TOOL_TARGETS)))
    for folder, _, files in os.walk(root):
        if "CMakeLists.txt" in files:
            with open(os.path.join(folder, "CMakeLists.txt"), encoding="utf-8") as f:
                names.update(m.group(1) for m in pattern.finditer(f.read()))
    return names


def check_cpp(path, text, macros, findings):
    code, literals = blank_comments_and_strings(text)
    lines = text.split("\n")
    blocks_ = blocks(code)
    types = "|".join(TYPES)
    decl = re.compile(r"\b(?:%s)\s+([A-Za-z_]\w*)\s*(;|\{\s*\}\s*;|=\s*\{\s*\}\s*;)" % types)
    for m in decl.finditer(code):
        name, line_no = m.group(1), line_of(code, m.start())
        if waived(lines, line_no):
            continue
        block = innermost(blocks_, m.start())
        scope = code[m.end():block[1]] if block else code[m.end():]
        chosen = r"\b%s\s*\.\s*transport\s*=[^=]" % re.escape(name)
        # ... or handed to a helper that chooses it: set_transport(o, eo).
        helper = r"\b\w*transport\w*\s*\([^;)]*\b%s\b" % re.escape(name)
        if not re.search(chosen, scope) and not re.search(helper, scope):
            findings.append("%s:%d: %s has no transport chosen (set %s.transport)"
                            % (path, line_no, name, name))
    temp = re.compile(r"\b(%s)\s*(\{\s*\}|\(\s*\))|\bparticipant_qos\s*\(\s*\{\s*\}\s*\)" % types)
    for m in temp.finditer(code):
        line_no = line_of(code, m.start())
        if not waived(lines, line_no):
            findings.append("%s:%d: `%s` leaves the transport to its default (the network)"
                            % (path, line_no, " ".join(m.group(0).split())))
    check_cpp_tools(path, text, code, literals, blocks_, macros, findings)


def check_cpp_tools(path, text, code, literals, blocks_, macros, findings):
    names = set(macros)
    # Constants set from a tool macro count as the tool: kBridge = MTC_BRIDGE_EXE.
    for m in re.finditer(r"\b([A-Za-z_]\w*)\s*=\s*(%s)\s*;" % "|".join(map(re.escape, macros)),
                         code) if macros else ():
        names.add(m.group(1))
    if not names:
        return
    uses = re.compile(r"\b(%s)\b" % "|".join(map(re.escape, sorted(names))))
    seen = set()
    for m in uses.finditer(code):
        block = function_block(blocks_, m.start())
        if block is None or block in seen:
            continue  # namespace scope: a constant's definition, judged where used
        seen.add(block)
        # The function with the comment above it (from the end of whatever
        # precedes it), where a waiver may stand.
        head = max(code.rfind("}", 0, block[0]), code.rfind(";", 0, block[0])) + 1
        body = text[head:block[1]]
        has_flag = any('"--transport"' in lit for start, end, lit in literals
                       if block[0] <= start < block[1])
        has_flag = has_flag or "with_loopback_transport(" in code[block[0]:block[1]]
        if not has_flag and WAIVER not in body:
            findings.append("%s:%d: starts %s without \"--transport\" in the same function"
                            % (path, line_of(code, m.start()), m.group(1)))


# ------------------------------------------------------------------ shell

def logical_lines(text):
    """(line number, text) with backslash continuations joined."""
    out, buf, start = [], "", None
    for no, line in enumerate(text.split("\n"), 1):
        if start is None:
            start = no
        if line.endswith("\\"):
            buf += line[:-1] + " "
            continue
        out.append((start, buf + line))
        buf, start = "", None
    return out


def shell_words(line):
    lexer = shlex.shlex(line, posix=True, punctuation_chars=";&|()<>")
    lexer.whitespace_split = True
    lexer.commenters = "#"
    try:
        return list(lexer)
    except ValueError:  # an unbalanced quote across lines (heredoc, awk): not a command
        return []


def shell_tool_vars(text):
    names = set(SHELL_TOOL_VARS)
    ends = "|".join(map(re.escape, TOOLS))
    for m in re.finditer(r'\b([A-Za-z_]\w*)="?[^"\s]*/(%s)"?(\s|$)' % ends, text):
        names.add(m.group(1))
    return names


def is_tool_word(word, names):
    m = re.fullmatch(r"\$\{?([A-Za-z_]\w*)\}?", word)
    if m:
        return m.group(1) in names
    return re.search(r"/(%s)$" % "|".join(map(re.escape, TOOLS)), word) is not None and "=" not in word


NOT_RUNS = {"[", "[[", "test", "echo", "printf", "kill", "basename", "readlink", "dirname",
            "command", "type", "which", "pgrep", "pkill", "rm", "cat", "ls", "tail", "grep"}
SEPARATORS = {";", "&", "&&", "|", "||", "(", ")", ";;", "|&"}


def check_shell(path, text, findings):
    names = shell_tool_vars(text)
    lines = text.split("\n")
    for line_no, line in logical_lines(text):
        if WAIVER in line or WAIVER in (lines[line_no - 2] if line_no >= 2 else ""):
            continue
        words = shell_words(line)
        command = []
        for word in words + [";"]:
            if word not in SEPARATORS:
                command.append(word)
                continue
            check_shell_command(path, line_no, command, names, findings)
            command = []


def check_shell_command(path, line_no, command, names, findings):
    for i, word in enumerate(command):
        if not is_tool_word(word, names):
            continue
        first = next((w for w in command if not re.match(r"^[A-Za-z_]\w*=", w)), "")
        before = command[i - 1] if i > 0 else ""
        # A test (-x "$cell"), an option's value (--security "$pki/mtc-bridge")
        # or a redirection (<"$cell") names the file; it does not run it.
        if first in NOT_RUNS or before.startswith("-") or before[-1:] in ("<", ">"):
            continue
        rest = command[i + 1:]
        if not any(w in ("--transport", "--help", "-h") for w in rest):
            findings.append("%s:%d: runs %s without --transport" % (path, line_no, word))


# ------------------------------------------------------------------ Python

def names_tool(node, others):
    """True when `node`, the first element of a list, is a tool's path:
    os.path.join(..., "mtc-cell"), "/path/to/mtc", or a bare "mtc-cell"
    followed by options (a bare name among names is data)."""
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        if os.path.basename(node.value) not in TOOLS:
            return False
        return "/" in node.value or any(
            isinstance(e, ast.Constant) and isinstance(e.value, str) and e.value.startswith("-")
            for e in others)
    if isinstance(node, ast.Call) and node.args:
        last = node.args[-1]
        return isinstance(last, ast.Constant) and last.value in TOOLS
    return False


def check_python(path, text, findings):
    try:
        tree = ast.parse(text)
    except SyntaxError as e:
        findings.append("%s:%s: cannot parse: %s" % (path, e.lineno, e.msg))
        return
    lines = text.split("\n")
    for node in ast.walk(tree):
        if not isinstance(node, ast.List) or not node.elts:
            continue
        if not names_tool(node.elts[0], node.elts[1:]):
            continue
        flags = {e.value for e in node.elts if isinstance(e, ast.Constant)}
        if flags & {"--transport", "--help", "-h"}:
            continue
        if WAIVER in lines[node.lineno - 1] or WAIVER in lines[node.lineno - 2]:
            continue
        findings.append("%s:%d: starts %s without \"--transport\" in its argument list"
                        % (path, node.lineno, ast.unparse(node.elts[0])))


# ------------------------------------------------------------------ files

def language(path):
    name = path[:-3] if path.endswith(".in") else path
    if name.endswith(CPP_EXT):
        return "cpp"
    if name.endswith(".sh"):
        return "shell"
    if name.endswith(".py"):
        return "python"
    return None


def repo_files(root):
    for top in SCAN_DIRS:
        for folder, dirs, files in os.walk(os.path.join(root, top)):
            rel = os.path.relpath(folder, root)
            if rel == FIXTURES or rel.startswith(FIXTURES + os.sep):
                dirs[:] = []
                continue
            for f in files:
                path = os.path.join(folder, f)
                # The tools' own C++ (apps/) holds the defaults on purpose.
                if top == "apps" and language(f) == "cpp":
                    continue
                if language(f) or (rel == ".ci" and f == "run"):
                    yield path


def scan(paths, root):
    macros = tool_macros(root)
    findings = []
    for path in paths:
        with open(path, encoding="utf-8", errors="replace") as f:
            text = f.read()
        shown = os.path.relpath(path, root)
        kind = language(path) or "shell"
        if kind == "cpp":
            check_cpp(shown, text, macros, findings)
        elif kind == "shell":
            check_shell(shown, text, findings)
        else:
            check_python(shown, text, findings)
    return findings


def continuation_end(lines, line_no):
    """The last physical line of the logical (backslash-continued) line
    starting at line_no."""
    while line_no <= len(lines) and lines[line_no - 1].endswith("\\"):
        line_no += 1
    return line_no


def self_test(root):
    folder = os.path.join(root, FIXTURES)
    paths = sorted(os.path.join(folder, f) for f in os.listdir(folder) if language(f))
    ok = bool(paths)
    for path in paths:
        with open(path, encoding="utf-8") as f:
            lines = f.read().split("\n")
        expected = {n for n, line in enumerate(lines, 1)
                    if re.search(r"(//|#)\s*expect-finding\s*$", line)}
        reported = {}
        for finding in scan([path], root):
            line_no = int(finding.split(":")[1])
            reported[continuation_end(lines, line_no)] = finding
        missed = sorted(expected - set(reported))
        false = sorted(set(reported) - expected)
        name = os.path.basename(path)
        for line_no in sorted(reported):
            print("  " + reported[line_no])
        print("%s: %d planted, %d reported, %d missed %s, %d false %s"
              % (name, len(expected), len(reported), len(missed), missed, len(false), false))
        ok = ok and not missed and not false and expected
    print("self-test " + ("passed: the guard goes red on every planted case and only there"
                          if ok else "FAILED"))
    return 0 if ok else 1


def main(argv):
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    files = []
    run_self_test = False
    i = 0
    while i < len(argv):
        a = argv[i]
        if a in ("-h", "--help"):
            usage(sys.stdout)
            return 0
        if a == "--self-test":
            run_self_test = True
            i += 1
            continue
        if a == "--root":
            if i + 1 >= len(argv):
                sys.stderr.write("check_transport_chosen.py: --root needs a directory\n")
                usage(sys.stderr)
                return 2
            root = os.path.abspath(argv[i + 1])
            i += 2
            continue
        if a.startswith("-"):
            sys.stderr.write("check_transport_chosen.py: unknown option '%s'\n" % a)
            usage(sys.stderr)
            return 2
        files.append(os.path.abspath(a))
        i += 1
    if not os.path.isdir(root):
        sys.stderr.write("check_transport_chosen.py: no directory '%s'\n" % root)
        return 2
    if run_self_test:
        return self_test(root)
    # A named file that is not a readable file is a usage error, not a traceback.
    for f in files:
        if not os.path.isfile(f):
            sys.stderr.write("check_transport_chosen.py: '%s' is not a file (use --root DIR "
                             "to scan a checkout)\n" % f)
            return 2
    paths = files or sorted(repo_files(root))
    findings = scan(paths, root)
    for line in findings:
        print(line)
    if findings:
        print("%d place(s) leave the DDS transport to its default (the network): choose "
              "loopback (tests/support/transport.hpp, benchmarks' mtc/bench/transport.hpp, "
              "--transport loopback) or the network on purpose" % len(findings))
        return 1
    print("transport chosen explicitly in %d files" % len(paths))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
