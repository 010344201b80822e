"""Shared fixtures: the repository's examples, the command-line binary the
same build made (to compare with), and a scratch directory."""
import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"


def cli_binary() -> pathlib.Path:
    """The `rfeid` binary: $RFEID_BIN, else target/release/rfeid."""
    path = pathlib.Path(os.environ.get("RFEID_BIN", ROOT / "target" / "release" / "rfeid"))
    if not path.exists():
        pytest.fail(f"{path}: the command-line binary is needed to compare with (cargo build --release)")
    return path


@pytest.fixture(scope="session")
def rfeid_cli():
    """Runs the command line; returns the completed process."""
    binary = cli_binary()

    def run(*args, check=True):
        p = subprocess.run([str(binary), *map(str, args)], capture_output=True, text=True)
        if check and p.returncode not in (0, 3, 4):
            raise AssertionError(f"rfeid {' '.join(map(str, args))}: exit {p.returncode}\n{p.stderr}")
        return p

    return run


@pytest.fixture(scope="session")
def knee_column():
    return EXAMPLES / "knee-column" / "model.toml"


def read_csv_exact(path):
    """A CSV of the command line as a DataFrame, each number parsed by
    Python's correctly rounded float(), so that equal text is equal bits."""
    import csv

    import pandas as pd

    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    return pd.DataFrame({h: [float(r[i]) for r in body] for i, h in enumerate(header)})


def seconds_to_stop(call, after=0.5):
    """Sends SIGINT to the main thread `after` seconds into `call()` (from
    another thread, as Ctrl-C would) and returns how long `call` took to
    raise KeyboardInterrupt after the signal."""
    import signal
    import threading
    import time

    sent = []

    def interrupt():
        time.sleep(after)
        sent.append(time.monotonic())
        signal.pthread_kill(threading.main_thread().ident, signal.SIGINT)

    threading.Thread(target=interrupt, daemon=True).start()
    with pytest.raises(KeyboardInterrupt):
        call()
    stopped = time.monotonic()
    assert sent, "the call ended before the signal"
    return stopped - sent[0]
