#!/usr/bin/env python3
"""List the library's string literals that spell an option as a front end
does (`--plan`, `--over-box`).

Usage: python3 tools/front_end_words.py PATH [PATH ...]

The library speaks to the command line and to the Python module alike, so
its messages name an option as the reference does, in backticks (`plan`,
`over_box`), and each front end spells it its own way
(`OptionError::spelt`). PATH is a .rs file or a directory (searched for .rs
files); comments and `#[cfg(test)]` items are left out. Exits 1 if any
literal holds `--` followed by a letter.
"""

import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from rust_source import blank_spans, cfg_test_spans, line_of, strip  # noqa: E402

FLAG = re.compile(r"--[a-z]")


def literals(text):
    """(offset, literal text) of each string literal of `text` outside its
    `#[cfg(test)]` items: the runs that `strip` blanks and that open with a
    quote rather than a comment's slash."""
    code = strip(text)
    shown = blank_spans(text, cfg_test_spans(code))
    i, n = 0, len(text)
    while i < n:
        if code[i] == text[i] or text[i].isspace():
            i += 1
            continue
        j = i
        while j < n and (code[j] != text[j] or text[j].isspace()) and code[j] == " ":
            j += 1
        if not text.startswith(("//", "/*"), i) and shown[i] != " ":
            yield i, text[i:j]
        i = max(j, i + 1)


def rust_files(paths):
    for path in paths:
        if os.path.isfile(path):
            yield path
            continue
        for root, _, files in sorted(os.walk(path)):
            for f in sorted(files):
                if f.endswith(".rs"):
                    yield os.path.join(root, f)


def main(paths):
    found = 0
    for path in rust_files(paths):
        with open(path, encoding="utf-8") as f:
            text = f.read()
        for at, lit in literals(text):
            if FLAG.search(lit):
                found += 1
                print(f"{path}:{line_of(text, at)}: {lit.strip()[:100]}")
    if found:
        print(f"{found} literal(s) spell an option as a front end does; "
              "name it in backticks (`plan`) for the front end to spell")
    return 1 if found else 0


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    sys.exit(main(sys.argv[1:]))
