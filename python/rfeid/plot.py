"""Figures of rfeid's results with matplotlib, for notebooks and scripts.

Each function takes a result and returns a :class:`matplotlib.figure.Figure`
made without pyplot (no global state, no GUI: it works headless, on the Agg
backend, and Jupyter shows it as a cell's value). The methods
:meth:`rfeid.Identification.plot_fit`,
:meth:`~rfeid.Identification.plot_residual_spectra`,
:meth:`~rfeid.Identification.plot_correlation` and
:meth:`rfeid.Design.plot` call them.

matplotlib is an optional extra: ``pip install "rfeid[plot]"`` (from a
checkout: ``pip install "./python[plot]"``). Without it these functions
raise ``ImportError`` saying so; :attr:`rfeid.Identification.figures` gives
the report's SVG figures instead, with no extra needed.

Units: time in s, frequencies in Hz, signals in each sensor's SI unit (m,
m/s or m/s^2), power spectral densities in unit^2/Hz, standard errors in %
of the value.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, List, Optional, Tuple

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

    from . import Design, Identification, Signals

__all__ = ["plot_fit", "plot_residual_spectra", "plot_correlation", "plot_design", "welch", "welch_segment"]

MISSING = (
    "rfeid's plots need matplotlib, an optional extra: pip install \"rfeid[plot]\" "
    "(from a checkout of rfeid: pip install \"./python[plot]\"), or pip install matplotlib; "
    "without it, Identification.figures gives the report's SVG figures"
)

# Correlation matrices up to this many parameters have their values written in.
ANNOTATE_UP_TO = 20


_FIGURE: Any = None


def _figure(**kwargs: Any) -> "Figure":
    """A new matplotlib Figure (no pyplot), or ImportError naming the extra.

    It is a ``matplotlib.figure.Figure`` with a ``_repr_png_``, so that
    Jupyter shows it as a cell's value even where pyplot was never imported
    (without pyplot's inline backend, IPython knows no way to draw a bare
    Figure and prints ``<Figure size ...>``); where the inline backend is
    active, its own formatter draws it instead, once.
    """
    global _FIGURE
    try:
        import matplotlib  # noqa: F401  (None in sys.modules must fail here)
        from matplotlib.figure import Figure
    except ImportError as e:
        raise ImportError(MISSING) from e
    if _FIGURE is None:

        class _Shown(Figure):
            """A matplotlib Figure that Jupyter shows as PNG."""

            def _repr_png_(self) -> bytes:
                import io

                buf = io.BytesIO()
                self.savefig(buf, format="png")
                return buf.getvalue()

        _FIGURE = _Shown
    return _FIGURE(**kwargs)


def _records(res: "Identification", experiment: Optional[str]) -> List["Signals"]:
    """The fitted records to draw: ``experiment``'s, or every one's."""
    if experiment is not None:
        return [res.signals(experiment)]
    return res._all_signals()


def _grid(fig: "Figure", records: List["Signals"], sharex: bool) -> List[List[Any]]:
    """One column of axes per record, one row per sensor; the axes a
    record with fewer sensors does not use are removed. Returns the axes
    as ``axes[column][sensor]``."""
    rows = max(len(r.names) for r in records)
    grid = fig.subplots(rows, len(records), sharex="col" if sharex else False, squeeze=False)
    out = []
    for j, r in enumerate(records):
        for i in range(len(r.names), rows):
            fig.delaxes(grid[i][j])
        out.append([grid[i][j] for i in range(len(r.names))])
    return out


def _size(figsize: Optional[Tuple[float, float]], records: List["Signals"]) -> Tuple[float, float]:
    rows = max(len(r.names) for r in records)
    return figsize or (min(6.4 * len(records), 16.0), 1.2 + 1.8 * rows)


def _fit_percent(y: np.ndarray, g: np.ndarray) -> Optional[float]:
    """Normalised RMS fit, %: 100 (1 - |y - g| / |y - mean y|); None for a
    constant y."""
    spread = np.linalg.norm(y - y.mean())
    return None if spread == 0 else 100.0 * (1.0 - np.linalg.norm(y - g) / spread)


def plot_fit(
    res: "Identification",
    *,
    experiment: Optional[str] = None,
    figsize: Optional[Tuple[float, float]] = None,
) -> "Figure":
    """Measured signals against the model simulated at the estimate.

    One axis per sensor (its SI unit, m, m/s or m/s^2, on the y axis; time
    in s on the x axis), the measured signal in grey and the model at the
    estimate in colour, with the fit over the fitted part in % (``100 (1 -
    |y - ŷ| / |y - mean y|)``, as RESULT.json's ``fit_percent``); the part
    before ``from`` (not fitted) is shaded. A campaign gets one column per
    fitted experiment (``experiment``: that one only). The simulation is
    the report's (:meth:`rfeid.Identification.signals`). ``figsize`` in
    inches. Returns a :class:`matplotlib.figure.Figure`.
    """
    fig = _figure(layout="constrained")
    records = _records(res, experiment)
    fig.set_size_inches(*_size(figsize, records))
    for r, axes in zip(records, _grid(fig, records, sharex=True)):
        first = r.first_fitted
        for i, ax in enumerate(axes):
            y, g = r.measured[:, i], r.fitted[:, i]
            ax.plot(r.time, y, color="0.7", lw=1.6, label="measured")
            ax.plot(r.time, g, color="C0", lw=0.6, label="model at the estimate")
            if first > 0:
                ax.axvspan(r.time[0], r.time[first], color="0.92", lw=0, label="not fitted")
            fit = _fit_percent(y[first:], g[first:])
            text = "fit -" if fit is None else f"fit {fit:.1f} %"
            ax.text(
                0.99, 0.03, text, transform=ax.transAxes, ha="right", va="bottom", fontsize="small",
                bbox={"facecolor": "white", "alpha": 0.8, "edgecolor": "none", "pad": 1.5},
            )
            ax.set_ylabel(f"{r.names[i]} ({r.units[i]})")
            ax.grid(True, lw=0.3)
        axes[-1].set_xlabel("time (s)")
        axes[0].set_title(f"experiment {r.experiment}" if r.experiment else "measured and fitted")
    fig.axes[0].legend(loc="upper right", fontsize="small")
    return fig


def welch_segment(n: int) -> int:
    """The default Welch segment for ``n`` samples: the largest power of
    two not above n/4 (so at least 7 half-overlapping segments), at least
    16 samples and at most ``n``."""
    if n < 2:
        raise ValueError(f"{n} samples: a spectrum needs at least 2")
    seg = 16
    while seg * 2 <= n // 4:
        seg *= 2
    return min(seg, n)


def welch(x: Any, sample_rate: float, segment: Optional[int] = None) -> Tuple[np.ndarray, np.ndarray]:
    """The one-sided power spectral density of ``x`` by Welch's method,
    with numpy only.

    Segments of ``segment`` samples (default :func:`welch_segment`: the
    largest power of two not above a quarter of the record) overlapping by
    half, each with its mean removed and a periodic Hann window. Returns
    (frequencies in Hz from 0 to ``sample_rate``/2, the density in x's
    unit^2/Hz), scaled so that its integral over frequency is x's variance.
    """
    x = np.asarray(x, dtype=float)
    n = len(x)
    seg = welch_segment(n) if segment is None else int(segment)
    if not 2 <= seg <= n:
        raise ValueError(f"segment={segment}: must be from 2 to the {n} samples")
    step = max(seg // 2, 1)
    starts = np.arange(0, n - seg + 1, step)
    parts = np.stack([x[s : s + seg] for s in starts])
    parts = parts - parts.mean(axis=1, keepdims=True)
    window = 0.5 - 0.5 * np.cos(2.0 * np.pi * np.arange(seg) / seg)
    spectra = np.abs(np.fft.rfft(parts * window, axis=1)) ** 2
    density = spectra.mean(axis=0) / (sample_rate * np.sum(window**2))
    # One-sided: every bin but 0 (and Nyquist, for an even segment) twice.
    density[1 : seg // 2 + (seg % 2)] *= 2.0
    return np.fft.rfftfreq(seg, 1.0 / sample_rate), density


def plot_residual_spectra(
    res: "Identification",
    *,
    segment: Optional[int] = None,
    experiment: Optional[str] = None,
    measured: bool = True,
    figsize: Optional[Tuple[float, float]] = None,
) -> "Figure":
    """The residuals' power spectral density, per sensor, on log axes.

    The residual is measured − model at the estimate, over the fitted part
    of the record only (from RESULT.json's ``from``, or each experiment's);
    its one-sided PSD by Welch's method (:func:`welch`: Hann window,
    ``segment`` samples per segment overlapping by half, default the
    largest power of two not above a quarter of the fitted samples), in
    (sensor's SI unit)^2/Hz against frequency in Hz. A residual that is
    noise is flat (white) or smooth; a peak at a mode is model error there.
    With ``measured`` the measured signal's PSD is drawn in grey to compare
    with. A campaign gets one column per fitted experiment (``experiment``:
    that one only). ``figsize`` in inches. Returns a
    :class:`matplotlib.figure.Figure`.
    """
    fig = _figure(layout="constrained")
    records = _records(res, experiment)
    fig.set_size_inches(*_size(figsize, records))
    for r, axes in zip(records, _grid(fig, records, sharex=True)):
        first = r.first_fitted
        rate = 1.0 / (r.time[1] - r.time[0]) if len(r.time) > 1 else 1.0
        for i, ax in enumerate(axes):
            y, g = r.measured[first:, i], r.fitted[first:, i]
            f, p = welch(y - g, rate, segment)
            if measured:
                _, q = welch(y, rate, segment)
                ax.loglog(f[1:], q[1:], color="0.65", lw=0.8, label="measured")
            ax.loglog(f[1:], p[1:], color="C3", lw=0.9, label="residual")
            ax.set_ylabel(f"{r.names[i]} PSD\n(({r.units[i]})²/Hz)")
            ax.grid(True, which="both", lw=0.3)
        seg = welch_segment(len(r.time) - first) if segment is None else segment
        axes[-1].set_xlabel(f"frequency (Hz); Welch, Hann, {seg}-sample segments")
        title = "residual spectra" + (f", experiment {r.experiment}" if r.experiment else "")
        axes[0].set_title(f"{title} (from {r.time[first]:.4g} s)")
    fig.axes[0].legend(loc="upper right", fontsize="small")
    return fig


def plot_correlation(
    res: "Identification",
    *,
    annotate: Optional[bool] = None,
    figsize: Optional[Tuple[float, float]] = None,
) -> "Figure":
    """The estimates' correlation matrix as an image.

    Rows and columns are :attr:`rfeid.Identification.parameter_names`; the
    colours run from -1 (blue) through 0 (white) to 1 (red) whatever the
    values (a diverging map fixed to [-1, 1], with a colour bar); NaN
    (undefined) cells are grey. ``annotate``: write each r in its cell
    (default: when there are at most 20 parameters). The correlation is
    dimensionless. ``figsize`` in inches. Returns a
    :class:`matplotlib.figure.Figure` with two axes (the matrix, the
    colour bar).
    """
    c = np.asarray(res.correlation, dtype=float)
    names = res.parameter_names
    r = len(names)
    side = min(max(4.0, 0.45 * r + 2.0), 14.0)
    fig = _figure(figsize=figsize or (side + 1.2, side), layout="constrained")
    ax = fig.add_subplot()
    import matplotlib as mpl

    cmap = mpl.colormaps["RdBu_r"].with_extremes(bad="0.8")
    image = ax.imshow(np.ma.masked_invalid(c), cmap=cmap, vmin=-1.0, vmax=1.0, interpolation="nearest")
    fig.colorbar(image, ax=ax, label="correlation r", shrink=0.85)
    ax.set_xticks(range(r), names, rotation=90)
    ax.set_yticks(range(r), names)
    if annotate is None:
        annotate = r <= ANNOTATE_UP_TO
    if annotate:
        small = "x-small" if r > 10 else "small"
        for i in range(r):
            for j in range(r):
                v = c[i, j]
                text = "-" if np.isnan(v) else f"{v:.2f}"
                colour = "white" if abs(v) > 0.6 else "black"
                ax.text(j, i, text, ha="center", va="center", fontsize=small, color=colour)
    ax.set_title("correlation of the estimates")
    return fig


def plot_design(design: "Design", *, figsize: Optional[Tuple[float, float]] = None) -> "Figure":
    """Predicted relative standard errors of a design, per parameter.

    Horizontal bars on a log axis, in % of the parameter's value: the
    placed sensors alone, and (after ``design(..., choose=K)``) with the
    chosen candidates added. A standard error that is undefined (``None``:
    the parameter cannot be identified from those sensors) or a value of 0
    has no bar and is marked "undefined". ``figsize`` in inches. Returns a
    :class:`matplotlib.figure.Figure` with one axis.
    """
    doc = design.document
    names = [p["name"] for p in doc["parameters"]]
    placed = _relative(doc["placed"]["parameters"])
    series = [("placed sensors", placed, "0.55")]
    if design.chosen:
        label = "with " + ", ".join(design.chosen)
        series.append((label, _relative(doc["parameters"]), "C0"))
    fig = _figure(figsize=figsize or (7.0, 1.5 + 0.2 * len(names) * len(series)), layout="constrained")
    ax = fig.add_subplot()
    y = np.arange(len(names))
    height = 0.8 / len(series)
    finite = [v for _, rel, _ in series for v in rel.values() if v is not None and v > 0]
    floor = min(finite) / 3 if finite else 1e-3
    for k, (label, rel, colour) in enumerate(series):
        pos = y - 0.4 + height * (k + 0.5)
        values = [rel.get(n) for n in names]
        widths = [v - floor if v is not None and v > 0 else np.nan for v in values]
        ax.barh(pos, widths, height=height, left=floor, color=colour, label=label)
        for p, v in zip(pos, values):
            if v is None or not v > 0:
                ax.text(floor, p, " undefined", va="center", fontsize="x-small", color=colour)
    ax.set_xscale("log")
    ax.set_yticks(y, names)
    ax.invert_yaxis()
    ax.set_xlabel("predicted standard error (% of the value)")
    ax.grid(True, axis="x", which="both", lw=0.3)
    if finite:
        ax.set_xlim(left=floor)
    ax.legend(loc="lower right", fontsize="small")
    ax.set_title("design: predicted standard errors")
    return fig


def _relative(parameters: List[dict]) -> dict:
    """name -> relative standard error in % (None where undefined)."""
    out = {}
    for p in parameters:
        rel = p.get("relative_std_error")
        if rel is None and p.get("std_error") is not None and p.get("value"):
            rel = p["std_error"] / abs(p["value"])
        out[p["name"]] = None if rel is None else 100.0 * rel
    return out
