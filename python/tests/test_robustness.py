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
