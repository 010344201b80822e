"""Identification through Python against `rfeid identify`'s RESULT.json (bit
for bit),
errors, the report, and Ctrl-C."""
import json
import os
import re

import numpy as np
import pandas as pd
import pytest

import rfeid
from conftest import EXAMPLES, read_csv_exact, seconds_to_stop


def close(a, b, rel=0.0):
    """a and b equal to `rel` relative, by default bit for bit
    (element-wise, NaN where both are)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    both_nan = np.isnan(a) & np.isnan(b)
    diff = np.abs(a - b)
    ok = both_nan | (diff <= rel * np.maximum(np.abs(b), 1e-300)) | (diff == 0)
    return bool(np.all(ok))


def measured(tmp_path, rfeid_cli, model, seed=1, noise="0.02"):
    data = tmp_path / "data.csv"
    rfeid_cli("simulate", model, "-o", data, "--noise", noise, "--seed", seed, "-q")
    return data


@pytest.mark.parametrize("example", ["knee-column", "lathe"])
def test_identification_from_a_data_frame_equals_the_command_line(tmp_path, rfeid_cli, example):
    model = EXAMPLES / example / "model.toml"
    data = measured(tmp_path, rfeid_cli, model)
    out = tmp_path / "result.json"
    rfeid_cli("identify", model, "--data", data, "-o", out, "-q")
    cli = json.loads(out.read_text())
    m = rfeid.Model.load(model)
    frame = read_csv_exact(data)
    res = rfeid.identify(m, frame)
    assert res.parameter_names == [p["name"] for p in cli["parameters"]]
    assert close([res.estimates[p["name"]] for p in cli["parameters"]], [p["estimate"] for p in cli["parameters"]])
    assert close([res.std_errors[p["name"]] for p in cli["parameters"]], [p["std_error"] for p in cli["parameters"]])
    assert close(res.correlation, [[np.nan if v is None else v for v in row] for row in cli["correlation"]])
    assert close(res.document["criterion"], cli["criterion"])
    assert res.verdict.trustworthy == cli["verdict"]["trustworthy"]
    # From the file itself: the whole document, but for the wall times.
    res = rfeid.identify(m, str(data))
    doc = json.loads(res.to_json())
    for d in (doc, cli):
        d.pop("timings")
    assert doc == cli


def test_a_mapping_and_options_with_the_command_lines_names(tmp_path, rfeid_cli, knee_column):
    data = measured(tmp_path, rfeid_cli, knee_column, seed=2)
    out = tmp_path / "result.json"
    rfeid_cli("identify", knee_column, "--data", data, "-o", out, "-q", "--plan", "40", "--weights", "equal",
              "--window", "0", "--set", "a_n4=6.6e15", "--threads", "1")
    cli = json.loads(out.read_text())
    frame = read_csv_exact(data)
    mapping = {c: frame[c].to_numpy() for c in frame.columns}
    res = rfeid.identify(rfeid.Model.load(knee_column), mapping, plan=40, weights="equal", window=0,
                         set={"a_n4": 6.6e15}, threads=1)
    assert "a_n4" not in res.estimates
    assert close(list(res.estimates.values()), [p["estimate"] for p in cli["parameters"]])
    assert res.document["source"]["set"] == ["a_n4=6600000000000000.0"]


def test_the_jacobian_by_blocks_as_on_the_command_line(tmp_path, rfeid_cli, knee_column):
    """`jacobian_memory=0` takes every Jacobian by blocks, as
    `--jacobian-memory 0` does (bit for bit), and lands where the whole
    Jacobian does (to rounding)."""
    data = measured(tmp_path, rfeid_cli, knee_column, seed=4)
    out = tmp_path / "result.json"
    rfeid_cli("identify", knee_column, "--data", data, "-o", out, "-q", "--plan", "20", "--jacobian-memory", "0")
    cli = json.loads(out.read_text())
    m = rfeid.Model.load(knee_column)
    blocks = rfeid.identify(m, str(data), plan=20, jacobian_memory=0)
    whole = rfeid.identify(m, str(data), plan=20)
    names = [p["name"] for p in cli["parameters"]]
    assert close([blocks.estimates[n] for n in names], [p["estimate"] for p in cli["parameters"]])
    assert close([blocks.std_errors[n] for n in names], [p["std_error"] for p in cli["parameters"]])
    for n in names:
        assert abs(blocks.estimates[n] - whole.estimates[n]) < 1e-6 * whole.std_errors[n]
        assert close(blocks.std_errors[n], whole.std_errors[n], rel=1e-8)


def test_data_lacking_a_sensor_names_the_column(tmp_path, rfeid_cli, knee_column):
    frame = read_csv_exact(measured(tmp_path, rfeid_cli, knee_column))
    with pytest.raises(rfeid.DataError) as e:
        rfeid.identify(rfeid.Model.load(knee_column), frame.drop(columns=["knee_ay"]))
    assert "knee_ay" in str(e.value)
    with pytest.raises(rfeid.DataError, match="time"):
        rfeid.identify(rfeid.Model.load(knee_column), frame.drop(columns=["time"]))
    with pytest.raises(rfeid.DataError, match="rate"):
        rfeid.identify(rfeid.Model.load(knee_column), frame.iloc[::2])
    bad = frame.copy()
    bad.loc[5, "knee_az"] = np.nan
    with pytest.raises(rfeid.DataError, match="knee_az"):
        rfeid.identify(rfeid.Model.load(knee_column), bad)
    twice = pd.concat([frame, frame[["knee_ax"]]], axis=1)
    with pytest.raises(rfeid.DataError, match="'knee_ax' appears twice"):
        rfeid.identify(rfeid.Model.load(knee_column), twice)
    text = frame.astype({"knee_ay": object})
    text.loc[3, "knee_ay"] = "x"
    with pytest.raises(rfeid.DataError, match="column 'knee_ay' is not numeric"):
        rfeid.identify(rfeid.Model.load(knee_column), text)
    with pytest.raises(rfeid.DataError, match="knee_az"):
        rfeid.identify(rfeid.Model.load(knee_column), {"time": frame["time"], "knee_ax": frame["knee_ax"],
                                                        "knee_ay": frame["knee_ay"], "knee_az": frame["knee_az"][:10]})


def test_bad_options_are_value_errors(tmp_path, rfeid_cli, knee_column):
    data = str(measured(tmp_path, rfeid_cli, knee_column))
    m = rfeid.Model.load(knee_column)
    for kwargs, text in [
        ({"plan": 0}, "plan=0: must be 1 to 1000000"),
        ({"starts": 5, "plan": 2}, "starts=5"),
        ({"window": 1.5}, "window=1.5"),
        ({"method": "newton"}, "method='newton': must be one of lm, bfgs"),
        ({"from_": 1e9}, "from_=1000000000"),
        ({"start": "values", "starts": 2}, "starts=2 with a start from the values"),
    ]:
        with pytest.raises(ValueError) as e:
            rfeid.identify(m, data, **kwargs)
        assert text in str(e.value)
    with pytest.raises(rfeid.ModelError, match="unknown parameter"):
        rfeid.identify(m, data, set={"x": 1})
    with pytest.raises(rfeid.DataError, match="no-such.csv"):
        rfeid.identify(m, str(tmp_path / "no-such.csv"))
    with pytest.raises(TypeError):
        rfeid.identify(m, 42)


def campaign_copy(tmp_path, rfeid_cli, validation=False):
    """The knee-column campaign copied into tmp_path with its three tests
    simulated (2 % noise, seeded); with `validation` the third is left out
    of the fit."""
    import shutil
    model = tmp_path / "model.toml"
    text = (EXAMPLES / "knee-column-campaign" / "model.toml").read_text()
    if validation:
        text = text.replace('name = "high"\n', 'name = "high"\nuse = "validation"\n')
    model.write_text(text)
    for n, e in enumerate(["low", "mid", "high"]):
        rfeid_cli("simulate", model, "--experiment", e, "-o", tmp_path / f"{e}.csv",
                  "--noise", "0.02", "--seed", 10 + n, "-q")
    return model


def test_a_campaign_equals_the_command_line(tmp_path, rfeid_cli):
    model = campaign_copy(tmp_path, rfeid_cli, validation=True)
    out = tmp_path / "result.json"
    rfeid_cli("identify", model, "-o", out, "-q", "--plan", "16")
    cli = json.loads(out.read_text())
    m = rfeid.Model.load(model)
    assert [(e.name, e.role) for e in m.experiments] == [("low", "fit"), ("mid", "fit"), ("high", "validation")]
    res = rfeid.identify(m, plan=16)
    doc = json.loads(res.to_json())
    for d in (doc, cli):
        d.pop("timings")
    assert doc == cli
    assert [e["role"] for e in res.experiments] == ["fit", "fit", "validation"]
    # One experiment's data as a DataFrame in place of its file: the same numbers.
    frames = rfeid.identify(m, {"mid": read_csv_exact(tmp_path / "mid.csv")}, plan=16)
    assert frames.estimates == res.estimates
    assert frames.experiments[1]["data"] == "data['mid']"
    path = frames.report(tmp_path / "report")
    assert path.endswith("report.html")
    # validate equals the command line's --json, from the object and from the file.
    cli_fits = json.loads(rfeid_cli("validate", model, out, "--json").stdout)
    assert rfeid.validate(m, res) == cli_fits
    assert rfeid.validate(m, out) == cli_fits
    one = json.loads(rfeid_cli("validate", model, out, "--experiment", "high", "--from", "0.1", "--json").stdout)
    assert rfeid.validate(m, out, experiment="high", from_=0.1) == one
    # RESULT.json read back with the files it names: the same document, a report.
    loaded = rfeid.Identification.load(out)
    assert json.loads(loaded.to_json()) == json.loads(out.read_text())
    assert loaded.report(tmp_path / "again").endswith("report.html")


def test_validate_and_load_of_one_record(tmp_path, rfeid_cli, knee_column):
    data = measured(tmp_path, rfeid_cli, knee_column, seed=4)
    other = tmp_path / "other.csv"
    rfeid_cli("simulate", knee_column, "-o", other, "--noise", "0.02", "--seed", 5, "-q")
    out = tmp_path / "result.json"
    rfeid_cli("identify", knee_column, "--data", data, "-o", out, "-q", "--plan", "20")
    cli = json.loads(rfeid_cli("validate", knee_column, out, "--data", other, "--json").stdout)
    m = rfeid.Model.load(knee_column)
    assert rfeid.validate(m, out, str(other)) == cli
    assert rfeid.validate(m, out, read_csv_exact(other)) == cli
    with pytest.raises(ValueError, match="from_=-1"):
        rfeid.validate(m, out, str(other), from_=-1.0)
    with pytest.raises(ValueError, match="lists no experiments"):
        rfeid.validate(m, out)
    loaded = rfeid.Identification.load(out)
    assert loaded.estimates == {p["name"]: p["estimate"] for p in json.loads(out.read_text())["parameters"]}
    # A result of another model is refused naming the parameter.
    lathe = rfeid.Model.load(EXAMPLES / "lathe" / "model.toml")
    with pytest.raises(rfeid.ModelError, match="not a parameter"):
        rfeid.validate(lathe, out, str(other))
    # A data file changed since: a warning.
    data.write_text(data.read_text().replace("0.0", "0.00", 1))
    with pytest.warns(UserWarning, match="not what the result was computed with"):
        rfeid.Identification.load(out)


def test_campaign_mistakes_are_named(tmp_path, rfeid_cli):
    model = campaign_copy(tmp_path, rfeid_cli)
    m = rfeid.Model.load(model)
    with pytest.raises(rfeid.DataError, match='experiment "nope"'):
        rfeid.identify(m, {"nope": str(tmp_path / "low.csv")}, plan=4)
    with pytest.raises(TypeError, match="campaign"):
        rfeid.identify(m, read_csv_exact(tmp_path / "low.csv"), plan=4)
    with pytest.raises(ValueError, match="window=0.2"):
        rfeid.identify(m, plan=4, window=0.2)
    with pytest.raises(rfeid.DataError, match="data\\['low'\\]"):
        rfeid.identify(m, {"low": {"time": [0.0, 0.001]}}, plan=4)
    with pytest.raises(TypeError, match="needed"):
        rfeid.identify(rfeid.Model.load(EXAMPLES / "knee-column" / "model.toml"))


def test_report_repr_and_progress(tmp_path, rfeid_cli, knee_column, capsys):
    data = str(measured(tmp_path, rfeid_cli, knee_column))
    res = rfeid.identify(rfeid.Model.load(knee_column), data, plan=3000, progress=True)
    assert "LP_τ plan" in capsys.readouterr().err
    path = res.report(tmp_path / "report")
    assert os.path.exists(path) and path.endswith("report.html")
    assert any(f.endswith(".svg") for f in os.listdir(tmp_path / "report"))
    assert "a_n1" in repr(res) and "verdict" in repr(res)
    assert "<table>" in res._repr_html_()


def test_ctrl_c_stops_an_identification_within_a_second(tmp_path, rfeid_cli, knee_column):
    data = str(measured(tmp_path, rfeid_cli, knee_column))
    m = rfeid.Model.load(knee_column)
    took = seconds_to_stop(lambda: rfeid.identify(m, data, plan=200_000))
    print(f"stopped {took:.3f} s after SIGINT")
    assert took < 1.0
    # The module still works afterwards.
    assert rfeid.identify(m, data, plan=10).estimates


def test_profiles_equal_the_command_lines(tmp_path, rfeid_cli, knee_column):
    data = measured(tmp_path, rfeid_cli, knee_column, seed=3)
    out = tmp_path / "result.json"
    rfeid_cli("identify", knee_column, "--data", data, "-o", out, "-q", "--start", "values",
              "--profiles=h_t3,a_n4", "--profile-points", "6")
    cli = json.loads(out.read_text())
    m = rfeid.Model.load(knee_column)
    res = rfeid.identify(m, str(data), start="values", profiles=["h_t3", "a_n4"], profile_points=6)
    assert res.document["profiles"] == cli["profiles"]
    profiles = res.profiles
    assert list(profiles) == ["a_n4", "h_t3"], "in the parameters' order"
    p = profiles["h_t3"]
    assert p["values"].shape == (7,) and np.all(np.diff(p["values"]) > 0)
    assert p["parameters"].shape == (7, len(res.parameter_names))
    assert np.nanmin(p["statistic"]) == 0.0
    lo, hi = p["interval"]
    assert lo < p["estimate"] < hi
    assert p["threshold"] == pytest.approx(3.841458820694124)
    assert rfeid.identify(m, str(data), start="values").profiles == {}
    with pytest.raises(ValueError, match="'k9'"):
        rfeid.identify(m, str(data), start="values", profiles=["k9"])


def test_shards_from_python_and_the_command_line_merge_either_way(tmp_path, rfeid_cli, knee_column):
    data = measured(tmp_path, rfeid_cli, knee_column, seed=6)
    one = tmp_path / "one.json"
    rfeid_cli("identify", knee_column, "--data", data, "-o", one, "-q", "--plan", "12")

    def comparable(doc):
        doc = dict(doc)
        doc.pop("timings"), doc.pop("threads")
        return doc

    single = comparable(json.loads(one.read_text()))
    m = rfeid.Model.load(knee_column)
    # Three shards from Python, merged by the command line.
    py_shards = [rfeid.identify(m, str(data), plan=12, shard=(k, 3), output=tmp_path / f"py{k}.json")
                 for k in range(3)]
    merged = tmp_path / "merged.json"
    rfeid_cli("merge", *py_shards, "-o", merged, "-q")
    assert comparable(json.loads(merged.read_text())) == single
    # Three shards from the command line, merged by Python.
    cli_shards = []
    for k in range(3):
        path = tmp_path / f"cli{k}.json"
        rfeid_cli("identify", knee_column, "--data", data, "-o", path, "-q", "--plan", "12", "--shard", f"{k}/3")
        cli_shards.append(path)
        assert json.loads(path.read_text())["points"] == json.loads(open(py_shards[k]).read())["points"]
    res = rfeid.merge(cli_shards)
    assert comparable(json.loads(res.to_json())) == single
    # Mistakes: a shard missing, a shard twice, a shard of a data frame.
    with pytest.raises(rfeid.DataError, match="missing"):
        rfeid.merge(cli_shards[:2])
    with pytest.raises(rfeid.DataError, match="twice"):
        rfeid.merge([cli_shards[0], cli_shards[0], cli_shards[1]])
    with pytest.raises(TypeError, match="data file"):
        rfeid.identify(m, read_csv_exact(data), plan=12, shard=(0, 3), output=tmp_path / "x.json")
    with pytest.raises(ValueError, match="shard=\\(3, 3\\)"):
        rfeid.identify(m, str(data), plan=12, shard=(3, 3), output=tmp_path / "x.json")
    assert not (tmp_path / "x.json").exists()


def test_verdict_reasons_and_warnings_are_tagged(knee_column):
    """A reason is its words (a str) with its kind and values, as
    RESULT.json tags it: here a slideway stiffer than its box allows."""
    m = rfeid.Model.load(knee_column)
    with pytest.warns(UserWarning, match="outside its box"):
        sim = m.simulate(set={"a_n1": "700 daN/um^2"}, noise=0.02, seed=1)
    res = rfeid.identify(m, sim.to_pandas(), plan=8)
    doc = res.document["verdict"]["reasons"]
    assert not res.verdict.trustworthy and doc
    for reason, tagged in zip(res.verdict.reasons, doc):
        assert isinstance(reason, str) and reason.kind == tagged["kind"] and reason.message == tagged["message"]
    at_bound = [r for r in res.verdict.reasons if r.kind == "at_bound"]
    assert at_bound and at_bound[0].parameter == "a_n1" and at_bound[0].fields["side"] == "upper"
    assert all(isinstance(w, rfeid.Reason) and w.kind for w in res.warnings)


def test_option_defaults_are_the_librarys_in_one_place(rfeid_cli):
    """Each option's default is defined once, in the library
    (identification::options::defaults): the keyword defaults are read
    from it, and the command line's --help shows the same."""
    import inspect

    defaults = rfeid._rfeid.search_defaults()
    sig = inspect.signature(rfeid.identify).parameters
    for keyword, name in [("plan", "plan"), ("starts", "starts"), ("method", "method"),
                          ("noise_model", "noise_model"), ("from_", "from"), ("profile_points", "profile_points")]:
        assert sig[keyword].default == defaults[name], keyword
    help_text = rfeid_cli("identify", "--help").stdout
    for flag, name in [("--plan", "plan"), ("--starts", "starts"), ("--method", "method"),
                       ("--noise-model", "noise_model"), ("--from", "from")]:
        value = defaults[name]
        expected = f"{value:g}" if isinstance(value, float) else str(value)
        shown = re.search(r"^ +" + re.escape(flag) + r" [^\[]*\[default: ([^\]]+)\]", help_text, re.M)
        assert shown and shown.group(1) == expected, (flag, shown and shown.group(1), expected)
    # The package writes no default of its own: each is _DEFAULTS[...].
    source = inspect.getsource(rfeid.identify)
    assert "plan: int = _DEFAULTS" in source and "= 100" not in source
    # An option's error names the option as a keyword here, as a flag there.
    with pytest.raises(ValueError, match=r"^profile_points=1: must be 2 to 1000"):
        rfeid.identify(rfeid.Model.load(EXAMPLES / "knee-column" / "model.toml"), {"time": [0.0]}, profiles=True,
                       profile_points=1)
