#!/usr/bin/env python3
"""Executes a notebook with nbclient, so that the example cannot rot.

    python tools/run_notebook.py NOTEBOOK [--min-images N] [--timeout S]

Run with the interpreter whose packages the notebook needs (tools/test uses
target/venv, with nbclient, ipykernel and matplotlib). The notebook must be
stored without outputs (git holds the source, not a run's figures); it is
run in its own folder on the kernel `python3` of that interpreter, and not
written back. Fails (exit 1) on any cell's error, on a cell running longer
than S seconds (default 300), or when fewer than N `image/png` outputs
(figures; default 0) come out. Prints the execution's wall time.
"""
import argparse
import pathlib
import sys
import time

import nbclient
import nbformat


def stored_outputs(nb):
    """The code cells (1-based) stored with outputs or execution counts."""
    return [
        k
        for k, c in enumerate(nb.cells, 1)
        if c.cell_type == "code" and (c.get("outputs") or c.get("execution_count") is not None)
    ]


def images(nb):
    """How many image/png outputs the executed notebook holds."""
    return sum(
        "image/png" in o.get("data", {})
        for c in nb.cells
        if c.cell_type == "code"
        for o in c.get("outputs", [])
    )


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("notebook", type=pathlib.Path)
    ap.add_argument("--min-images", type=int, default=0)
    ap.add_argument("--timeout", type=int, default=300, help="seconds per cell")
    args = ap.parse_args()
    path = args.notebook.resolve()
    nb = nbformat.read(path, as_version=4)
    stored = stored_outputs(nb)
    if stored:
        sys.exit(f"{args.notebook}: code cells {stored} are stored with outputs; clear them before committing")
    client = nbclient.NotebookClient(
        nb, timeout=args.timeout, kernel_name="python3", resources={"metadata": {"path": str(path.parent)}}
    )
    t0 = time.monotonic()
    try:
        client.execute()
    except nbclient.exceptions.CellExecutionError as e:
        sys.exit(f"{args.notebook}: a cell failed after {time.monotonic() - t0:.1f} s:\n{e}")
    seconds = time.monotonic() - t0
    n = images(nb)
    cells = sum(c.cell_type == "code" for c in nb.cells)
    print(f"{args.notebook}: {cells} code cells ran in {seconds:.1f} s, {n} figures (image/png)")
    if n < args.min_images:
        sys.exit(f"{args.notebook}: {n} image/png outputs, expected at least {args.min_images}")


if __name__ == "__main__":
    main()
