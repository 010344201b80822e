"""rfeid: stiffness and damping of nonlinear machine-tool joints, identified
from vibration tests on rigid-finite-element models.

The library does the work (the same code as the ``rfeid`` command line, so
the same inputs and options give the same numbers); this package turns its
results into numpy arrays, pandas DataFrames and dicts::

    import rfeid
    m = rfeid.Model.load("examples/knee-column/model.toml")
    sim = m.simulate(noise=0.02, seed=3)
    res = rfeid.identify(m, sim.to_pandas())
    res.estimates, res.std_errors, res.verdict.trustworthy

Errors are exceptions: :class:`ModelError` and :class:`DataError` (both
``ValueError``) name the file, entry, field or column; an identification
that cannot be done raises :class:`IdentificationError` (a
``RuntimeError``). Ctrl-C stops a long call with ``KeyboardInterrupt``.
"""
from __future__ import annotations

import json
import os
import sys
import warnings
from dataclasses import dataclass
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _rfeid
from ._rfeid import DataError, IdentificationError, ModelError, __version__

__all__ = [
    "Model",
    "Parameter",
    "Simulation",
    "Identification",
    "Verdict",
    "identify",
    "design",
    "Design",
    "ModelError",
    "DataError",
    "IdentificationError",
    "__version__",
]

PathLike = Union[str, "os.PathLike[str]"]
SetValues = Optional[Mapping[str, Union[float, int, str]]]


def _floats(data: bytes) -> np.ndarray:
    """Little-endian float64 bytes from the library as a (writable) numpy array."""
    return np.frombuffer(data, dtype="<f8").astype(np.float64)


def _as_bytes(values: Any) -> bytes:
    """An array-like as little-endian float64 bytes for the library."""
    return np.ascontiguousarray(np.asarray(values, dtype=np.float64), dtype="<f8").tobytes()


def _set_list(set: SetValues) -> List[str]:
    """``{"a_n1": 4e15, "P0": "20 daN"}`` as the command line's ``NAME=VALUE``.

    A float is written with ``repr``, which reads back to the same value.
    """
    if set is None:
        return []
    if not isinstance(set, Mapping):
        raise TypeError("set: expected a mapping of parameter names to values, e.g. {'a_n1': 4e15}")
    out = []
    for name, value in set.items():
        if isinstance(value, bool) or not isinstance(value, (int, float, str, np.floating, np.integer)):
            raise TypeError(f"set[{name!r}]: expected a number or a string with a unit, not {type(value).__name__}")
        text = value if isinstance(value, str) else repr(float(value))
        out.append(f"{name}={text}")
    return out


@dataclass(frozen=True)
class Parameter:
    """A parameter of a model: SI values, its box (``None`` if fixed), and
    the unit it is shown in (``unit_scale`` is one unit in SI)."""

    name: str
    value: float
    min: Optional[float]
    max: Optional[float]
    unit: str
    unit_scale: float
    scale: str
    dimension: str
    identified: bool
    per_experiment: bool


