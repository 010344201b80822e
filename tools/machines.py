#!/usr/bin/env python3
"""Times `rfeid identify` on generated 20-body machines against the
knee-column, in one run (issue 46).

For each stiffness factor (default 5, 10, 20) and each geometry seed 1-3
(seed 1 a chain, 2 a tower, 3 a gantry, each with its geometry varied by
the seed), the example `machine_tool` writes the model, `rfeid simulate`
adds 1 % noise (seed 1), and `rfeid identify --timings` fits it. The
knee-column (2 % noise, seed 1) runs before every machine, so each ratio
compares runs made under the same load. Prints one line per machine with
the median over ROUNDS rounds of the whole process's wall time, the ratio
to the knee-column's median, the steps per sample and the verdict.

Usage: tools/machines.py [--rounds N] [--stiffer 5,10,20] [--bodies 20]
       [--params 16] [--shapes chain,tower,gantry]
Build first: cargo build --release -p rfeid-cli -p rfeid --example machine_tool
"""
import argparse
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
RFEID = ROOT / "target/release/rfeid"
GENERATOR = ROOT / "target/release/examples/machine_tool"


def run(args):
    """Runs a command; returns (seconds, stdout + stderr); exits on failure
    other than the verdicts' statuses 3 and 4."""
    t0 = time.perf_counter()
    p = subprocess.run(args, capture_output=True, text=True)
    dt = time.perf_counter() - t0
    if p.returncode not in (0, 3, 4):
        sys.exit(f"{' '.join(map(str, args))} failed ({p.returncode}):\n{p.stderr}")
    return dt, p.stdout + p.stderr


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--stiffer", default="5,10,20")
    ap.add_argument("--bodies", type=int, default=20)
    ap.add_argument("--params", type=int, default=16)
    ap.add_argument("--shapes", default="chain,tower,gantry")
    a = ap.parse_args()
    for exe in (RFEID, GENERATOR):
        if not exe.exists():
            sys.exit(f"{exe} is missing; build it first (see --help)")
    shapes = a.shapes.split(",")
    work = Path(tempfile.mkdtemp(prefix="machines-"))
    knee = ROOT / "examples/knee-column/model.toml"
    run([RFEID, "simulate", knee, "-o", work / "kc.csv", "--noise", "0.02", "--seed", "1", "-q"])
    cases = []
    for f in a.stiffer.split(","):
        for seed, shape in enumerate(shapes, start=1):
            name = f"{shape}-{f}x-seed{seed}"
            model = work / f"{name}.toml"
            text = subprocess.run(
                [GENERATOR, str(a.bodies), str(a.params), shape, f, str(seed)],
                capture_output=True, text=True, check=True).stdout
            model.write_text(text)
            _, out = run([RFEID, "simulate", model, "-o", work / f"{name}.csv",
                          "--noise", "0.01", "--seed", "1"])
            steps = re.search(r"(\d+) step\(s\) per sample", out)
            cases.append((name, model, steps.group(1) if steps else "?"))
    print(f"{'machine':<24} {'steps':>5} {'median s':>9} {'knee s':>7} {'x knee':>7}  verdict")
    ratios = []
    for name, model, steps in cases:
        times, knees, verdict = [], [], "?"
        for _ in range(a.rounds):
            dt, _ = run([RFEID, "identify", knee, "--data", work / "kc.csv", "-q",
                         "-o", work / "kc-out"])
            knees.append(dt)
            dt, out = run([RFEID, "identify", model, "--data", work / f"{name}.csv",
                           "-o", work / f"{name}-out"])
            times.append(dt)
            m = re.search(r"verdict: ([^(—\n]*[^ (—\n])", out)
            verdict = m.group(1) if m else "?"
        t, k = statistics.median(times), statistics.median(knees)
        ratios.append(t / k)
        print(f"{name:<24} {steps:>5} {t:>9.2f} {k:>7.2f} {t / k:>7.1f}  {verdict}",
              flush=True)
    print(f"ratios: {min(ratios):.1f} to {max(ratios):.1f}, median {statistics.median(ratios):.1f}"
          f" ({a.rounds} rounds; models in {work})")


if __name__ == "__main__":
    main()
