#!/usr/bin/env python3
"""Writes examples/feed-axis/force.csv: the feed-axis example's "measured"
drive force, a stand-in made reproducible: a slow back-and-forth command
(0.4 Hz, 150 N) plus seeded Gaussian noise low-passed by two passes of a
one-pole filter at 15 Hz (45 N RMS), as a motor current times its force
constant looks, sampled at 1 kHz for 20 s (column "drive")."""
import math
import random
from pathlib import Path

random.seed(11)
rate, n = 1000.0, 20000
a = math.exp(-2 * math.pi * 15 / rate)
x = [random.gauss(0, 1) for _ in range(n)]
for _ in range(2):
    y, out = 0.0, []
    for v in x:
        y = a * y + (1 - a) * v
        out.append(y)
    x = out
rms = math.sqrt(sum(v * v for v in x) / n)
path = Path(__file__).resolve().parent.parent / "examples" / "feed-axis" / "force.csv"
with open(path, "w") as f:
    f.write("time,drive\n")
    for k, v in enumerate(x):
        t = k / rate
        u = 150.0 * math.sin(2 * math.pi * 0.4 * t) + 45.0 * v / rms
        f.write(f"{t:.3f},{u:.5g}\n")
