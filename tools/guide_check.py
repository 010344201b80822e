#!/usr/bin/env python3
"""Runs every command block of the user guide, so that the guide cannot rot.

    python3 tools/guide_check.py [docs/guide/CHAPTER.md ...]

Each chapter runs in a fresh scratch directory holding copies of the
repository's `examples/` and `data/`, so a chapter's commands are written as
a user types them at the repository's root and its outputs land nowhere
else. Fenced blocks, in order:

- ```sh            run with bash (-e -o pipefail); must exit 0;
- ```sh exit=N     must exit with status N (the exit-status examples);
- ```LANG file=P   not run: its text is written to P (a model file, a data
                   file), for the blocks after it;
- ```LANG append=P not run: its text is appended to P (a model file built up
                   step by step);
- ```python        run in one Python interpreter per chapter, the blocks
                   sharing their variables as in a notebook;
- anything else (```text, ```toml without file=, ```console) is shown
  output or an excerpt, and is not run.

First, every relative link of README.md, CHANGELOG.md and docs/ must name
an existing file (and heading). `rfeid` is the binary the tests built (target/release/rfeid, or $RFEID_BIN);
`python` is the tests' virtual environment (target/venv, or $GUIDE_PYTHON).
"""
import concurrent.futures
import os
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
FENCE = re.compile(r"^```(\S*)(.*)$")

# Runs the files named on stdin in one namespace and answers each with a line.
DRIVER = r"""
import sys, traceback
ns = {"__name__": "__main__"}
for line in sys.stdin:
    path = line.strip()
    try:
        exec(compile(open(path).read(), path, "exec"), ns)
        ok = True
    except BaseException:
        traceback.print_exc()
        ok = False
    sys.stdout.flush(); sys.stderr.flush()
    print("@@guide-block-done@@" + ("ok" if ok else "failed"), flush=True)
"""


def blocks(path):
    """The fenced blocks of `path`: (line, language, options, text)."""
    out, lines = [], path.read_text().splitlines()
    i = 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        lang, opts = m.group(1), dict(
            kv.split("=", 1) for kv in m.group(2).split() if "=" in kv
        )
        start, body = i + 1, []
        i += 1
        while i < len(lines) and not lines[i].startswith("```"):
            body.append(lines[i])
            i += 1
        out.append((start, lang, opts, "\n".join(body) + "\n"))
        i += 1
    return out


def tool_paths():
    binary = pathlib.Path(os.environ.get("RFEID_BIN", ROOT / "target/release/rfeid"))
    if not binary.exists():
        sys.exit(f"guide_check: no rfeid binary at {binary} (build with cargo build --release)")
    python = os.environ.get("GUIDE_PYTHON")
    if python is None:
        venv = ROOT / "target/venv/bin/python"
        python = str(venv) if venv.exists() else sys.executable
    return binary.resolve(), python


class Python:
    """One interpreter for a chapter's python blocks."""

    def __init__(self, python, cwd, env):
        self.proc = subprocess.Popen(
            [python, "-u", "-c", DRIVER], cwd=cwd, env=env, text=True,
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
        )

    def run(self, path):
        self.proc.stdin.write(f"{path}\n")
        self.proc.stdin.flush()
        output = []
        for line in self.proc.stdout:
            if line.startswith("@@guide-block-done@@"):
                return line.strip().endswith("ok"), "".join(output)
            output.append(line)
        return False, "".join(output) + "(the interpreter ended)"

    def close(self):
        self.proc.stdin.close()
        self.proc.wait()


