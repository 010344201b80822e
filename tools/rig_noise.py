#!/usr/bin/env python3
"""Rehearse identification on noise as a test rig records it, and tabulate how
honest the standard errors and the verdicts are.

The script simulates the clean record once (`rfeid simulate` of the data
model, --data-model, default --model, at its parameters' true `value`s), then
for each seed adds noise, writes the noisy CSV (same header and time column,
values printed to round trip), runs `rfeid identify` with --model on it and
reads RESULT.json. For every identified parameter it forms
z = (estimate - truth) / std_error, estimate and std_error in SI from
RESULT.json's `parameters`, the truth the data model's `value` in SI (from
`rfeid check --json`). With the default data model that is RESULT.json's
`nominal`. A different --data-model rehearses fitting a wrong model: the truth
is taken only where a parameter of that name has the same SI unit in both
models; other parameters get no z (e.g. a power law's `a` when the exponent m
differs: N/m^2.1 is not N/m^2) and are left out of RMS z and max |z|. Honest
standard errors give z of RMS about 1 and |z| beyond 3 about once in 370
estimates.

Usage (numpy and scipy needed, e.g. a venv):
  python tools/rig_noise.py --rfeid BIN --model MODEL [--data-model MODEL]
      [--seeds 1-10] [--noise 0.02] [--filter SPEC ...] [--hum H] [--flicker F]
      [--common C] [--from SECONDS] [--extra "identify args"] [--keep DIR]
      [--jobs 2] [--json-out FILE] [--summary-json FILE]

Noise of each sensor, total standard deviation NOISE x RMS of that sensor's
clean signal (over the whole record), made of four independent parts whose
variances are fractions of the total:
  base     1 - H - F - C: white Gaussian noise through the filter, stationary
           from the first sample (the filter runs over a burn-in of BURN
           samples first, which is discarded). Filter SPEC:
             butter:FC  2nd-order Butterworth low-pass, corner FC Hz
             ellip:FC   4th-order elliptic low-pass (0.5 dB ripple, 60 dB
                        stop band), edge FC Hz
             white      no filter
  hum      H: mains at 50 Hz detuned by a random +-0.5 % per seed (the same
           for all sensors), harmonics 100 and 150 Hz, amplitudes 1, 0.5,
           0.3, random phases per sensor and harmonic.
  flicker  F: 1/f noise, white noise shaped by 1/sqrt(f) over a circular
           buffer of at least 16 records (its lowest frequency well below
           1/record), so stationary; independent per sensor.
  common   C: one low-passed (same filter) sequence shared by all sensors,
           scaled to each sensor's share.
Every part is normalised by its theoretical variance, not by the sample's.
The generator is numpy's default_rng(seed), and every part is always drawn in
the same order, so one seed gives the same underlying sequences whatever the
shares and filter: settings compared at equal seeds are paired.

Each --filter SPEC given is one setting; per setting one line is printed:
verdict counts (trustworthy = exit 0, suspect = 3, model error = 4, failed =
anything else or no RESULT.json), RMS z over every seed and parameter that
has a z, the largest |z| with its seed and parameter, and the median wall time
of the `identify` process; `from S` and `data FILE` appear in the line only
when --from resp. a different --data-model is given. --json-out writes every
seed's result (exit status, verdict reasons, estimates, standard errors,
truths, z, wall time). --summary-json appends the same summary as one JSON
line per setting (filter, noise, hum, flicker, common, from, model, data
model, seeds, verdict counts, z count, RMS z, max |z| with seed and parameter,
median wall time), to build tables from several runs.

Seeds run --jobs at a time (default 2); with more than one job each identify
gets `--threads 1`. --from is passed to identify (the noise still covers the
whole record), --extra is split like a shell line and appended to identify's
arguments (write it --extra="--plan 200 --starts 3": argparse would take a
separate value that starts with "-" for an option). --keep DIR keeps the clean and noisy CSVs and the RESULT.json files
there (otherwise a temporary directory is removed at the end).

Example:
  python3 tools/rig_noise.py --rfeid target/release/rfeid \\
      --model examples/knee-column/model.toml --filter butter:1000 white --hum 0.15
"""
import argparse
import concurrent.futures
import json
import math
import os
import shlex
import statistics
import subprocess
import tempfile
import time

import numpy as np
from scipy import signal

BURN = 20000  # burn-in samples of the filters: thousands of time constants
VERDICTS = {0: "trustworthy", 3: "suspect", 4: "model error"}
HUM = ((1, 1.0), (2, 0.5), (3, 0.3))  # (harmonic, relative amplitude)


def parse_seeds(text):
    """'1-10' or '1,3,7-9' -> list of ints."""
    seeds = []
    for part in text.split(","):
        lo, _, hi = part.partition("-")
        seeds += range(int(lo), int(hi or lo) + 1)
    return seeds


