#!/usr/bin/env python3
"""Compares two directories written by tools/compare_results.sh.

Every RESULT.json (and --json output) must be equal but for wall times,
thread counts and the keys named on the command line as allowed to differ
(dotted paths, '*' for any list index or key), e.g.

    python3 tools/compare_results.py OLD NEW --allow simulations \
        --allow experiments.*.steps

Numbers are compared exactly (bit for bit, as JSON text parses them).
Prints one line per difference and exits 1 if there is any.

--words compares results of before and after warnings and reasons were
tagged: a tagged warning ({"kind", ..., "message"}) counts as its message
(the words older files hold), a verdict reason's `message` (its words) is
dropped, and the `detail` of `no_standard_errors`/`simulation_failed` is
compared as the `message` it was called before; every other field must be
equal, so the tags add values without changing a word.
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


def words(doc):
    """`doc` with tagged warnings and reasons as the words they replace
    (see --words); documents of other shapes are returned as they are."""
    if not isinstance(doc, dict):
        return doc

    def reason(r):
        if not isinstance(r, dict):
            return r
        r = {k: v for k, v in r.items() if k != "message"}
        if "detail" in r:
            r["message"] = r.pop("detail")
        return r

    def warning(w):
        return w.get("message") if isinstance(w, dict) else w

    out = dict(doc)
    if isinstance(out.get("warnings"), list):
        out["warnings"] = [warning(w) for w in out["warnings"]]
    verdict = out.get("verdict")
    if isinstance(verdict, dict) and isinstance(verdict.get("reasons"), list):
        out["verdict"] = dict(verdict, reasons=[reason(r) for r in verdict["reasons"]])
    for p in out.get("profiles") or []:
        if isinstance(p, dict) and isinstance(p.get("warnings"), list):
            p["warnings"] = [warning(w) for w in p["warnings"]]
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("old", type=Path)
    ap.add_argument("new", type=Path)
    ap.add_argument("--allow", action="append", default=[])
    ap.add_argument("--words", action="store_true", help="compare tagged warnings and reasons as their words")
    a = ap.parse_args()
    norm = words if a.words else (lambda d: d)
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
        diff(norm(load(a.old / name)), norm(load(new)), [], allowed, out)
        for line in out:
            print(f"{name}: {line}")
        failed += bool(out)
        if not out:
            print(f"{name}: equal")
    print(f"{len(names) - failed} equal, {failed} differ")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
