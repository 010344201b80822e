#!/usr/bin/env python3
"""List Rust functions and files longer than a limit.

Usage: python3 tools/long_items.py [--max-fn N] [--max-file M] PATH [PATH ...]

PATH is a .rs file or a directory (searched for .rs files; files under a
`tests/` directory are skipped). A function's length runs from its `fn`
line to its closing brace (brace-matched, with comments and literals left
out); a file's length is its line count without its `#[cfg(test)]` items
(`mod tests { ... }` blocks and the like), whose functions are not listed
either. Defaults: --max-fn 80, --max-file 600.

A function preceded (above its doc comment and attributes) by a comment
line containing `long-fn: numerical kernel` is listed separately as
allowed. Exits 1 if any other function or any file is over its limit.
"""

import argparse
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from rust_source import cfg_test_spans, line_of, match_brace, strip  # noqa: E402

MARKER = "long-fn: numerical kernel"
FN = re.compile(r"(?<![\w])fn\s+(\w+)")


def rust_files(paths):
    """The .rs files of `paths`, without those under a `tests/` directory."""
    for path in paths:
        if os.path.isfile(path):
            yield path
            continue
        for root, dirs, names in os.walk(path):
            dirs[:] = sorted(d for d in dirs if d != "tests")
            for name in sorted(names):
                if name.endswith(".rs"):
                    yield os.path.join(root, name)


def allowed(lines, fn_line):
    """Whether a comment line with MARKER precedes the function at line
    `fn_line` (1-based), above its doc comments and attributes."""
    k = fn_line - 2
    while k >= 0:
        s = lines[k].strip()
        if MARKER in s and s.startswith("//"):
            return True
        if s.startswith("//") or s.startswith("#[") or s.startswith("#!["):
            k -= 1
            continue
        if s.endswith(")]") or s.endswith("]"):  # the end of a multi-line attribute
            k -= 1
            continue
        return False
    return False


def functions(text):
    """(name, first line, length in lines) of each function with a body,
    outside the `#[cfg(test)]` items."""
    code = strip(text)
    tests = cfg_test_spans(code)
    found = []
    for m in FN.finditer(code):
        if any(a <= m.start() < b for a, b in tests):
            continue
        # The body: the first `{` after the signature, unless a `;` comes first
        # (a declaration in a trait or an extern block).
        depth, j = 0, m.end()
        while j < len(code):
            c = code[j]
            if c in "([<":
                depth += 1
            elif c in ")]>" and not (c == ">" and code[j - 1] == "-"):
                depth -= 1
            elif c == ";" and depth <= 0:
                j = -1
                break
            elif c == "{" and depth <= 0:
                break
            j += 1
        if j < 0 or j >= len(code):
            continue
        end = match_brace(code, j)
        first, last = line_of(code, m.start()), line_of(code, end)
        found.append((m.group(1), first, last - first + 1))
    return found, code, tests


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--max-fn", type=int, default=80)
    parser.add_argument("--max-file", type=int, default=600)
    parser.add_argument("paths", nargs="+")
    args = parser.parse_args(argv)
    long_fns, allowed_fns, long_files = [], [], []
    for path in rust_files(args.paths):
        with open(path, encoding="utf-8") as f:
            text = f.read()
        lines = text.split("\n")
        fns, code, tests = functions(text)
        for name, first, length in fns:
            if length > args.max_fn:
                item = (path, first, name, length)
                (allowed_fns if allowed(lines, first) else long_fns).append(item)
        test_lines = sum(code.count("\n", a, b) + 1 for a, b in tests)
        n_lines = len(text.rstrip("\n").split("\n")) - test_lines
        if n_lines > args.max_file:
            long_files.append((path, n_lines))
    if long_fns:
        print(f"functions over {args.max_fn} lines:")
        for path, first, name, length in long_fns:
            print(f"  {path}:{first}: fn {name}: {length} lines")
    if allowed_fns:
        print(f"functions over {args.max_fn} lines, allowed ({MARKER}):")
        for path, first, name, length in allowed_fns:
            print(f"  {path}:{first}: fn {name}: {length} lines")
    if long_files:
        print(f"files over {args.max_file} lines (without their tests):")
        for path, n_lines in long_files:
            print(f"  {path}: {n_lines} lines")
    if not (long_fns or long_files):
        print(f"no function over {args.max_fn} lines, no file over {args.max_file} lines"
              + (" (but for the allowed ones)" if allowed_fns else ""))
        return 0
    return 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