def make_filter(spec, fs):
    """SOS of the filter SPEC (None for white) and its noise gain (RMS out/in)."""
    kind, _, fc = spec.partition(":")
    if kind == "white":
        return None, 1.0
    if kind == "butter":
        sos = signal.butter(2, float(fc), fs=fs, output="sos")
    elif kind == "ellip":
        sos = signal.ellip(4, 0.5, 60, float(fc), fs=fs, output="sos")
    else:
        raise SystemExit(f"rig_noise: unknown filter {spec!r} (butter:FC, ellip:FC or white)")
    impulse = np.zeros(BURN)
    impulse[0] = 1.0
    return sos, math.sqrt(np.sum(signal.sosfilt(sos, impulse) ** 2))


def filtered(rng, n, sos, gain):
    """n samples of unit-variance stationary filtered white noise."""
    w = rng.standard_normal(BURN + n)
    return (w if sos is None else signal.sosfilt(sos, w))[BURN:] / gain


def flicker(rng, n):
    """n samples of unit-variance stationary 1/f noise."""
    size = 1 << math.ceil(math.log2(16 * n))
    f = np.fft.rfftfreq(size)
    shape = np.zeros_like(f)
    shape[1:] = f[1:] ** -0.5
    var = (2 * np.sum(shape[1:-1] ** 2) + shape[-1] ** 2) / size  # of the real result
    y = np.fft.irfft(np.fft.rfft(rng.standard_normal(size)) * shape, size)
    return y[:n] / math.sqrt(var)


def rig_noise(seed, clean, fs, sos, gain, a):
    """Noise (samples x sensors) of one seed, as described in the docstring."""
    n, m = clean.shape
    rng = np.random.default_rng(seed)
    t = np.arange(n) / fs
    mains = 50.0 * (1 + rng.uniform(-0.005, 0.005))
    common = filtered(rng, n, sos, gain)
    hum_norm = math.sqrt(sum(amp**2 for _, amp in HUM) / 2)
    out = np.empty_like(clean)
    for j in range(m):
        base = filtered(rng, n, sos, gain)
        phases = rng.uniform(0, 2 * math.pi, len(HUM))
        hum = sum(amp * np.sin(2 * math.pi * k * mains * t + ph)
                  for (k, amp), ph in zip(HUM, phases)) / hum_norm
        flick = flicker(rng, n)
        sigma = a.noise * math.sqrt(np.mean(clean[:, j] ** 2))
        out[:, j] = sigma * (math.sqrt(1 - a.hum - a.flicker - a.common) * base
                             + math.sqrt(a.hum) * hum + math.sqrt(a.flicker) * flick
                             + math.sqrt(a.common) * common)
    return out


def model_values(rfeid, model):
    """{name: (value in SI, SI unit)} of a model's parameters (`check --json`)."""
    out = subprocess.run([rfeid, "check", "--json", "-q", model],
                         capture_output=True, text=True, check=True).stdout
    return {q["name"]: (q["nominal"], q["si_unit"]) for q in json.loads(out)["parameters"]}


def run_seed(seed, spec, clean_csv, sos, gain, truth, outdir, a):
    """Write one noisy record, identify it, and return its result."""
    header, times, clean, fs = clean_csv
    stem = os.path.join(outdir, f"{spec.replace(':', '')}-seed{seed}")
    noisy = clean + rig_noise(seed, clean, fs, sos, gain, a)
    with open(stem + ".csv", "w") as f:
        f.write(header)
        for t, row in zip(times, noisy.tolist()):
            f.write(t + "," + ",".join(map(repr, row)) + "\n")
    cmd = [a.rfeid, "identify", a.model, "--data", stem + ".csv", "-o", stem + ".json", "-q"]
    if a.jobs > 1:
        cmd += ["--threads", "1"]
    if a.start is not None:
        cmd += ["--from", str(a.start)]
    cmd += shlex.split(a.extra)
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True)
    res = {"seed": seed, "exit": p.returncode, "wall": time.perf_counter() - t0,
           "verdict": VERDICTS.get(p.returncode, "failed")}
    if res["verdict"] == "failed" or not os.path.exists(stem + ".json"):
        return dict(res, verdict="failed", stderr=p.stderr.strip()[-2000:])
    with open(stem + ".json") as f:
        r = json.load(f)
    res["reasons"] = r["verdict"]["reasons"]
    res["std_errors_cover"] = r.get("std_errors_cover")
    res["parameters"] = {}
    for q in r["parameters"]:
        t = truth.get(q["name"])
        z = None if t is None or not q["std_error"] else (q["estimate"] - t) / q["std_error"]
        res["parameters"][q["name"]] = {"estimate": q["estimate"], "std_error": q["std_error"],
                                        "nominal": q["nominal"], "truth": t, "z": z}
    return res


