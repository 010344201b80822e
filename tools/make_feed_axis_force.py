#!/usr/bin/env python3
"""Writes examples/feed-axis/force.csv: the feed-axis example's "measured"
drive force, a stand-in made reproducible: a slow back-and-forth command
(0.4 Hz, 150 N) plus seeded Gaussian noise low-passed by two passes of a
one-pole filter at 15 Hz (45 N RMS), as a motor current times its force
constant looks, sampled at 1 kHz for 20 s (column "drive")."""
import math
from pathlib import Path

from lowpassed_noise import lowpassed_noise

rate, n = 1000.0, 20000
x = lowpassed_noise(11, n, rate, 15)
path = Path(__file__).resolve().parent.parent / "examples" / "feed-axis" / "force.csv"
with open(path, "w") as f:
    f.write("time,drive\n")
    for k, v in enumerate(x):
        t = k / rate
        u = 150.0 * math.sin(2 * math.pi * 0.4 * t) + 45.0 * v
        f.write(f"{t:.3f},{u:.5g}\n")
