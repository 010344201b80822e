"""Simulation through Python against `rfeid simulate`'s CSV, bit for bit."""
import numpy as np
import pandas as pd
import pytest

import rfeid
from conftest import read_csv_exact


@pytest.mark.parametrize(
    "kwargs, args",
    [
        ({}, []),
        ({"noise": 0.02, "seed": 3}, ["--noise", "0.02", "--seed", "3"]),
        ({"set": {"a_n1": "450 daN/um^2"}, "noise": 0.01, "noise_corner": 400.0, "seed": 7},
         ["--set", "a_n1=450 daN/um^2", "--noise", "0.01", "--noise-corner", "400", "--seed", "7"]),
    ],
)
def test_simulation_equals_the_command_lines_csv(tmp_path, rfeid_cli, knee_column, kwargs, args):
    out = tmp_path / "sim.csv"
    rfeid_cli("simulate", knee_column, "-o", out, "-q", *args)
    cli = read_csv_exact(out)
    sim = rfeid.Model.load(knee_column).simulate(**kwargs)
    frame = sim.to_pandas()
    assert list(frame.columns) == list(cli.columns)
    for c in cli.columns:
        # Bit for bit: the CSV's numbers read back exactly.
        assert np.array_equal(frame[c].to_numpy(), cli[c].to_numpy()), c


def test_simulation_arrays(knee_column):
    sim = rfeid.Model.load(knee_column).simulate(set={"a_n1": 4e15})
    assert sim.values.shape == (len(sim.time), 3)
    assert sim.values.flags["C_CONTIGUOUS"]
    assert sim.time[0] == 0.0
    d = sim.to_dict()
    assert set(d) == {"time", "knee_ax", "knee_ay", "knee_az"}


def test_bad_settings_are_errors(knee_column):
    m = rfeid.Model.load(knee_column)
    with pytest.raises(rfeid.ModelError, match="unknown parameter 'nope'"):
        m.simulate(set={"nope": 1.0})
    with pytest.raises(rfeid.ModelError, match="dimension"):
        m.simulate(set={"a_n1": "3 kg"})
    with pytest.raises(ValueError, match="noise"):
        m.simulate(noise=-1.0)
    with pytest.raises(ValueError, match="noise_corner"):
        m.simulate(noise_corner=100.0)
    with pytest.raises(TypeError):
        m.simulate(set=["a_n1=1"])
