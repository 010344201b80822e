#!/usr/bin/env python3
"""Writes examples/tailstock/force.csv: the tailstock example's "measured"
force, a stand-in made reproducible: seeded Gaussian noise, low-passed by
two passes of a one-pole filter at 300 Hz, scaled to 150 N RMS, sampled at
5 kHz for 0.3 s (column "hammer")."""
import math
import random
from pathlib import Path

random.seed(7)
rate, n = 5000.0, 1500
a = math.exp(-2 * math.pi * 300 / rate)
x = [random.gauss(0, 1) for _ in range(n)]
for _ in range(2):
    y, out = 0.0, []
    for v in x:
        y = a * y + (1 - a) * v
        out.append(y)
    x = out
rms = math.sqrt(sum(v * v for v in x) / n)
path = Path(__file__).resolve().parent.parent / "examples" / "tailstock" / "force.csv"
with open(path, "w") as f:
    f.write("time,hammer\n")
    for k, v in enumerate(x):
        f.write(f"{k / rate:.6f},{150.0 * v / rms:.6f}\n")
