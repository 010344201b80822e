"""Shared helpers for the Rust source checkers in tools/ (stdlib only).

`strip(text)` blanks comments, string and character literals, keeping the
line structure (and every other character's position), so that braces and
paths can be found with plain scanning. `blank_cfg_test(code)` then blanks
every item marked `#[cfg(test)]` (a `mod tests { ... }` block, a `mod x;`,
a `use`, a function).
"""

import re


def strip(text):
    """The text with comments and literals replaced by spaces (newlines kept)."""
    out = list(text)
    i, n = 0, len(text)

    def blank(a, b):
        for k in range(a, b):
            if out[k] != "\n":
                out[k] = " "

    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            blank(i, j)
            i = j
        elif text.startswith("/*", i):
            depth, j = 1, i + 2
            while j < n and depth:
                if text.startswith("/*", j):
                    depth, j = depth + 1, j + 2
                elif text.startswith("*/", j):
                    depth, j = depth - 1, j + 2
                else:
                    j += 1
            blank(i, j)
            i = j
        elif c in "rb" and re.match(r'(?:br|r)#*"', text[i:i + 260]) and (
            i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")
        ):
            m = re.match(r'(?:br|r)(#*)"', text[i:])
            end = '"' + m.group(1)
            j = text.find(end, i + m.end())
            j = n if j < 0 else j + len(end)
            blank(i + 1, j)
            i = j
        elif c == '"':
            j = i + 1
            while j < n and text[j] != '"':
                j += 2 if text[j] == "\\" else 1
            blank(i + 1, j)
            i = j + 1
        elif c == "'":
            # A character literal ('x', '\n', '\u{..}'), not a lifetime ('a).
            m = re.match(r"'(?:\\u\{[0-9a-fA-F]+\}|\\.|[^\\'\n])'", text[i:])
            if m:
                blank(i + 1, i + m.end() - 1)
                i += m.end()
            else:
                i += 1
        else:
            i += 1
    return "".join(out)


def match_brace(code, i):
    """The index of the brace closing the one at `code[i]` (len(code) if none)."""
    depth = 0
    for j in range(i, len(code)):
        if code[j] == "{":
            depth += 1
        elif code[j] == "}":
            depth -= 1
            if depth == 0:
                return j
    return len(code)


def item_end(code, i):
    """The end of the item starting at i: its first `;` at depth zero, or the
    brace closing its first block, whichever comes first."""
    depth = 0
    for j in range(i, len(code)):
        c = code[j]
        if c in "([":
            depth += 1
        elif c in ")]":
            depth -= 1
        elif c == ";" and depth == 0:
            return j + 1
        elif c == "{" and depth == 0:
            return match_brace(code, j) + 1
    return len(code)


CFG_TEST = re.compile(r"#\[cfg\(test\)\]")
ATTRIBUTE = re.compile(r"\s*#\[[^\]]*\]")


def cfg_test_spans(code):
    """The (start, end) spans of the items marked `#[cfg(test)]`."""
    spans = []
    for m in CFG_TEST.finditer(code):
        j = m.end()
        while True:
            a = ATTRIBUTE.match(code, j)
            if not a:
                break
            j = a.end()
        spans.append((m.start(), item_end(code, j)))
    return spans


def blank_spans(code, spans):
    """`code` with the spans blanked (newlines kept)."""
    out = list(code)
    for a, b in spans:
        for k in range(a, min(b, len(out))):
            if out[k] != "\n":
                out[k] = " "
    return "".join(out)


def blank_cfg_test(code):
    """`code` without its `#[cfg(test)]` items."""
    return blank_spans(code, cfg_test_spans(code))


def line_of(code, i):
    """The 1-based line number of offset i."""
    return code.count("\n", 0, i) + 1
