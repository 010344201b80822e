"""The Python module's overhead against the command line: the same
identification (model file and data file of an example) run five times
each way; prints the medians.

    python python/bench/overhead.py [EXAMPLE ...]      (default: knee-column lathe)

The command line is timed as a whole process (`rfeid identify … -o`), the
module as the call that does the same work in a running interpreter
(`Model.load`, `identify` from the file, `to_json` written to a file).
RFEID_BIN names the binary (default target/release/rfeid).
"""
import os
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

import rfeid

ROOT = pathlib.Path(__file__).resolve().parents[2]
BIN = pathlib.Path(os.environ.get("RFEID_BIN", ROOT / "target" / "release" / "rfeid"))


def median_of_5(run):
    times = []
    for _ in range(5):
        t = time.perf_counter()
        run()
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def main(examples):
    with tempfile.TemporaryDirectory() as tmp:
        for name in examples:
            model = ROOT / "examples" / name / "model.toml"
            data = pathlib.Path(tmp) / f"{name}.csv"
            subprocess.run([BIN, "simulate", model, "-o", data, "--noise", "0.02", "--seed", "1", "-q"], check=True)
            out = pathlib.Path(tmp) / "r.json"

            def cli():
                p = subprocess.run([BIN, "identify", model, "--data", data, "-o", out, "-q"], stderr=subprocess.DEVNULL)
                assert p.returncode in (0, 3, 4), p.returncode

            def module():
                res = rfeid.identify(rfeid.Model.load(model), str(data))
                out.write_text(res.to_json())

            c, m = median_of_5(cli), median_of_5(module)
            print(f"{name}: command line {c:.3f} s, Python {m:.3f} s (median of 5): ratio {m / c:.3f}")


if __name__ == "__main__":
    main(sys.argv[1:] or ["knee-column", "lathe"])