class Model:
    """A model file (TOML, SPEC §1), loaded and validated by the library."""

    def __init__(self, native: _rfeid.Model) -> None:
        self._native = native

    @classmethod
    def load(cls, path: PathLike) -> "Model":
        """Loads and validates a model file; raises :class:`ModelError`
        naming the file, entry and field of a problem."""
        return cls(_rfeid.Model.load(os.fspath(path)))

    @classmethod
    def from_toml(cls, text: str, base_dir: PathLike = ".") -> "Model":
        """A model from the text of a model file; relative paths in it are
        found from ``base_dir``."""
        return cls(_rfeid.Model.from_toml(text, os.fspath(base_dir)))

    @property
    def path(self) -> Optional[str]:
        """The file the model was loaded from (``None`` for a text)."""
        p = self._native.path
        return None if p is None else os.fspath(p)

    @property
    def parameters(self) -> List[Parameter]:
        """The parameters: names, values, boxes and units."""
        return [Parameter(**d) for d in self._native.parameters]

    @property
    def sensors(self) -> List[str]:
        """The sensors' names, in the model's order."""
        return list(self._native.sensor_names)

    @property
    def sensor_units(self) -> List[str]:
        """The sensors' SI units, in the model's order."""
        return list(self._native.sensor_units)

    @property
    def sample_rate(self) -> float:
        """The sample rate, Hz."""
        return self._native.sample_rate

    @property
    def duration(self) -> float:
        """The record's length, s."""
        return self._native.duration

    @property
    def notes(self) -> List[str]:
        """What reading the file noted."""
        return list(self._native.notes)

    def simulate(
        self,
        set: SetValues = None,
        noise: Optional[float] = None,
        noise_corner: Optional[float] = None,
        seed: int = 0,
        tolerance: Optional[float] = None,
        substeps: Optional[int] = None,
    ) -> "Simulation":
        """The sensors' response at the nominal values, as ``rfeid simulate``.

        ``set`` changes parameter values (SI numbers, or strings with a
        unit such as ``"450 daN/um^2"``); ``noise`` adds white Gaussian
        noise of that fraction of each sensor's RMS (seeded with ``seed``),
        passed through a low-pass at ``noise_corner`` Hz if given;
        ``tolerance`` and ``substeps`` override the model's integrator
        settings. The GIL is released while it runs.
        """
        if noise_corner is not None and noise is None:
            raise ValueError("noise_corner: needs noise")
        time, values, n, c, notes = self._native.simulate(
            _set_list(set), noise, noise_corner, int(seed), tolerance, substeps
        )
        for note in notes:
            warnings.warn(note, stacklevel=2)
        return Simulation(
            time=_floats(time),
            names=self.sensors,
            units=self.sensor_units,
            values=_floats(values).reshape(c, n).T.copy(),
        )

    def __repr__(self) -> str:
        return repr(self._native)


@dataclass
class Simulation:
    """A simulated record: ``time`` (s, n), ``values`` (n × sensors, SI),
    the sensors' ``names`` and ``units``."""

    time: np.ndarray
    names: List[str]
    units: List[str]
    values: np.ndarray

    def to_pandas(self) -> Any:
        """A DataFrame with a ``time`` column and one column per sensor,
        as the CSV of ``rfeid simulate``."""
        import pandas as pd

        frame = pd.DataFrame(self.values, columns=self.names)
        frame.insert(0, "time", self.time)
        return frame

    def to_dict(self) -> Dict[str, np.ndarray]:
        """A mapping ``time`` and sensor name → array, as ``identify`` takes."""
        out = {"time": self.time}
        out.update({n: self.values[:, i] for i, n in enumerate(self.names)})
        return out

    def __repr__(self) -> str:
        return (
            f"<rfeid.Simulation: {len(self.time)} samples × {len(self.names)} sensors "
            f"({', '.join(self.names)})>"
        )


@dataclass(frozen=True)
class Verdict:
    """Whether the result can be trusted (SPEC §4): ``outcome`` is
    ``"trustworthy"``, ``"suspect"`` or ``"model error"``, with the reasons
    in words."""

    outcome: str
    reasons: Tuple[str, ...]

    @property
    def trustworthy(self) -> bool:
        """True when no check failed."""
        return self.outcome == "trustworthy"


