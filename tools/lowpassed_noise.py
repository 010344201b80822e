"""Seeded Gaussian noise low-passed by two passes of a one-pole filter and
scaled to unit RMS: the stand-in for a "measured" force that the examples'
force generators (make_*_force.py) build on."""
import math
import random


def lowpassed_noise(seed, n, rate, corner):
    """n samples at `rate` Hz with the filter's corner at `corner` Hz."""
    random.seed(seed)
    a = math.exp(-2 * math.pi * corner / rate)
    x = [random.gauss(0, 1) for _ in range(n)]
    for _ in range(2):
        y, out = 0.0, []
        for v in x:
            y = a * y + (1 - a) * v
            out.append(y)
        x = out
    rms = math.sqrt(sum(v * v for v in x) / n)
    return [v / rms for v in x]