def summary(spec, a, results):
    """The setting's summary as a dict (one line of --summary-json)."""
    zs = [(abs(p["z"]), r["seed"], name) for r in results
          for name, p in r.get("parameters", {}).items() if p["z"] is not None]
    worst = max(zs, default=(None, None, None))
    return {"filter": spec, "noise": a.noise, "hum": a.hum, "flicker": a.flicker,
            "common": a.common, "from": a.start, "model": a.model,
            "data_model": a.data_model, "seeds": a.seeds,
            "counts": {v: sum(r["verdict"] == v for r in results)
                       for v in ("trustworthy", "suspect", "model error", "failed")},
            "z_count": len(zs),
            "rms_z": math.sqrt(sum(z * z for z, _, _ in zs) / len(zs)) if zs else None,
            "max_abs_z": worst[0], "max_seed": worst[1], "max_parameter": worst[2],
            "median_wall": statistics.median(r["wall"] for r in results)}


def summary_line(s):
    """The setting's one-line summary, as printed."""
    line = (f"{s['filter']} noise {s['noise']:g} hum {s['hum']:g} flicker {s['flicker']:g}"
            f" common {s['common']:g}")
    if s["from"] is not None:
        line += f" from {s['from']:g}"
    if s["data_model"] != s["model"]:
        line += f" data {os.path.basename(s['data_model'])}"
    line += f" seeds {s['seeds']}: " + ", ".join(f"{v} {c}" for v, c in s["counts"].items())
    if s["z_count"]:
        line += (f"; RMS z {s['rms_z']:.3f}, max |z| {s['max_abs_z']:.2f}"
                 f" (seed {s['max_seed']}, {s['max_parameter']})")
    return line + f"; median identify {s['median_wall']:.2f} s"


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rfeid", required=True, help="the rfeid binary")
    ap.add_argument("--model", required=True, help="model file (TOML) that is fitted")
    ap.add_argument("--data-model", help="model whose clean record is simulated (default --model)")
    ap.add_argument("--seeds", default="1-10", help="e.g. 1-10 or 1,4,7-9 (default 1-10)")
    ap.add_argument("--noise", type=float, default=0.02, help="total noise σ / signal RMS")
    ap.add_argument("--filter", nargs="+", default=["butter:1000"], metavar="SPEC",
                    help="butter:FC, ellip:FC or white; several: one setting each")
    ap.add_argument("--hum", type=float, default=0.0, help="mains hum's share of the variance")
    ap.add_argument("--flicker", type=float, default=0.0, help="1/f noise's share")
    ap.add_argument("--common", type=float, default=0.0, help="shared noise's share")
    ap.add_argument("--from", dest="start", type=float, help="identify --from SECONDS")
    ap.add_argument("--extra", default="", help="further identify arguments, one string")
    ap.add_argument("--keep", help="keep CSVs and RESULT.json files in this directory")
    ap.add_argument("--jobs", type=int, default=2, help="identify runs at a time")
    ap.add_argument("--json-out", help="write every seed's result to this JSON file")
    ap.add_argument("--summary-json", help="append one JSON line per setting to this file")
    a = ap.parse_args()
    if min(a.hum, a.flicker, a.common) < 0 or a.hum + a.flicker + a.common > 1:
        ap.error("--hum, --flicker and --common must be >= 0 and sum to at most 1")
    a.rfeid, a.model = os.path.abspath(a.rfeid), os.path.abspath(a.model)
    a.data_model = os.path.abspath(a.data_model or a.model)
    fitted = model_values(a.rfeid, a.model)
    truth = {name: v for name, (v, unit) in model_values(a.rfeid, a.data_model).items()
             if name in fitted and fitted[name][1] == unit}
    tmp = None if a.keep else tempfile.TemporaryDirectory()
    outdir = a.keep or tmp.name
    os.makedirs(outdir, exist_ok=True)

    clean_path = os.path.join(outdir, "clean.csv")
    subprocess.run([a.rfeid, "simulate", a.data_model, "-o", clean_path, "-q"], check=True)
    with open(clean_path) as f:
        header, *lines = f.readlines()
    times = [ln.split(",", 1)[0] for ln in lines]
    clean = np.array([[float(v) for v in ln.split(",")[1:]] for ln in lines])
    fs = (len(times) - 1) / (float(times[-1]) - float(times[0]))
    clean_csv = (header, times, clean, fs)

    settings = []
    for spec in a.filter:
        sos, gain = make_filter(spec, fs)
        with concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
            results = list(pool.map(
                lambda s: run_seed(s, spec, clean_csv, sos, gain, truth, outdir, a),
                parse_seeds(a.seeds)))
        s = summary(spec, a, results)
        print(summary_line(s), flush=True)
        if a.summary_json:
            with open(a.summary_json, "a") as f:
                f.write(json.dumps(s) + "\n")
        settings.append({"filter": spec, "summary": s, "results": results})
    if a.json_out:
        with open(a.json_out, "w") as f:
            json.dump({"args": vars(a), "settings": settings}, f, indent=1)
    if tmp:
        tmp.cleanup()


if __name__ == "__main__":
    main()