def run_chapter(chapter, binary, python):
    """Runs one chapter; returns (blocks run, failures)."""
    failures, ran = [], 0
    with tempfile.TemporaryDirectory(prefix="rfeid-guide-") as tmp:
        work = pathlib.Path(tmp) / "work"
        work.mkdir()
        for d in ("examples", "data"):
            shutil.copytree(ROOT / d, work / d)
        bindir = pathlib.Path(tmp) / "bin"
        bindir.mkdir()
        (bindir / "rfeid").symlink_to(binary)
        # The interpreter's own directory on PATH, so that `python` in a shell
        # block is the virtual environment's (a link to it would not be).
        pydir = pathlib.Path(python).absolute().parent
        env = dict(os.environ, PATH=f"{bindir}:{pydir}:{os.environ['PATH']}",
                   MPLBACKEND="Agg", NO_COLOR="1")
        py = None
        for n, (line, lang, opts, text) in enumerate(blocks(chapter)):
            where = f"{chapter.relative_to(ROOT)}:{line}"
            if "file" in opts or "append" in opts:
                target = work / opts.get("file", opts.get("append"))
                target.parent.mkdir(parents=True, exist_ok=True)
                with open(target, "a" if "append" in opts else "w") as f:
                    f.write(text)
                continue
            if lang == "sh":
                want = int(opts.get("exit", 0))
                r = subprocess.run(["bash", "-e", "-o", "pipefail", "-c", text], cwd=work,
                                   env=env, capture_output=True, text=True, timeout=600)
                ran += 1
                if r.returncode != want:
                    failures.append(f"{where}: exit status {r.returncode}, expected {want}\n"
                                    f"{text}{r.stdout[-3000:]}{r.stderr[-3000:]}")
            elif lang == "python":
                py = py or Python(python, work, env)
                script = work / f".guide-block-{n}.py"
                script.write_text(text)
                ok, output = py.run(script)
                ran += 1
                if not ok:
                    failures.append(f"{where}: the Python block failed\n{text}{output[-3000:]}")
            if failures:
                break  # later blocks build on this one
        if py:
            py.close()
    return ran, failures


def anchors(path):
    """The anchors of a Markdown file's headings, as GitHub makes them."""
    out = set()
    for line in path.read_text().splitlines():
        if line.startswith("#"):
            title = line.lstrip("#").strip().lower()
            slug = "".join(c for c in title if c.isalnum() or c in " -_")
            out.add(slug.replace(" ", "-"))
    return out


def broken_links():
    """Relative links of README.md and docs/ whose file or heading is missing."""
    bad = []
    for doc in [ROOT / "README.md", ROOT / "CHANGELOG.md", *sorted((ROOT / "docs").rglob("*.md"))]:
        if not doc.exists():
            continue
        in_code = False
        for n, line in enumerate(doc.read_text().splitlines(), 1):
            if line.startswith("```"):
                in_code = not in_code
            if in_code:
                continue
            for target in re.findall(r"\]\(([^)\s]+)\)", line):
                if re.match(r"[a-z]+:", target):
                    continue  # a web address
                file, _, anchor = target.partition("#")
                path = (doc.parent / file).resolve() if file else doc
                if not path.exists():
                    bad.append(f"{doc.relative_to(ROOT)}:{n}: no such file: {target}")
                elif anchor and path.suffix == ".md" and anchor not in anchors(path):
                    bad.append(f"{doc.relative_to(ROOT)}:{n}: no such heading: {target}")
    return bad


def main():
    bad_links = broken_links()
    for b in bad_links:
        print(b, file=sys.stderr)
    if bad_links:
        sys.exit(f"guide_check: {len(bad_links)} broken link(s)")
    binary, python = tool_paths()
    chapters = [pathlib.Path(a).resolve() for a in sys.argv[1:]] or sorted(
        (ROOT / "docs/guide").glob("*.md"))
    def timed(chapter):
        t0 = time.monotonic()
        ran, failures = run_chapter(chapter, binary, python)
        return ran, failures, time.monotonic() - t0

    # Two chapters at a time: each runs in its own directory, and much of a
    # chapter's time is one process on one core.
    bad = 0
    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        for chapter, (ran, failures, seconds) in zip(chapters, pool.map(timed, chapters)):
            status = "ok" if not failures else "FAILED"
            print(f"{chapter.relative_to(ROOT)}: {ran} blocks, {seconds:.1f} s, {status}")
            for f in failures:
                print(f, file=sys.stderr)
            bad += bool(failures)
    if bad:
        sys.exit(f"guide_check: {bad} chapter(s) failed")


if __name__ == "__main__":
    main()
