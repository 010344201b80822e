"""FRFs from Python (`Identification.frf`) against `rfeid frf --result`:
the same model FRF and band, H1 of the identification's data, the
DataFrame's shape, and bad values refused."""
import json

import numpy as np
import pytest

import rfeid
from conftest import EXAMPLES


def test_frf_of_an_identification_equals_the_command_line(tmp_path, rfeid_cli):
    model = EXAMPLES / "knee-column" / "model.toml"
    data = tmp_path / "data.csv"
    rfeid_cli("simulate", model, "-o", data, "--noise", "0.02", "--seed", "4", "-q")
    res = rfeid.identify(rfeid.Model.load(model), str(data))
    result = tmp_path / "result.json"
    result.write_text(res.to_json())
    frf = res.frf(fmin=10.0, fmax=400.0, points=300)
    out = tmp_path / "frf.json"
    rfeid_cli("frf", model, "--result", result, "--fmin", "10", "--fmax", "400", "--points", "300", "--json-file", out, "-q")
    cli = json.loads(out.read_text())
    assert frf.document["linearised_at"] == "rest"
    assert np.array_equal(frf.frequencies, cli["frequencies_hz"])
    for p, q in zip(frf.document["pairs"], cli["pairs"]):
        assert (p["excitation"], p["output"]) == (q["excitation"], q["output"])
        assert np.array_equal(p["real"], q["real"]) and np.array_equal(p["imag"], q["imag"])
        assert np.array_equal(p["band"]["magnitude_hi"], q["band"]["magnitude_hi"])
    h = frf.response("knee_ax")
    lo, hi = frf.band("knee_ax")
    assert h.dtype == complex and np.all(lo <= np.abs(h)) and np.all(np.abs(h) <= hi)
    df = frf.to_pandas()
    assert set(df["curve"]) == {"model", "H1 measured"}
    assert len(df[df["curve"] == "model"]) == 3 * 300
    assert df.loc[df["curve"] == "H1 measured", "coherence"].between(0, 1).all()
    assert frf.svg.startswith("<svg")
    assert frf.plot(tmp_path / "frf.svg").endswith("frf.svg")


def test_bad_frf_values_are_refused(tmp_path, rfeid_cli):
    model = EXAMPLES / "knee-column" / "model.toml"
    data = tmp_path / "data.csv"
    rfeid_cli("simulate", model, "-o", data, "--noise", "0.02", "--seed", "5", "-q")
    res = rfeid.identify(rfeid.Model.load(model), str(data))
    for kwargs in ({"fmax": -1.0}, {"points": 1}, {"spacing": "octave"}, {"segment": 1000}, {"fmin": 1e9}):
        with pytest.raises(ValueError):
            res.frf(**kwargs)
    with pytest.raises(KeyError):
        res.frf(points=10).response("nope")
