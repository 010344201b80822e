#!/usr/bin/env python3
"""Whole-process times of `rfeid simulate` on the knee-column example and on a
generated 50-body model, alternating, with the run's own time that `simulate`
prints (the simulation alone): medians of N runs each.

Usage: tools/simulate_times.py RFEID_BINARY N [M50_TOML]
The 50-body model is made with
  cargo run --release -p rfeid --example machine_tool -- 50 16 > m50.toml
(default path /tmp/m50.toml)."""
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
binary, n = sys.argv[1], int(sys.argv[2])
cases = {
    "kc": os.path.join(root, "examples/knee-column/model.toml"),
    "m50": sys.argv[3] if len(sys.argv) > 3 else "/tmp/m50.toml",
}
whole = {k: [] for k in cases}
alone = {k: [] for k in cases}
with tempfile.TemporaryDirectory() as out:
    for _ in range(n):
        for k, model in cases.items():
            t = time.perf_counter()
            p = subprocess.run([binary, "simulate", model, "-o", os.path.join(out, k + ".csv")],
                               check=True, capture_output=True, text=True)
            whole[k].append(time.perf_counter() - t)
            alone[k].append(float(re.search(r"in ([0-9.]+) ms", p.stderr + p.stdout).group(1)) / 1e3)
for k in cases:
    w, a = statistics.median(whole[k]), statistics.median(alone[k])
    # The ratio within each run is steadier than the ratio of the medians
    # when the host's load changes between runs.
    r = statistics.median(x / y for x, y in zip(whole[k], alone[k]))
    print(f"{k}: whole process {w * 1e3:.1f} ms, simulation alone {a * 1e3:.1f} ms, "
          f"ratio of medians {w / a:.2f}, median ratio per run {r:.2f}")
print(f"m50 / knee-column, whole process: {statistics.median(whole['m50']) / statistics.median(whole['kc']):.1f}")
