#!/usr/bin/env python3
"""Writes examples/tailstock/force.csv: the tailstock example's "measured"
force, a stand-in made reproducible: seeded Gaussian noise, low-passed by
two passes of a one-pole filter at 300 Hz, scaled to 150 N RMS, sampled at
5 kHz for 0.3 s (column "hammer")."""
from pathlib import Path

from lowpassed_noise import lowpassed_noise

rate, n = 5000.0, 1500
x = lowpassed_noise(7, n, rate, 300)
path = Path(__file__).resolve().parent.parent / "examples" / "tailstock" / "force.csv"
with open(path, "w") as f:
    f.write("time,hammer\n")
    for k, v in enumerate(x):
        f.write(f"{k / rate:.6f},{150.0 * v:.6f}\n")
