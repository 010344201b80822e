#!/usr/bin/env python3
"""Times `rfeid identify` on the knee-column (2 % noise, seed 1) against one
simulation of the same model with scipy, alternating, in one run (issue 46's
first row).

The scipy simulation is the one a typical script would make: `solve_ivp`
with the model's right-hand side from `tools/reference/knee_column.py` (an
implementation straight from SPEC §1 and §4 that shares no code with rfeid),
dense output at the 3000 sample instants, and the tolerance rfeid's own run
meets (relative 1e-7, absolute 1e-7 of each state's scale). Both methods are
timed, DOP853 and RK45; the simulation's relative RMS difference from rfeid's
noise-free response is printed so that the two are compared at the same
accuracy.

Usage: tools/scipy_knee.py [--rounds N]   (needs numpy and scipy)
Build first: cargo build --release -p rfeid-cli
"""
import argparse
import csv
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools/reference"))
import knee_column as kc  # noqa: E402

RFEID = ROOT / "target/release/rfeid"
MODEL = ROOT / "examples/knee-column/model.toml"


def scipy_simulation(method, rtol=1e-7):
    """One simulation of the knee-column: the sensors' accelerations at the
    sample instants (3000 × 3) and the number of right-hand side calls."""
    kc.NFEV[0] = 0
    sol = solve_ivp(kc.rhs, (0.0, kc.T_SAMPLES[-1]), np.zeros(2 * kc.NQ), method=method,
                    t_eval=kc.T_SAMPLES, rtol=rtol, atol=rtol * kc.SCALE)
    if not sol.success:
        sys.exit(f"scipy {method}: {sol.message}")
    return kc.sensor_matrix(sol.y.T), kc.NFEV[0]


def timed(f):
    t0 = time.perf_counter()
    out = f()
    return time.perf_counter() - t0, out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=5)
    a = ap.parse_args()
    if not RFEID.exists():
        sys.exit(f"{RFEID} is missing; build it first (see --help)")
    work = Path(tempfile.mkdtemp(prefix="scipy-knee-"))
    data, clean = work / "kc.csv", work / "clean.csv"
    for path, noise in ((data, ["--noise", "0.02", "--seed", "1"]), (clean, [])):
        subprocess.run([RFEID, "simulate", MODEL, "-o", path, "-q", *noise], check=True)
    with open(clean) as fh:
        rows = list(csv.reader(fh))
    reference = np.array([[float(v) for v in r[1:]] for r in rows[1:]])
    times = {"identify": [], "DOP853": [], "RK45": []}
    calls = {}
    for _ in range(a.rounds):
        dt, p = timed(lambda: subprocess.run(
            [RFEID, "identify", MODEL, "--data", data, "-o", work / "r.json", "-q"],
            capture_output=True))
        if p.returncode != 0:
            sys.exit(f"rfeid identify failed ({p.returncode}): {p.stderr.decode()}")
        times["identify"].append(dt)
        for method in ("DOP853", "RK45"):
            dt, (y, nfev) = timed(lambda: scipy_simulation(method))
            times[method].append(dt)
            err = np.sqrt(np.mean((y - reference) ** 2, axis=0) / np.mean(reference ** 2, axis=0))
            calls[method] = (nfev, err.max())
    ident = statistics.median(times["identify"])
    print(f"rfeid identify: median {ident:.3f} s of {a.rounds} "
          f"({', '.join(f'{t:.3f}' for t in times['identify'])})")
    for method in ("DOP853", "RK45"):
        sim = statistics.median(times[method])
        nfev, err = calls[method]
        print(f"scipy solve_ivp {method} rtol 1e-7: median {sim:.3f} s "
              f"({', '.join(f'{t:.3f}' for t in times[method])}), {nfev} calls, "
              f"relative RMS difference from rfeid's response {err:.1e}; "
              f"identify / simulation = {ident / sim:.2f}")


if __name__ == "__main__":
    main()