def _column(label: str, name: str, values: Any) -> bytes:
    """One column as float64 bytes; a column that is not numeric is a
    :class:`DataError` naming it."""
    try:
        array = np.asarray(values, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise DataError(f"{label}: column '{name}' is not numeric: {e}") from None
    if array.ndim != 1:
        raise DataError(f"{label}: column '{name}' is not one-dimensional (shape {array.shape})")
    return _as_bytes(array)


def _table(data: Any) -> Tuple[str, bytes, List[str], List[bytes]]:
    """A DataFrame (a ``time`` column or index) or a mapping with ``time``
    as (label, time, names, columns) for the library."""
    label = type(data).__name__
    if hasattr(data, "columns") and hasattr(data, "index"):
        names_all = [str(c) for c in data.columns]
        twice = sorted({n for n in names_all if names_all.count(n) > 1})
        if twice:
            raise DataError(f"{label}: the column '{twice[0]}' appears twice")
        if "time" in names_all:
            time = data[data.columns[names_all.index("time")]].to_numpy()
        elif getattr(data.index, "name", None) == "time":
            time = data.index.to_numpy()
        else:
            raise DataError(f"{label}: no column 'time' (columns: {', '.join(names_all)})")
        pairs = [(str(c), data[c].to_numpy()) for c in data.columns if str(c) != "time"]
    elif isinstance(data, Mapping):
        keys = [str(k) for k in data.keys()]
        if "time" not in keys:
            raise DataError(f"{label}: no entry 'time' (entries: {', '.join(keys)})")
        time = next(v for k, v in data.items() if str(k) == "time")
        pairs = [(str(k), v) for k, v in data.items() if str(k) != "time"]
    else:
        raise TypeError(
            "data: expected a path, a pandas DataFrame with a 'time' column, "
            f"or a mapping of names to arrays with 'time', not {type(data).__name__}"
        )
    cols = [_column(label, n, v) for n, v in pairs]
    return label, _column(label, "time", time), [n for n, _ in pairs], cols


class _Bar:
    """A progress line on standard error (a notebook's too)."""

    def __init__(self) -> None:
        self.last = ""

    def __call__(self, done: int, total: int, search: int, searches: int, it: int, cost: float) -> None:
        if search == 0 and total:
            filled = int(30 * done / total)
            line = f"LP_τ plan [{'=' * filled}{' ' * (30 - filled)}] {done}/{total} points"
        elif search:
            line = f"local search {search}/{searches}: iteration {it}, J = {cost:.6e}"
        else:
            return
        if line != self.last:
            sys.stderr.write("\r" + line.ljust(len(self.last)))
            sys.stderr.flush()
            self.last = line

    def close(self) -> None:
        if self.last:
            sys.stderr.write("\n")
            sys.stderr.flush()


def identify(
    model: Model,
    data: Any,
    *,
    set: SetValues = None,
    plan: int = 100,
    starts: int = 1,
    method: str = "lm",
    weights: Optional[str] = None,
    noise_model: str = "ar",
    window: Optional[float] = None,
    from_: float = 0.0,
    threads: Optional[int] = None,
    start: str = "plan",
    tolerance: Optional[float] = None,
    substeps: Optional[int] = None,
    jacobian_memory: Optional[int] = None,
    progress: bool = False,
) -> "Identification":
    """Identifies the parameters with a box from measured data, as
    ``rfeid identify`` with the same options does (same numbers).

    ``data`` is a data file (CSV, MAT, UFF), a DataFrame with a ``time``
    column (or index) and a column per sensor, or a mapping of names to
    arrays with ``"time"``. Options have the command line's names and
    defaults: ``plan`` LP_τ points (100), ``starts`` local searches (1),
    ``method`` ``"lm"`` or ``"bfgs"``, ``weights`` ``"equal"`` or
    ``"estimated"`` (default), ``noise_model`` ``"ar"`` or ``"white"``,
    ``window`` the fraction of the record fitted first (0.15; 0 off),
    ``from_`` the first time fitted (s; ``--from``), ``threads`` (all
    cores; results do not depend on it), ``start`` ``"plan"`` or
    ``"values"``, ``set`` parameters fixed for this run,
    ``jacobian_memory`` the most MiB a whole Jacobian may take (256; a
    longer record's goes block by block into its triangular factor, the
    same results to rounding; 0: always). ``progress=True`` shows the
    search's progress on standard error.

    The GIL is released while it runs; Ctrl-C raises ``KeyboardInterrupt``
    within about a second.
    """
    if not isinstance(model, Model):
        raise TypeError(f"model: expected rfeid.Model, not {type(model).__name__}")
    source = os.fspath(data) if isinstance(data, (str, os.PathLike)) else _table(data)
    bar = _Bar() if progress else None
    try:
        native, notes = _rfeid.identify(
            model._native,
            source,
            set=_set_list(set),
            plan=plan,
            starts=starts,
            method=method,
            weights=weights,
            noise_model=noise_model,
            window=window,
            from_=float(from_),
            threads=threads,
            start=start,
            tolerance=tolerance,
            substeps=substeps,
            jacobian_memory=jacobian_memory,
            progress=bar,
        )
    finally:
        if bar is not None:
            bar.close()
    for note in notes:
        if note.startswith("warning: "):
            warnings.warn(note[len("warning: "):], stacklevel=2)
    return Identification(native, notes)


class Identification:
    """The result of :func:`identify`: estimates and standard errors (SI),
    correlations, the verdict, RESULT.json's document and the report."""

    def __init__(self, native: _rfeid.Identification, notes: Sequence[str] = ()) -> None:
        self._native = native
        self.notes: List[str] = list(notes)
        self.document: Dict[str, Any] = json.loads(native.to_json())
        """RESULT.json's document as a dict."""

    @property
    def parameter_names(self) -> List[str]:
        """The identified parameters, in the result's order."""
        return [p["name"] for p in self.document["parameters"]]

    @property
    def estimates(self) -> Dict[str, float]:
        """Estimates by parameter name, SI."""
        return {p["name"]: p["estimate"] for p in self.document["parameters"]}

    @property
    def std_errors(self) -> Dict[str, Optional[float]]:
        """Standard errors (Cramér–Rao, eq. 26–29) by parameter name, SI;
        ``None`` where they could not be computed."""
        return {p["name"]: p.get("std_error") for p in self.document["parameters"]}

    @property
    def correlation(self) -> np.ndarray:
        """The estimates' correlation matrix, r × r, in
        :attr:`parameter_names` order (NaN where undefined)."""
        c = self.document.get("correlation")
        r = len(self.parameter_names)
        if c is None:
            return np.full((r, r), np.nan)
        return np.array([[np.nan if v is None else v for v in row] for row in c], dtype=float)

    @property
    def verdict(self) -> Verdict:
        """Whether the result can be trusted, and why not."""
        v = self._native.verdict()
        if v is None:
            return Verdict("suspect", ("no verdict was reached",))
        return Verdict(v[0], tuple(v[1]))

    def to_json(self) -> str:
        """The same document as RESULT.json of ``rfeid identify``."""
        return self._native.to_json()

    def report(self, directory: PathLike) -> str:
        """Writes the HTML report (report.html and SVG figures) into
        ``directory`` (created if missing); returns report.html's path."""
        return os.fspath(self._native.report(os.fspath(directory)))

    def _rows(self) -> List[Tuple[str, str, str, str, str]]:
        rows = []
        for p in self.document["parameters"]:
            scale = p.get("unit_scale") or 1.0
            unit = p.get("unit") or ""
            se = p.get("std_error")
            rel = "-" if se is None or p["estimate"] == 0 else f"{100 * se / abs(p['estimate']):.3g} %"
            rows.append(
                (
                    p["name"],
                    f"{p['estimate'] / scale:.6g}",
                    "-" if se is None else f"{se / scale:.3g}",
                    rel,
                    unit,
                )
            )
        return rows

    def __repr__(self) -> str:
        v = self.verdict
        head = f"<rfeid.Identification: {len(self.parameter_names)} parameters, verdict {v.outcome}>"
        widths = [max(len(r[i]) for r in self._rows() + [("parameter", "estimate", "s.e.", "rel. s.e.", "unit")]) for i in range(5)]
        lines = [head]
        for r in [("parameter", "estimate", "s.e.", "rel. s.e.", "unit")] + self._rows():
            lines.append("  " + "  ".join(c.ljust(w) for c, w in zip(r, widths)))
        lines.extend(f"  - {reason}" for reason in v.reasons)
        return "\n".join(lines)

    def _repr_html_(self) -> str:
        import html

        v = self.verdict
        cells = "".join(
            "<tr>" + "".join(f"<td>{html.escape(c)}</td>" for c in r) + "</tr>" for r in self._rows()
        )
        reasons = "".join(f"<li>{html.escape(r)}</li>" for r in v.reasons)
        return (
            f"<p><b>rfeid identification</b>: verdict <b>{html.escape(v.outcome)}</b></p>"
            "<table><tr><th>parameter</th><th>estimate</th><th>s.e.</th><th>rel. s.e.</th><th>unit</th></tr>"
            f"{cells}</table>" + (f"<ul>{reasons}</ul>" if reasons else "")
        )


def design(
    model: Model,
    *,
    set: SetValues = None,
    choose: Optional[int] = None,
    over_box: Optional[int] = None,
    threads: Optional[int] = None,
) -> "Design":
    """What a test will give before it is run, as ``rfeid design`` (SPEC §6).

    Predicts the Cramér–Rao standard errors of the placed sensors (each
    sensor's ``noise`` in the model file) at the parameters' values (or at
    ``set``, inside the box); ``choose=K`` adds the D-optimal K of the
    candidate sensors (``candidate = true``), with a bound on how far from
    optimal the choice can be; ``over_box=N`` chooses for the average over
    N LP_τ points of the box.
    """
    if not isinstance(model, Model):
        raise TypeError(f"model: expected rfeid.Model, not {type(model).__name__}")
    native, notes = _rfeid.design(
        model._native, set=_set_list(set), choose=choose, over_box=over_box, threads=threads
    )
    for note in notes:
        warnings.warn(note, stacklevel=2)
    return Design(native)


class Design:
    """The result of :func:`design`: the document of ``rfeid design -o``."""

    def __init__(self, native: _rfeid.Design) -> None:
        self._native = native
        self.document: Dict[str, Any] = json.loads(native.to_json())
        """The design's document as a dict."""

    @property
    def chosen(self) -> List[str]:
        """The candidate sensors chosen (empty without ``choose``)."""
        return list(self.document["chosen"])

    @property
    def std_errors(self) -> Dict[str, Optional[float]]:
        """Predicted standard errors by parameter, SI: with the chosen
        sensors added, else the placed sensors'."""
        return {p["name"]: p["std_error"] for p in self.document["parameters"]}

    @property
    def placed_std_errors(self) -> Dict[str, Optional[float]]:
        """Predicted standard errors of the placed sensors alone, SI."""
        return {p["name"]: p["std_error"] for p in self.document["placed"]["parameters"]}

    @property
    def efficiency_at_least(self) -> Optional[float]:
        """The D-efficiency the choice is guaranteed (``None`` without ``choose``)."""
        choice = self.document.get("choice")
        return None if choice is None else choice["efficiency_at_least"]

    def to_json(self) -> str:
        """The same document as ``rfeid design -o``."""
        return self._native.to_json()

    def report(self, directory: PathLike) -> str:
        """Writes the HTML report into ``directory``; returns report.html's path."""
        return os.fspath(self._native.report(os.fspath(directory)))

    def __repr__(self) -> str:
        rel = {p["name"]: p.get("relative_std_error") for p in self.document["parameters"]}
        parts = ", ".join(
            f"{n} {100 * r:.3g} %" if r is not None else f"{n} -" for n, r in rel.items()
        )
        chosen = f", chosen {self.chosen}" if self.chosen else ""
        return f"<rfeid.Design: relative s.e. {parts}{chosen}>"
