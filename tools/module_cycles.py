#!/usr/bin/env python3
"""Find import circles among the sibling modules of Rust module directories.

Usage: python3 tools/module_cycles.py DIR [DIR ...]

DIR is a Rust module directory (e.g. crates/rfeid/src/simulation). Its
nodes are its files `X.rs` and its subdirectories `X/` (all files below
count as X), plus `mod.rs` for the items that mod.rs defines itself.
Modules declared under `#[cfg(test)]` (in mod.rs, or in a subdirectory's
mod.rs) are left out.

A file depends on node B if its code (comments, literals and every
`#[cfg(test)]` item left out) names a path into B: `super::B::..`,
`crate::<dir path>::B::..`, `super::super::B` from a subdirectory, a bare
`B::..` in mod.rs, inside `use` lines (grouped imports included:
`use super::{a::X, b::{Y, Z}}`) or inline (`super::b::f(..)`). A path to an
item of the directory itself (`super::Item`, `crate::<dir>::Item`) depends
on the file that defines the item: mod.rs's `pub use b::Item` is followed
(through further `pub use` in b), and mod.rs is the node only for items it
defines. A `pub use` inside a sibling file counts for both that file and the
file it re-exports from. mod.rs's own `mod` and `pub use` lines are
declarations, not dependencies; its other code does count.

Prints each circle (strongly connected component of more than one node)
with one example reference per edge (file:line), and exits 1 if there is
any; otherwise prints "no import circles in DIR" and exits 0.

Not seen: method calls (`sim.run(..)` names no path: a method in an
`impl` block of another file than its type's is a dependency this does not
see), glob imports other than `super::*` (counted as mod.rs), paths
through macros, and re-exports made outside DIR (e.g. in lib.rs).
"""

import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from rust_source import blank_cfg_test, blank_spans, cfg_test_spans, line_of, strip  # noqa: E402

MOD = "mod.rs"
USE = re.compile(r"(?<![\w:])((?:pub(?:\s*\([^)]*\))?\s+)?)use\s+([^;]*);")
INLINE = re.compile(r"(?<![\w:$])(crate|super|self)((?:\s*::\s*\w+)+)")
MOD_DECL = re.compile(r"(?<![\w:])((?:pub(?:\s*\([^)]*\))?\s+)?)mod\s+(\w+)\s*;")


def parse_use_tree(s):
    """The full paths (lists of segments) of a use tree, with `self` in a
    group standing for the group's prefix; `as` renames are dropped."""
    s = re.sub(r"\s+", " ", s).strip()
    pos = 0

    def tree(prefix):
        nonlocal pos
        segs = list(prefix)
        paths = []
        while True:
            skip_ws()
            if pos < len(s) and s[pos] == "{":
                pos += 1
                while True:
                    skip_ws()
                    if pos < len(s) and s[pos] == "}":
                        pos += 1
                        break
                    paths += tree(segs)
                    skip_ws()
                    if pos < len(s) and s[pos] == ",":
                        pos += 1
                return paths
            m = re.compile(r"(\w+|\*)").match(s, pos)
            if not m:
                return paths + ([segs] if segs else [])
            word = m.group(1)
            pos = m.end()
            if not (word == "self" and prefix and len(segs) == len(prefix)):
                segs = segs + [word]  # (`self` in a group: the prefix itself)
            skip_ws()
            if s.startswith("::", pos):
                pos += 2
                continue
            a = re.compile(r"as (\w+)").match(s, pos)
            if a:
                pos = a.end()
            return [segs]

    def skip_ws():
        nonlocal pos
        while pos < len(s) and s[pos] == " ":
            pos += 1

    return tree([])


def module_name(node):
    """The module name of a node: `run` for `run.rs`, `x` for `x/`."""
    return node[:-3] if node.endswith(".rs") else node.rstrip("/")


