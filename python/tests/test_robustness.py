"""No input crashes the interpreter: seeded random model texts and data
tables give a result or the module's exceptions; long calls release the
GIL; nothing is printed unless asked; the README's example runs as written."""
import os
import pathlib
import random
import re
import threading
import time

import numpy as np
import pandas as pd
import pytest

import rfeid
from conftest import EXAMPLES, ROOT


def mutations(text, rng, n):
    """`n` seeded mutations of `text`: a line dropped, doubled or cut, a
    number replaced by an odd one, a character inserted."""
    lines = text.splitlines()
    odd = ["0", "-1", "1e308", "nan", "inf", "\"\"", "[]", "\"1 kg\"", "1e-320", "{}"]
    for _ in range(n):
        ls = list(lines)
        for _ in range(rng.randint(1, 3)):
            i = rng.randrange(len(ls))
            kind = rng.randrange(5)
            if kind == 0:
                del ls[i]
            elif kind == 1:
                ls.insert(i, ls[i])
            elif kind == 2:
                ls[i] = ls[i][: rng.randrange(len(ls[i]) + 1)]
            elif kind == 3:
                ls[i] = re.sub(r"-?\d+(\.\d+)?(e-?\d+)?", rng.choice(odd), ls[i], count=1)
            else:
                j = rng.randrange(len(ls[i]) + 1)
                ls[i] = ls[i][:j] + rng.choice("[]{}=\"#,\x00é") + ls[i][j:]
        yield "\n".join(ls)


def test_mutated_model_files_raise_model_errors_or_load():
    rng = random.Random(11)
    text = (EXAMPLES / "knee-column" / "model.toml").read_text()
    loaded = refused = 0
    for t in mutations(text, rng, 300):
        try:
            m = rfeid.Model.from_toml(t, base_dir=EXAMPLES / "knee-column")
        except rfeid.ModelError as e:
            assert str(e)
            refused += 1
        else:
            loaded += 1
            m.parameters, m.sensors
    assert refused > 50 and loaded > 10, (refused, loaded)


def test_bad_tables_raise_data_errors():
    m = rfeid.Model.load(EXAMPLES / "knee-column" / "model.toml")
    sim = m.simulate(noise=0.02, seed=1)
    rng = np.random.default_rng(5)
    n = len(sim.time)
    cases = [
        {"time": [], "knee_ax": [], "knee_ay": [], "knee_az": []},
        {"time": [0.0], "knee_ax": [1.0], "knee_ay": [1.0], "knee_az": [1.0]},
        {"time": sim.time[::-1], **{k: sim.values[:, i] for i, k in enumerate(sim.names)}},
        {"time": sim.time, **{k: np.full(n, np.inf) for k in sim.names}},
        {"time": np.zeros(n), **{k: sim.values[:, i] for i, k in enumerate(sim.names)}},
        {"time": sim.time, **{k: rng.normal(size=n) * 1e200 for k in sim.names}},
        {"time": sim.time, **{k: np.zeros(n) for k in sim.names}},
        {"time": sim.time * 3, **{k: sim.values[:, i] for i, k in enumerate(sim.names)}},
    ]
    for case in cases:
        with pytest.raises(rfeid.DataError):
            rfeid.identify(m, case, plan=2)


def test_identify_releases_the_gil_and_prints_nothing_unless_asked(capfd):
    m = rfeid.Model.load(EXAMPLES / "knee-column" / "model.toml")
    data = m.simulate(noise=0.02, seed=1).to_dict()
    done = []
    worker = threading.Thread(target=lambda: done.append(rfeid.identify(m, data, plan=400)))
    worker.start()
    spins = 0
    t = time.monotonic()
    while time.monotonic() - t < 0.3:
        spins += 1
    worker.join()
    assert done and spins > 10_000, spins
    out, err = capfd.readouterr()
    assert out == "" and err == ""


def test_the_readmes_example_runs_as_written(tmp_path, monkeypatch):
    text = (ROOT / "README.md").read_text()
    section = text[text.index("## Python"):]
    block = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    (tmp_path / "examples").symlink_to(EXAMPLES)
    monkeypatch.chdir(tmp_path)
    exec(compile(block, "README.md", "exec"), {})
    assert (tmp_path / "out" / "report.html").exists()


def test_options_of_the_wrong_type_are_refused_naming_the_keyword():
    """Outside test 2026-11-27, W5: no value is truncated or converted."""
    m = rfeid.Model.load(EXAMPLES / "knee-column" / "model.toml")
    data = {"time": np.zeros(3)}
    for call, keyword in [
        (lambda: m.simulate(noise=0.02, seed=3.7), "seed"),
        (lambda: m.simulate(noise=0.02, seed="3"), "seed"),
        (lambda: m.simulate(noise=True), "noise"),
        (lambda: rfeid.identify(m, data, plan=True), "plan"),
        (lambda: rfeid.identify(m, data, from_="0.1"), "from_"),
        (lambda: rfeid.design(m, choose=True), "choose"),
        (lambda: rfeid.design(m, threads=2.0), "threads"),
    ]:
        with pytest.raises(TypeError, match=f"^{keyword}="):
            call()
    with pytest.raises(ValueError, match="^threads=0"):
        rfeid.design(m, threads=0)


