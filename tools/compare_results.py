#!/usr/bin/env python3
"""Compares two directories written by tools/compare_results.sh.

Every RESULT.json (and --json output) must be equal but for wall times,
thread counts and the keys named on the command line as allowed to differ
(dotted paths, '*' for any list index or key), e.g.

    python3 tools/compare_results.py OLD NEW --allow simulations \
        --allow experiments.*.steps

Numbers are compared exactly (bit for bit, as JSON text parses them).
Prints one line per difference and exits 1 if there is any.
"""
import argparse
import json
import sys
from pathlib import Path

ALWAYS = ["timings", "threads"]


def matches(path, pattern):
    p = pattern.split(".")
    if len(p) > len(path):
        return False
    return all(a == "*" or a == b for a, b in zip(p, path[: len(p)]))


def diff(a, b, path, allowed, out):
    if any(matches(path, pat) for pat in allowed):
        return
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if k not in a:
                if not any(matches(path + [k], pat) for pat in allowed):
                    out.append(f"{'.'.join(path + [k])}: added {json.dumps(b[k])[:120]}")
            elif k not in b:
                if not any(matches(path + [k], pat) for pat in allowed):
                    out.append(f"{'.'.join(path + [k])}: removed")
            else:
                diff(a[k], b[k], path + [k], allowed, out)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            out.append(f"{'.'.join(path)}: length {len(a)} -> {len(b)}")
            return
        for i, (x, y) in enumerate(zip(a, b)):
            diff(x, y, path + [str(i)], allowed, out)
    elif a != b or type(a) is not type(b):
        out.append(f"{'.'.join(path)}: {json.dumps(a)[:120]} -> {json.dumps(b)[:120]}")


def load(p):
    text = p.read_text()
    try:
        return json.loads(text)
    except json.JSONDecodeError:
        return {"text": text}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("old", type=Path)
    ap.add_argument("new", type=Path)
    ap.add_argument("--allow", action="append", default=[])
    a = ap.parse_args()
    allowed = ALWAYS + a.allow
    failed = 0
    names = sorted(p.name for p in a.old.iterdir() if p.suffix in (".json", ".status"))
    names += sorted(p.name for p in a.old.iterdir() if p.name.endswith(".stdout") and p.stat().st_size)
    for name in names:
        new = a.new / name
        if not new.exists():
            print(f"{name}: missing in {a.new}")
            failed += 1
            continue
        out = []
        diff(load(a.old / name), load(new), [], allowed, out)
        for line in out:
            print(f"{name}: {line}")
        failed += bool(out)
        if not out:
            print(f"{name}: equal")
    print(f"{len(names) - failed} equal, {failed} differ")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