def crate_module_path(directory):
    """The module path of `directory` below its crate's `src` (a list)."""
    parts = os.path.normpath(os.path.abspath(directory)).split(os.sep)
    if "src" not in parts:
        sys.exit(f"{directory}: not below a crate's src directory")
    k = len(parts) - 1 - parts[::-1].index("src")
    return parts[k + 1:]


class Directory:
    """The nodes and files of one module directory."""

    def __init__(self, directory):
        self.dir = directory
        self.base = crate_module_path(directory)
        self.mod_file = os.path.join(directory, "mod.rs")
        if not os.path.exists(self.mod_file):
            for root in ("lib.rs", "main.rs"):
                if os.path.exists(os.path.join(directory, root)):
                    self.mod_file = os.path.join(directory, root)
        self.code = {}
        mod_code = self.read(self.mod_file) if os.path.exists(self.mod_file) else ""
        self.test_only = self.test_modules(self.mod_file)
        self.nodes = {}  # name -> list of (file, module path)
        for entry in sorted(os.listdir(directory)):
            path = os.path.join(directory, entry)
            if entry.endswith(".rs") and path != self.mod_file:
                name = entry[:-3]
                if name not in self.test_only:
                    self.nodes[entry] = [(path, self.base + [name])]
            elif os.path.isdir(path) and entry not in self.test_only:
                files = []
                for root, dirs, names in os.walk(path):
                    skip = self.test_modules(os.path.join(root, "mod.rs"))
                    dirs[:] = sorted(x for x in dirs if x not in skip)
                    for f in sorted(names):
                        if f.endswith(".rs") and f[:-3] not in skip:
                            fp = os.path.join(root, f)
                            rel = os.path.relpath(fp, directory)[:-3].split(os.sep)
                            if rel[-1] == "mod":
                                rel = rel[:-1]
                            files.append((fp, self.base + rel))
                if files:
                    self.nodes[entry + "/"] = files
        if os.path.exists(self.mod_file):
            self.nodes[MOD] = [(self.mod_file, self.base)]
        self.by_name = {module_name(node): node for node in self.nodes if node != MOD}
        self.exports = {}  # (node, item) -> set of nodes it resolves to
        self.mod_items = self.defined_items(mod_code)

    def test_modules(self, path):
        """The modules that the file at `path` declares under `#[cfg(test)]`."""
        if not os.path.exists(path):
            return set()
        code = strip(self.raw(path))
        return {m.group(2) for a, b in cfg_test_spans(code) for m in MOD_DECL.finditer(code[a:b])}

    @staticmethod
    def raw(path):
        with open(path, encoding="utf-8") as f:
            return f.read()

    def read(self, path):
        if path not in self.code:
            self.code[path] = blank_cfg_test(strip(self.raw(path)))
        return self.code[path]

    @staticmethod
    def defined_items(code):
        return set(re.findall(
            r"\b(?:fn|struct|enum|trait|type|const|static|union|macro_rules!)\s+(\w+)", code))

    def node_file(self, node):
        for path, module in self.nodes[node]:
            if module == self.base + [module_name(node)]:
                return path, module
        return self.nodes[node][0]

    def absolute(self, segs, module, children):
        """`segs` as an absolute path (from below `crate`), or None."""
        segs = list(segs)
        if not segs:
            return None
        if segs[0] == "crate":
            return segs[1:]
        if segs[0] in ("super", "self"):
            cur = list(module)
            while segs and segs[0] in ("super", "self"):
                if segs.pop(0) == "super":
                    if not cur:
                        return None
                    cur.pop()
            return cur + segs
        if segs[0] in children:
            return list(module) + segs
        return None

    def resolve(self, path, seen=()):
        """The nodes an absolute path depends on (empty if outside DIR)."""
        n = len(self.base)
        if path[:n] != self.base or len(path) == n:
            return set()
        head = path[n]
        if head == "*":
            return {MOD}
        node = self.by_name.get(head)
        if node is not None:
            result = {node}
            if len(path) > n + 1 and node.endswith(".rs"):
                result |= self.reexport(node, path[n + 1], seen)
            return result
        # An item of the directory itself: defined in mod.rs or re-exported.
        return self.reexport(MOD, head, seen) or {MOD}

    def reexport(self, node, item, seen):
        """Where `pub use` in node's file sends `item` (empty if not re-exported)."""
        key = (node, item)
        if key in seen:
            return set()
        if key not in self.exports:
            result = set()
            path, module = self.node_file(node) if node != MOD else (self.mod_file, self.base)
            code = self.read(path)
            children = self.children(code)
            for m in USE.finditer(code):
                if not m.group(1).strip():
                    continue
                for segs in parse_use_tree(m.group(2)):
                    if segs and segs[-1] == item:
                        target = self.absolute(segs, module, children)
                        if target:
                            result |= self.resolve(target, seen + (key,))
            result.discard(node)
            self.exports[key] = result
        return self.exports[key]

    @staticmethod
    def children(code):
        return {m.group(2) for m in MOD_DECL.finditer(code)}

    def references(self, path, module, is_mod):
        """(line, text, absolute path) of every path reference in a file."""
        code = self.read(path)
        children = self.children(code)
        refs = []
        spans = []
        for m in USE.finditer(code):
            spans.append((m.start(), m.end()))
            if is_mod and m.group(1).strip():
                continue  # a re-export: a declaration of mod.rs, not a dependency
            for segs in parse_use_tree(m.group(2)):
                target = self.absolute(segs, module, children)
                if target:
                    refs.append((line_of(code, m.start()), " ".join(m.group(0).split()), target))
        rest = blank_spans(code, spans)
        for m in INLINE.finditer(rest):
            segs = [m.group(1)] + re.findall(r"\w+", m.group(2))
            target = self.absolute(segs, module, children)
            if target:
                refs.append((line_of(rest, m.start()), " ".join(m.group(0).split()), target))
        if children:
            decl = blank_spans(rest, [(m.start(), m.end()) for m in MOD_DECL.finditer(rest)])
            names = "|".join(sorted(children))
            for m in re.finditer(r"(?<![\w:])(%s)((?:\s*::\s*\w+)+)" % names, decl):
                segs = [m.group(1)] + re.findall(r"\w+", m.group(2))
                refs.append((line_of(decl, m.start()), " ".join(m.group(0).split()),
                             list(module) + segs))
        return refs

    def graph(self):
        """node -> {node: example reference}."""
        edges = {node: {} for node in self.nodes}
        for node, files in self.nodes.items():
            for path, module in files:
                for line, text, target in self.references(path, module, path == self.mod_file):
                    for dep in self.resolve(target):
                        if dep != node and dep not in edges[node]:
                            rel = os.path.relpath(path)
                            edges[node][dep] = f"{rel}:{line}: {text}"
        return edges


def strongly_connected(edges):
    """Tarjan's components, each a sorted list."""
    index, low, stack, on, comps = {}, {}, [], set(), []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(edges[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            comps.append(sorted(comp))

    sys.setrecursionlimit(10000)
    for v in sorted(edges):
        if v not in index:
            visit(v)
    return comps


def check(directory):
    """Prints the circles of one directory; whether there are any."""
    d = Directory(directory)
    edges = d.graph()
    circles = [c for c in strongly_connected(edges) if len(c) > 1]
    if not circles:
        print(f"no import circles in {directory}")
        return False
    print(f"import circles in {directory}:")
    for k, comp in enumerate(circles, 1):
        print(f"  circle {k}: {', '.join(comp)}")
        for a in comp:
            for b in sorted(edges[a]):
                if b in comp:
                    print(f"    {a} -> {b}   {edges[a][b]}")
    return True


def main(argv):
    if not argv or argv[0] in ("-h", "--help"):
        print(__doc__)
        return 0 if argv else 2
    found = False
    for directory in argv:
        if not os.path.isdir(directory):
            print(f"{directory}: not a directory", file=sys.stderr)
            return 2
        found |= check(directory)
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
