#!/usr/bin/env python3
"""The house limits on the code's shape: no source file over 800 lines, no function over 150.

Usage: scripts/code_shape.py [ROOT]   (exit 1 and one line per file or function over a limit)

Sources are the C++ files (.h, .cpp, .inc) under engine/, viewer/, cli/, report/, tests/ and
bench/. A function is a body whose opening brace follows a parenthesised header at file,
namespace or class scope (a lambda or a block inside a function counts as that function's);
its length runs from its header's first line to its closing brace. Comments, strings and
character literals are blanked first, so braces inside them do not count.
"""
import os
import re
import sys

MAX_FILE_LINES = 800
MAX_FUNCTION_LINES = 150
FOLDERS = ("engine", "viewer", "cli", "report", "tests", "bench")
CONTROL = re.compile(r"^\s*(if|for|while|switch|catch|do|else|try)\b")
TYPE = re.compile(r"\b(class|struct|union|enum|namespace)\b[^()]*$")


def blank(text):
    """Comments, strings and character literals replaced by spaces (newlines kept)."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif text.startswith('R"', i):
            m = re.match(r'R"([^(]*)\(', text[i:])
            end = text.find(")" + m.group(1) + '"', i) if m else -1
            j = n if end < 0 else end + len(m.group(1)) + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            j = min(n, j + 1)
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        else:
            out.append(c)
            i += 1
    return "".join(out)


def functions(text):
    """(name, first line, last line) of every function definition in `text` (blanked)."""
    found = []
    stack = []  # each open brace: (kind, header start line, name)
    header_start = 0  # offset where the current statement's header began
    line_of = lambda offset: text.count("\n", 0, offset) + 1
    for i, c in enumerate(text):
        if c == "{":
            header = text[header_start:i]
            enclosing = stack[-1][0] if stack else "scope"
            kind = "block"
            if enclosing in ("scope", "type"):
                stripped = " ".join(header.split())
                if TYPE.search(stripped) or stripped.startswith("extern"):
                    kind = "type" if not stripped.startswith("namespace") else "scope"
                    if re.search(r"\bnamespace\b", stripped):
                        kind = "scope"
                elif ")" in stripped and not CONTROL.match(stripped) and "=" not in stripped.split("(")[0]:
                    kind = "function"
            if kind == "function":
                start = header_start + len(header) - len(header.lstrip())
                name = re.findall(r"([~\w:<>]+)\s*\(", header)
                stack.append((kind, line_of(start), name[0] if name else "?"))
            else:
                stack.append((kind, 0, ""))
            header_start = i + 1
        elif c == "}":
            if stack:
                kind, first, name = stack.pop()
                if kind == "function":
                    found.append((name, first, line_of(i)))
            header_start = i + 1
        elif c == ";":
            header_start = i + 1
        elif c == ":" and stack and stack[-1][0] == "type":
            # access specifiers (public:) end a header inside a class
            before = text[header_start:i].strip()
            if before in ("public", "private", "protected"):
                header_start = i + 1
    return found


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..")
    problems = []
    for folder in FOLDERS:
        for base, _, names in os.walk(os.path.join(root, folder)):
            for name in sorted(names):
                if not name.endswith((".h", ".cpp", ".inc")):
                    continue
                path = os.path.join(base, name)
                rel = os.path.relpath(path, root)
                with open(path, encoding="utf-8", errors="replace") as f:
                    text = f.read()
                lines = text.count("\n")
                if lines > MAX_FILE_LINES:
                    problems.append("%s: %d lines (at most %d)" % (rel, lines, MAX_FILE_LINES))
                for fn, first, last in functions(blank(text)):
                    if last - first + 1 > MAX_FUNCTION_LINES:
                        problems.append("%s:%d: %s is %d lines (at most %d)" %
                                        (rel, first, fn, last - first + 1, MAX_FUNCTION_LINES))
    for p in problems:
        print(p)
    if problems:
        return 1
    print("code shape: no file over %d lines, no function over %d" %
          (MAX_FILE_LINES, MAX_FUNCTION_LINES))
    return 0


if __name__ == "__main__":
    sys.exit(main())
