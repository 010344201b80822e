"""Figures (rfeid.plot) and what they draw: the signals at the estimate,
the Welch spectra, the report's SVGs without matplotlib, the message when
the extra is missing, and the plan's bar with tqdm. Small plans: a few
seconds in all."""
import sys
import types

import numpy as np
import pytest

import rfeid
from rfeid import plot
from conftest import EXAMPLES


@pytest.fixture(scope="module")
def knee():
    """(model, simulated record, identification) of the knee-column."""
    m = rfeid.Model.load(EXAMPLES / "knee-column" / "model.toml")
    sim = m.simulate(noise=0.02, seed=1)
    return m, sim, rfeid.identify(m, sim.to_dict(), plan=8)


@pytest.fixture(scope="module")
def design(knee):
    return rfeid.design(knee[0], choose=3)


@pytest.fixture()
def no_matplotlib(monkeypatch):
    """matplotlib as if it were not installed."""
    for name in [n for n in sys.modules if n == "matplotlib" or n.startswith("matplotlib.")]:
        monkeypatch.setitem(sys.modules, name, None)
    monkeypatch.setitem(sys.modules, "matplotlib", None)


def test_signals_are_the_data_and_the_model_at_the_estimate(knee):
    m, sim, res = knee
    s = res.signals()
    assert s.experiment == "" and s.names == m.sensors and s.units == m.sensor_units
    assert s.sample_rate == m.sample_rate and s.from_ == 0.0 and s.first_fitted == 0
    assert np.array_equal(s.time, sim.time)
    assert np.array_equal(s.measured, sim.values)  # the data fitted, bit for bit
    # The model at the estimate with the steps the identification ended
    # with (the report's simulation): simulate gives the same numbers.
    steps = res.document["simulation"]["substeps"]
    assert np.array_equal(s.fitted, m.simulate(set=res.estimates, substeps=steps).values)
    # What is left is the 2 % noise.
    ratio = s.residual.std(axis=0) / s.measured.std(axis=0)
    assert np.all((ratio > 0.015) & (ratio < 0.03)), ratio
    frame = s.to_pandas()
    assert frame.shape == (len(s.time), 3 * len(s.names)) and frame.index.name == "time"
    assert np.array_equal(frame["residual"][s.names[0]].to_numpy(), s.residual[:, 0])
    assert res.signals() is s  # simulated once
    with pytest.raises(KeyError, match="fitted"):
        res.signals("low")


def test_first_fitted_sample_from_the_start_time():
    n = 100
    s = rfeid.Signals("", np.arange(n) / 1000.0, ["a"], ["m"], np.zeros((n, 1)), np.zeros((n, 1)), 1000.0, 0.013)
    assert s.first_fitted == 13


def test_welch_is_a_density_whose_integral_is_the_variance():
    rng = np.random.default_rng(3)
    fs, sigma = 2000.0, 0.5
    x = sigma * rng.standard_normal(8192) + 3.0
    f, p = plot.welch(x, fs)
    assert plot.welch_segment(len(x)) == 2048 and len(f) == 1025
    assert f[0] == 0.0 and f[-1] == fs / 2
    variance = np.sum(p) * (f[1] - f[0])
    assert abs(variance / sigma**2 - 1) < 0.05  # white: flat at 2 sigma^2 / fs
    assert abs(np.median(p[1:-1]) * fs / (2 * sigma**2) - 1) < 0.1
    t = np.arange(4096) / fs
    f, p = plot.welch(np.sin(2 * np.pi * 250.0 * t), fs, segment=256)
    assert f[np.argmax(p)] == 250.0
    with pytest.raises(ValueError, match="segment"):
        plot.welch(x[:100], fs, segment=200)


def test_plot_fit_has_an_axis_per_sensor(knee):
    Figure = pytest.importorskip("matplotlib.figure").Figure
    m, _, res = knee
    fig = res.plot_fit()
    assert isinstance(fig, Figure) and len(fig.axes) == len(m.sensors)
    assert [ax.get_ylabel() for ax in fig.axes] == [f"{n} ({u})" for n, u in zip(m.sensors, m.sensor_units)]
    assert fig.axes[-1].get_xlabel() == "time (s)"
    assert [line.get_label() for line in fig.axes[0].get_lines()] == ["measured", "model at the estimate"]
    assert any(t.get_text().startswith("fit 9") for t in fig.axes[0].texts)
    assert fig._repr_png_()[:8] == b"\x89PNG\r\n\x1a\n"  # Jupyter shows it without pyplot


def test_plot_residual_spectra_on_log_axes(knee):
    pytest.importorskip("matplotlib")
    m, _, res = knee
    fig = res.plot_residual_spectra(segment=256)
    assert len(fig.axes) == len(m.sensors)
    assert all(ax.get_xscale() == "log" and ax.get_yscale() == "log" for ax in fig.axes)
    assert "256-sample segments" in fig.axes[-1].get_xlabel()
    assert "PSD" in fig.axes[0].get_ylabel() and "(m/s^2)²/Hz" in fig.axes[0].get_ylabel()
    assert [line.get_label() for line in fig.axes[0].get_lines()] == ["measured", "residual"]
    assert len(res.plot_residual_spectra(measured=False).axes[0].get_lines()) == 1