def test_boolean_and_complex_columns_are_refused_naming_the_column():
    """Outside test 2026-11-27, W7: a signal is real numbers."""
    pd = pytest.importorskip("pandas")
    m = rfeid.Model.load(EXAMPLES / "knee-column" / "model.toml")
    frame = pd.DataFrame({"time": [0.0, 1e-3], "knee_ax": [0.5, -0.5]})
    for bad in [frame.knee_ax + 1j, frame.knee_ax > 0, (frame.knee_ax > 0).astype("boolean")]:
        with pytest.raises(rfeid.DataError, match="column 'knee_ax' is (boolean|complex)"):
            rfeid.identify(m, frame.assign(knee_ax=bad), plan=1, threads=1)


def test_reports_follow_the_command_lines_output_rules(tmp_path, monkeypatch):
    """Outside test 2026-11-27, W2: `report(dir)` replaces an earlier report
    as a whole and refuses a directory holding anything else."""
    import shutil

    shutil.copy(EXAMPLES / "knee-column" / "model.toml", tmp_path / "kc.toml")
    m = rfeid.Model.load(tmp_path / "kc.toml")
    d = rfeid.design(m, threads=1)
    rep = tmp_path / "rep"
    rep.mkdir()
    (rep / "stale-figure.svg").write_text("<svg/>")
    assert d.report(rep) == str(rep / "report.html")
    assert not (rep / "stale-figure.svg").exists()
    monkeypatch.chdir(tmp_path)
    for where in [".", tmp_path]:
        with pytest.raises(ValueError, match="holds .* not part of an rfeid report"):
            d.report(where)
    assert not (tmp_path / "report.html").exists()
    (rep / "notes.txt").write_text("mine")
    with pytest.raises(ValueError, match="notes.txt"):
        d.report(rep)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["kc.toml", "rep"]


def test_reading_notes_are_warnings_and_time_must_be_seconds(knee_column):
    """U1: a note of the reading (a record shifted, a column read by no
    sensor) is a UserWarning; U9: timedelta or datetime time is refused."""
    m = rfeid.Model.load(knee_column)
    df = m.simulate(noise=0.02, seed=1).to_pandas()
    with pytest.warns(UserWarning, match="taken as starting"):
        res = rfeid.identify(m, df.assign(time=df.time + 5.0), plan=4)
    assert any("taken as starting" in n for n in res.notes)
    with pytest.warns(UserWarning, match="extra"):
        rfeid.identify(m, df.assign(extra=1.0), plan=4)
    with pytest.raises(rfeid.DataError, match="total_seconds"):
        rfeid.identify(m, df.assign(time=pd.to_timedelta(df.time, unit="s")), plan=4)
    with pytest.raises(rfeid.DataError, match="datetime"):
        rfeid.identify(m, df.assign(time=pd.Timestamp("2026-01-01") + pd.to_timedelta(df.time, unit="s")), plan=4)


def test_pickling_a_model_reads_it_again_and_results_say_what_to_pass(knee_column):
    """U14: a Model pickles as its file or text; a result or design says
    to pass its JSON."""
    import pickle

    m = rfeid.Model.load(knee_column)
    again = pickle.loads(pickle.dumps(m))
    assert again.path == m.path and [p.name for p in again.parameters] == [p.name for p in m.parameters]
    text = rfeid.Model.from_toml(open(knee_column).read(), base_dir=os.path.dirname(knee_column))
    assert pickle.loads(pickle.dumps(text)).sensors == m.sensors
    res = rfeid.identify(m, m.simulate(noise=0.02, seed=1).to_pandas(), plan=4)
    with pytest.raises(TypeError, match="to_json"):
        pickle.dumps(res)
    with pytest.raises(TypeError, match="to_json"):
        pickle.dumps(rfeid.design(m))


def test_a_campaign_experiment_is_simulated_by_name():
    """R3: Model.simulate(experiment=...) is `simulate --experiment`."""
    camp = rfeid.Model.load(EXAMPLES / "knee-column-campaign" / "model.toml")
    low, high = camp.simulate(experiment="low"), camp.simulate(experiment="high")
    assert low.values.shape == high.values.shape and not np.array_equal(low.values, high.values)
    with pytest.raises(ValueError, match="experiments: low, mid, high"):
        camp.simulate(experiment="nope")


def test_a_cancel_event_stops_a_run_in_another_thread(knee_column):
    """R5: identify(cancel=event) in a worker thread stops when the event is set."""
    import threading
    import time

    m = rfeid.Model.load(knee_column)
    df = m.simulate(noise=0.02, seed=1).to_pandas()
    event, out = threading.Event(), {}

    def run():
        try:
            rfeid.identify(m, df, plan=200_000, cancel=event)
        except rfeid.Cancelled as e:
            out["stopped"] = time.monotonic()
            out["error"] = e

    worker = threading.Thread(target=run)
    worker.start()
    time.sleep(0.5)
    event.set()
    set_at = time.monotonic()
    worker.join(timeout=10)
    assert not worker.is_alive() and "error" in out
    assert out["stopped"] - set_at < 1.0
    with pytest.raises(TypeError, match="threading.Event"):
        rfeid.identify(m, df, plan=4, cancel=True)


def test_setting_errors_name_the_keywords(knee_column):
    """R2: a bad set, tolerance or substeps is a ModelError spelt with the
    keywords, not the command line's flags."""
    m = rfeid.Model.load(knee_column)
    for kwargs, text in [({"set": {"a_n9": 1.0}}, r"^set: unknown parameter 'a_n9'"),
                         ({"tolerance": 0.0}, r"^tolerance=0e0: "),
                         ({"substeps": 0}, r"^substeps=0: ")]:
        with pytest.raises(rfeid.ModelError, match=text):
            m.simulate(**kwargs)
    with pytest.warns(UserWarning, match=r"^set a_n1: the value lies outside its box"):
        m.simulate(set={"a_n1": "700 daN/um^2"}, substeps=1)
