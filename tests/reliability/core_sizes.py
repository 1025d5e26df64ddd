#!/usr/bin/env python3
"""Size limits of core/: no function over 120 lines, no file in core/src over 500 lines.

    /usr/bin/python3 tests/reliability/core_sizes.py [REPO]     (exit 1 and the offenders if not)

Functions are found by their braces: a block opened outside any function that is not a
namespace, class, struct, union, enum or initializer list is a function body (lambdas and
blocks inside it count towards it). Comments and string literals are blanked first.
"""
import pathlib
import re
import sys

MAX_FUNCTION_LINES = 120
MAX_FILE_LINES = 500


def strip(text):
    text = re.sub(r"/\*.*?\*/", lambda m: re.sub(r"[^\n]", " ", m.group(0)), text, flags=re.S)
    text = re.sub(r"//[^\n]*", "", text)
    text = re.sub(r'"(\\.|[^"\\\n])*"', '""', text)
    return re.sub(r"'(\\.|[^'\\\n])'", "''", text)


def functions(path):
    """(first line, line count, header) of every function body in the file."""
    text = strip(path.read_text())
    stack = []  # kinds of the open blocks
    out = []
    start = 0
    pending = ""  # text since the last ; { or }
    line = 1
    for ch in text:
        if ch == "\n":
            line += 1
        if ch == "{":
            head = pending.strip()
            in_function = "function" in stack
            if in_function:
                kind = "inner"
            elif re.search(r"\b(namespace|class|struct|union|enum)\b[^()]*$", head) or head.endswith("=") or head == "":
                kind = "scope"
            elif "(" in head:
                kind = "function"
                start = line
                header = " ".join(head.split())[-100:]
            else:
                kind = "scope"
            stack.append(kind)
            pending = ""
        elif ch == "}":
            kind = stack.pop() if stack else "scope"
            if kind == "function":
                out.append((start, line - start + 1, header))
            pending = ""
        elif ch == ";" and "function" not in stack:
            pending = ""
        else:
            pending += ch
    return out


def main(repo):
    core = pathlib.Path(repo) / "core"
    bad = []
    for path in sorted(core.rglob("*.[ch]pp")):
        rel = path.relative_to(repo)
        if "src" in path.parts:
            n = len(path.read_text().splitlines())
            if n > MAX_FILE_LINES:
                bad.append(f"{rel}: {n} lines (at most {MAX_FILE_LINES})")
        for first, count, header in functions(path):
            if count > MAX_FUNCTION_LINES:
                bad.append(f"{rel}:{first}: function of {count} lines (at most {MAX_FUNCTION_LINES}): {header}")
    for b in bad:
        print(b)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parents[2]))