def test_plot_correlation_fixed_to_plus_minus_one(knee):
    pytest.importorskip("matplotlib")
    res = knee[2]
    r = len(res.parameter_names)
    fig = res.plot_correlation()
    assert len(fig.axes) == 2  # the matrix and its colour bar
    ax = fig.axes[0]
    assert ax.images[0].get_clim() == (-1.0, 1.0)
    assert [t.get_text() for t in ax.get_xticklabels()] == res.parameter_names
    assert len(ax.texts) == r * r  # 16 <= 20: annotated
    assert ax.texts[0].get_text() == "1.00"
    assert len(res.plot_correlation(annotate=False).axes[0].texts) == 0


def test_design_plot_placed_and_chosen(design):
    pytest.importorskip("matplotlib")
    fig = design.plot()
    assert len(fig.axes) == 1
    ax = fig.axes[0]
    assert ax.get_xscale() == "log" and "%" in ax.get_xlabel()
    names = [p["name"] for p in design.document["parameters"]]
    assert [t.get_text() for t in ax.get_yticklabels()] == names
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels == ["placed sensors", "with " + ", ".join(design.chosen)]
    # An undefined standard error (None) is marked, not drawn.
    doc = {k: v for k, v in design.document.items()}
    doc["placed"] = dict(doc["placed"], parameters=[dict(p) for p in doc["placed"]["parameters"]])
    doc["placed"]["parameters"][0].update(std_error=None, relative_std_error=None)
    stub = types.SimpleNamespace(document=doc, chosen=[])
    ax = plot.plot_design(stub).axes[0]
    assert [t.get_text().strip() for t in ax.texts] == ["undefined"]
    assert len(ax.get_legend().get_texts()) == 1


def test_a_missing_extra_is_named(knee, design, no_matplotlib):
    res = knee[2]
    for call in [res.plot_fit, res.plot_residual_spectra, res.plot_correlation, design.plot]:
        with pytest.raises(ImportError, match=r'rfeid\[plot\]') as e:
            call()
        assert "./python[plot]" in str(e.value)


def test_figures_are_the_reports_svgs(knee, monkeypatch):
    res = knee[2]
    figures = res.figures
    assert "correlation.svg" in figures and all(n.endswith(".svg") for n in figures)
    text = lambda f: getattr(f, "data", f)  # noqa: E731  (an IPython SVG, or the text)
    assert all("<svg" in text(f) for f in figures.values())
    monkeypatch.setitem(sys.modules, "IPython", None)
    monkeypatch.setitem(sys.modules, "IPython.display", None)
    plain = res.figures
    assert all(isinstance(f, str) and "<svg" in f for f in plain.values())
    assert plain.keys() == figures.keys()


def test_a_campaign_draws_each_fitted_experiment(tmp_path, rfeid_cli):
    text = (EXAMPLES / "knee-column-campaign" / "model.toml").read_text()
    text = text.replace('duration = "0.3 s"', 'duration = "0.05 s"', 1)  # 500 samples: quick
    text = text.replace('name = "mid"\n', 'name = "mid"\nfrom = "0.01 s"\n')
    text = text.replace('name = "high"\n', 'name = "high"\nuse = "validation"\n')
    model = tmp_path / "model.toml"
    model.write_text(text)
    for n, e in enumerate(["low", "mid", "high"]):
        rfeid_cli("simulate", model, "--experiment", e, "-o", tmp_path / f"{e}.csv", "--noise", "0.02", "--seed", 10 + n, "-q")
    res = rfeid.identify(rfeid.Model.load(model), plan=4, start="values")
    low, mid = res.signals(), res.signals("mid")
    assert (low.experiment, low.from_, low.first_fitted) == ("low", 0.0, 0)
    assert (mid.experiment, mid.from_, mid.first_fitted) == ("mid", 0.01, 100)
    assert len(low.time) == 500 and low.measured.shape == (500, 3)
    with pytest.raises(KeyError, match="high"):  # validation: not fitted
        res.signals("high")
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        return
    fig = res.plot_fit()  # a column per fitted experiment
    titles = [ax.get_title() for ax in fig.axes if ax.get_title()]
    assert len(fig.axes) == 6 and titles == ["experiment low", "experiment mid"]
    assert len(res.plot_residual_spectra(experiment="mid").axes) == 3


def test_the_plans_bar_is_tqdms_where_installed(monkeypatch):
    bars = []

    class FakeTqdm:
        def __init__(self, total, desc, unit):
            self.total, self.desc, self.n, self.closed = total, desc, 0, False
            bars.append(self)

        def update(self, k):
            self.n += k

        def close(self):
            self.closed = True

    auto = types.ModuleType("tqdm.auto")
    auto.tqdm = FakeTqdm
    monkeypatch.setitem(sys.modules, "tqdm", types.ModuleType("tqdm"))
    monkeypatch.setitem(sys.modules, "tqdm.auto", auto)
    bar = rfeid._Bar()
    for done in (1, 5, 8):
        bar(done, 8, 0, 0, 0, 0.0)
    assert len(bars) == 1 and (bars[0].desc, bars[0].total, bars[0].n) == ("LP_τ plan", 8, 8)
    bar.close()
    assert bars[0].closed
