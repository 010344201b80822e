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

- :class:`Model` -- a model file: ``Model.load(path)``, its parameters,
  sensors and sampling, and ``Model.simulate()`` -> :class:`Simulation`;
- :func:`identify` -> :class:`Identification`: estimates, standard
  errors, correlations, the :class:`Verdict`, RESULT.json and the report;
- :func:`design` -> :class:`Design`: predicted standard errors of a
  planned test and the D-optimal choice of candidate sensors.

Units: every number is SI (N, m, kg, s, rad and their products: a
stiffness in N/m, a damping in N*s/m, a power law's ``a`` in N/m^m, or in
N with a reference deformation), whatever unit the model file wrote it
in; times are in seconds and rates in Hz. :class:`Parameter` gives the
unit a value is shown in and its size in SI.

Errors are exceptions: :class:`ModelError` and :class:`DataError` (both
``ValueError``) name the file, entry, field or column; an option out of
range is a ``ValueError`` named as the keyword (``plan=0: ...``); an
identification or simulation that cannot be done raises
:class:`IdentificationError` (a ``RuntimeError``). Notes of the library
that are warnings (a ``set`` value outside its box, say) are issued as
``UserWarning``. Ctrl-C stops a long call with ``KeyboardInterrupt``.
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
from ._signals import Signals, report_figures as _report_figures, signals_of as _signals_of

__all__ = [
    "Model",
    "Parameter",
    "Experiment",
    "Simulation",
    "Identification",
    "Frf",
    "Signals",
    "Verdict",
    "Reason",
    "identify",
    "validate",
    "merge",
    "design",
    "Design",
    "ModelError",
    "DataError",
    "IdentificationError",
    "Cancelled",
    "__version__",
]

PathLike = Union[str, "os.PathLike[str]"]
# The search options' defaults, the library's (and so the command line's).
_DEFAULTS: Dict[str, Any] = dict(_rfeid.search_defaults())
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


def _int(name: str, value: Any, optional: bool = False) -> Optional[int]:
    """An integer keyword as given: a ``bool``, ``float`` or ``str`` is a
    ``TypeError`` naming the keyword (never truncated or parsed), a negative
    one a ``ValueError``."""
    if value is None and optional:
        return None
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name}={value!r}: expected an integer, not {type(value).__name__}")
    if value < 0:
        raise ValueError(f"{name}={value}: must not be negative")
    return int(value)


def _float(name: str, value: Any, optional: bool = False) -> Optional[float]:
    """A real keyword as given: a ``bool``, ``str`` or complex number is a
    ``TypeError`` naming the keyword."""
    if value is None and optional:
        return None
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name}={value!r}: expected a real number, not {type(value).__name__}")
    return float(value)


@dataclass(frozen=True)
class Parameter:
    """A parameter of a model, as :attr:`Model.parameters` lists it.

    Attributes:
        name: its name in the model file.
        value: the nominal value (the model file's ``value``), SI.
        min, max: the box it is identified in, SI; ``None`` for a fixed
            parameter.
        unit: the unit it is shown in, as the model file wrote it
            (``"daN/um^2"``); ``""`` for a bare number.
        unit_scale: one ``unit`` in SI (1e13 for daN/um^2), so
            ``value / unit_scale`` is the value in ``unit``.
        scale: ``"linear"`` or ``"log"``: how the plan and the local search
            spread over the box.
        dimension: its SI unit as text (``"N/m^2"``, ``"N·s/m"``, ``"kg"``,
            ``"dimensionless"``): the unit of ``value``, ``min`` and ``max``.
        identified: True when it has a box (``min`` and ``max``).
        per_experiment: True when a campaign identifies it once per
            experiment (the command line's campaigns only).
    """

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


@dataclass(frozen=True)
class Experiment:
    """One test of a campaign (an ``[[experiment]]`` entry of the model
    file, SPEC §5).

    Attributes:
        name: its name (``name[experiment]`` in results).
        role: ``"fit"`` (fitted by :func:`identify`) or ``"validation"``
            (simulated at the estimate and compared).
        data: its data file, resolved against the model file's directory.
    """

    name: str
    role: str
    data: str


class Model:
    """A model file (TOML, SPEC §1), loaded and validated by the library.

    Make one with :meth:`load` (a file) or :meth:`from_toml` (its text).
    ``repr()`` summarises it: bodies, elements, parameters, sensors,
    samples and sample rate.
    """

    def __init__(self, native: _rfeid.Model, source: Optional[Tuple[str, ...]] = None) -> None:
        self._native = native
        # How to read it again, for pickling: ("file", path) or ("text", text, base_dir).
        self._source = source

    def __reduce__(self) -> Any:
        """A model pickles as what it was read from (its file's path, or its
        text), and is read again on unpickling (multiprocessing, joblib)."""
        if self._source is None:
            raise TypeError("this rfeid.Model cannot be pickled: load it with Model.load or Model.from_toml")
        if self._source[0] == "file":
            return (Model.load, (self._source[1],))
        return (Model.from_toml, (self._source[1], self._source[2]))

    @classmethod
    def load(cls, path: PathLike) -> "Model":
        """Loads and validates a model file (TOML, SPEC §1).

        Returns a :class:`Model`. Raises :class:`ModelError` naming the
        file, entry and field of a problem (a missing or unreadable file
        too).
        """
        return cls(_rfeid.Model.load(os.fspath(path)), ("file", os.fspath(path)))

    @classmethod
    def from_toml(cls, text: str, base_dir: PathLike = ".") -> "Model":
        """A model from the text of a model file.

        Returns a :class:`Model` whose :attr:`path` is ``None``; relative
        paths in the text (signal tables) are found from ``base_dir``
        (default: the current directory). Raises :class:`ModelError` as
        :meth:`load` does.
        """
        return cls(
            _rfeid.Model.from_toml(text, os.fspath(base_dir)),
            ("text", text, os.path.abspath(os.fspath(base_dir))),
        )

    @property
    def path(self) -> Optional[str]:
        """The file the model was loaded from, a ``str`` as given to
        :meth:`load` (``None`` for a model from a text)."""
        p = self._native.path
        return None if p is None else os.fspath(p)

    @property
    def parameters(self) -> List[Parameter]:
        """The model's parameters in the file's order: a list of
        :class:`Parameter` (names, values and boxes in SI, the units they
        are shown in)."""
        return [Parameter(**d) for d in self._native.parameters]

    @property
    def sensors(self) -> List[str]:
        """The sensors' names (a list of ``str``) in the model's order: the
        columns of :attr:`Simulation.values`, and the columns
        :func:`identify` reads."""
        return list(self._native.sensor_names)

    @property
    def sensor_units(self) -> List[str]:
        """The sensors' SI units (a list of ``str``: ``"m"``, ``"m/s"`` or
        ``"m/s^2"`` for displacement, velocity or acceleration), in the
        model's order."""
        return list(self._native.sensor_units)

    @property
    def sample_rate(self) -> float:
        """The sample rate of the model's record, Hz (a ``float``)."""
        return self._native.sample_rate

    @property
    def duration(self) -> float:
        """The record's length, s (a ``float``): ``round(duration ×
        sample_rate)`` samples, the first at t = 0."""
        return self._native.duration

    @property
    def notes(self) -> List[str]:
        """What reading the file noted (a list of ``str``; a table's time
        axis taken on the model's grid, say); empty when nothing was."""
        return list(self._native.notes)

    @property
    def experiments(self) -> List[Experiment]:
        """The experiments of a campaign (``[[experiment]]`` entries, SPEC
        §5) in the file's order, each an :class:`Experiment`; empty for a
        model fitted to one data set."""
        return [Experiment(n, r, os.fspath(d)) for n, r, d in self._native.experiments]

    def simulate(
        self,
        set: SetValues = None,
        noise: Optional[float] = None,
        noise_corner: Optional[float] = None,
        seed: int = 0,
        tolerance: Optional[float] = None,
        substeps: Optional[int] = None,
        experiment: Optional[str] = None,
    ) -> "Simulation":
        """The sensors' response at the parameters' values, as ``rfeid simulate``.

        Returns a :class:`Simulation`: ``time`` in s (n samples from 0 at
        1/:attr:`sample_rate`), ``values`` n × sensors in each sensor's SI
        unit (m, m/s or m/s^2), the same numbers as ``rfeid simulate``'s
        CSV.

        ``set`` changes parameter values (a mapping name -> SI number, or
        a string with a unit such as ``"450 daN/um^2"``; a value outside
        its box is allowed, with a ``UserWarning``); ``noise`` adds
        Gaussian noise of standard deviation ``noise`` × RMS of each
        sensor's signal (a fraction: 0.02 is 2 %), seeded with ``seed``,
        passed through a second-order Butterworth low-pass with its corner
        at ``noise_corner`` Hz if given (the standard deviation stays the
        same); ``tolerance`` (the relative RMS error the integrator's steps
        are chosen for, 1e-13 to 1e-2) and ``substeps`` (steps per sample,
        1 to 1000) override the model's integrator settings. ``experiment``
        names one of a campaign's experiments (:attr:`experiments`): its
        ``set`` values, sampling, excitations and sensors are simulated
        (``--experiment``); without it a campaign's model is simulated at
        its own values.

        Raises :class:`ModelError` for an unknown parameter, a value of the
        wrong dimension or a bad ``tolerance``/``substeps``, ``ValueError``
        for a negative ``noise`` or a ``noise_corner`` without ``noise``,
        :class:`IdentificationError` if the simulation fails, ``TypeError``
        naming the keyword for a value of the wrong type (``seed=3.7``,
        ``noise=True``: never truncated or converted). The GIL is released
        while it runs.
        """
        if noise_corner is not None and noise is None:
            raise ValueError("noise_corner: needs noise")
        time, values, n, c, notes = self._native.simulate(
            _set_list(set),
            _float("noise", noise, True),
            _float("noise_corner", noise_corner, True),
            _int("seed", seed),
            _float("tolerance", tolerance, True),
            _int("substeps", substeps, True),
            None if experiment is None else str(experiment),
        )
        for note in notes:
            warnings.warn(note, stacklevel=2)
        sensors = self._native.experiment_sensors(experiment) if experiment is not None else None
        return Simulation(
            time=_floats(time),
            names=sensors[0] if sensors else self.sensors,
            units=sensors[1] if sensors else self.sensor_units,
            values=_floats(values).reshape(c, n).T.copy(),
        )

    def __repr__(self) -> str:
        return repr(self._native)


@dataclass
class Simulation:
    """A simulated record, as :meth:`Model.simulate` returns it.

    Attributes:
        time: the sample instants, s: a numpy array of n floats from 0 in
            steps of 1/sample_rate.
        names: the sensors' names, in the model's order.
        units: the sensors' SI units (``"m"``, ``"m/s"``, ``"m/s^2"``).
        values: the readings, a numpy array n × sensors (row k at
            ``time[k]``, column i the sensor ``names[i]`` in ``units[i]``).
    """

    time: np.ndarray
    names: List[str]
    units: List[str]
    values: np.ndarray

    def to_pandas(self) -> Any:
        """Returns a pandas DataFrame: a ``time`` column (s), then one
        column per sensor (SI), as the CSV of ``rfeid simulate``; it is
        data :func:`identify` takes. Needs pandas (``pip install
        "./python[pandas]"``)."""
        import pandas as pd

        frame = pd.DataFrame(self.values, columns=self.names)
        frame.insert(0, "time", self.time)
        return frame

    def to_dict(self) -> Dict[str, np.ndarray]:
        """Returns a dict ``"time"`` (s) and each sensor's name -> a 1-D
        numpy array (SI), which :func:`identify` takes as data (no pandas
        needed)."""
        out = {"time": self.time}
        out.update({n: self.values[:, i] for i, n in enumerate(self.names)})
        return out

    def __repr__(self) -> str:
        return (
            f"<rfeid.Simulation: {len(self.time)} samples × {len(self.names)} sensors "
            f"({', '.join(self.names)})>"
        )


class Reason(str):
    """One reason of a verdict, or one warning of a run: its words (it is a
    ``str``) with its kind and values, as RESULT.json tags it.

    Attributes:
        kind: the tag (``"poor_fit"``, ``"not_white"``, ``"at_bound"``,
            ``"strong_correlation"``, ``"model_error"``, ``"side_minimum"``,
            ...; see the reference of RESULT.json); ``""`` for words read
            from a file written before tags.
        fields: its values (SI), a dict as RESULT.json holds them.
    """

    kind: str
    fields: Dict[str, Any]

    def __new__(cls, tagged: Any, words: Optional[str] = None) -> "Reason":
        if not isinstance(tagged, Mapping):
            tagged = {"message": str(tagged)}
        text = words if words is not None else str(tagged.get("message", ""))
        obj = super().__new__(cls, text)
        obj.kind = str(tagged.get("kind", ""))
        obj.fields = {k: v for k, v in tagged.items() if k not in ("kind", "message")}
        return obj

    @property
    def message(self) -> str:
        """Its words, a plain ``str``."""
        return str.__str__(self)

    @property
    def sensor(self) -> Optional[str]:
        """The sensor it is about, if it names one."""
        return self.fields.get("sensor")

    @property
    def parameter(self) -> Optional[str]:
        """The parameter it is about, if it names one."""
        return self.fields.get("parameter")

    def __repr__(self) -> str:
        return f"Reason(kind={self.kind!r}, message={self.message!r})"

    def __reduce__(self) -> Any:
        return (Reason, (dict(self.fields, kind=self.kind, message=self.message),))


@dataclass(frozen=True)
class Verdict:
    """Whether the result can be trusted (SPEC §4), as
    :attr:`Identification.verdict` gives it.

    Attributes:
        outcome: ``"trustworthy"``, ``"suspect"`` or ``"model error"`` (the
            command line's exit status 0, 3 and 4).
        reasons: the checks that failed (a tuple of :class:`Reason`, each a
            ``str`` in words with ``kind``, ``sensor``, ``parameter`` and
            ``fields``; empty when trustworthy).
    """

    outcome: str
    reasons: Tuple[str, ...]

    @property
    def trustworthy(self) -> bool:
        """Returns True when no check failed (``outcome`` is
        ``"trustworthy"``), else False."""
        return self.outcome == "trustworthy"


def _column(label: str, name: str, values: Any) -> bytes:
    """One column as float64 bytes; a column that is not real numbers
    (strings, booleans, complex numbers) is a :class:`DataError` naming it."""
    raw = np.asarray(values)
    kind = raw.dtype.kind
    if kind == "O" and raw.size:
        flat = raw.ravel()
        if any(isinstance(v, (bool, np.bool_)) for v in flat):
            kind = "b"
        elif any(isinstance(v, (complex, np.complexfloating)) for v in flat):
            kind = "c"
    if kind in "bc":
        what = "boolean" if kind == "b" else "complex"
        raise DataError(f"{label}: column '{name}' is {what}; a signal is real numbers (float)")
    if kind in "mM":
        what = "timedelta" if kind == "m" else "datetime"
        raise DataError(
            f"{label}: column '{name}' holds {what} values; times and signals are seconds and SI "
            "numbers (float): convert with .dt.total_seconds() (or "
            "(t - t[0]).dt.total_seconds() for datetimes)"
        )
    try:
        array = np.asarray(raw, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise DataError(f"{label}: column '{name}' is not numeric: {e}") from None
    if array.ndim != 1:
        raise DataError(f"{label}: column '{name}' is not one-dimensional (shape {array.shape})")
    return _as_bytes(array)


def _table(data: Any, label: Optional[str] = None) -> Tuple[str, bytes, List[str], List[bytes]]:
    """A DataFrame (a ``time`` column or index) or a mapping with ``time``
    as (label, time, names, columns) for the library; ``label`` names it in
    messages (default: its type's name)."""
    label = label or type(data).__name__
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
    """A progress line on standard error (a notebook's too); the plan's bar
    is a ``tqdm.auto`` bar (a widget in Jupyter) where tqdm is installed."""

    def __init__(self) -> None:
        self.last = ""
        self.plan: Any = None
        try:
            from tqdm.auto import tqdm
        except ImportError:
            tqdm = None
        self.tqdm = tqdm

    def __call__(self, done: int, total: int, search: int, searches: int, it: int, cost: float) -> None:
        if search == 0 and total and self.tqdm is not None:
            if self.plan is None:
                self.plan = self.tqdm(total=total, desc="LP_τ plan", unit="point")
            self.plan.update(max(done - self.plan.n, 0))
            return
        if search and self.plan is not None:
            self.plan.close()
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
        if self.plan is not None:
            self.plan.close()
        if self.last:
            sys.stderr.write("\n")
            sys.stderr.flush()


class Cancelled(Exception):
    """Raised by :func:`identify` or :func:`merge` when the ``cancel``
    event given to it was set: the run stopped within about 50 ms plus one
    simulation, and nothing keeps computing."""


def _watch(bar: Optional[_Bar], cancel: Any) -> Any:
    """The native call's progress callback: the bar (if any), and a check
    of ``cancel`` (anything with ``is_set()``, a ``threading.Event``)
    that raises :class:`Cancelled` once it is set, which stops the run."""
    if cancel is None:
        return bar
    if not callable(getattr(cancel, "is_set", None)):
        raise TypeError(f"cancel: expected a threading.Event (with is_set()), not {type(cancel).__name__}")

    def call(*state: Any) -> None:
        if bar is not None:
            bar(*state)
        if cancel.is_set():
            raise Cancelled("the run was cancelled (its cancel event was set)")

    return call


def _profile_names(profiles: Union[None, bool, Sequence[str]]) -> Optional[List[str]]:
    """The native ``profiles``: ``None`` for none, ``[]`` for every
    parameter, else the names."""
    if profiles is None or profiles is False:
        return None
    if profiles is True:
        return []
    if isinstance(profiles, str):
        return [profiles]
    return [str(p) for p in profiles]


def _warn_notes(notes: Sequence[str]) -> None:
    """Issues the library's notes of a reading (a record shifted or cut, a
    column read by no sensor, a constant signal) as warnings (``UserWarning``), as
    the command line prints them; a ``"warning: "`` prefix is dropped."""
    for note in notes:
        text = note[len("warning: "):] if note.startswith("warning: ") else note
        warnings.warn(text, stacklevel=3)


def _source(data: Any, label: Optional[str] = None) -> Any:
    """Measured data for the library: a path as ``str``, else a table."""
    if isinstance(data, (str, os.PathLike)):
        return os.fspath(data)
    return _table(data, label)


def _data_args(model: Model, data: Any) -> Tuple[Any, List[Tuple[str, Any]]]:
    """The native ``data`` and ``experiments`` of :func:`identify`: one data
    set for a model without experiments, else data by experiment name."""
    if not model._native.experiments:
        if data is None:
            raise TypeError(
                "data: needed (a path, a DataFrame or a mapping with 'time'), as the model "
                "lists no [[experiment]] with data files of its own"
            )
        return _source(data), []
    if data is None:
        return None, []
    if not isinstance(data, Mapping) or "time" in data:
        raise TypeError(
            "data: the model is a campaign ([[experiment]] entries, which name their own data "
            "files); give None, or a dict of experiment name -> data (a path or a DataFrame) "
            f"for the experiments whose data are not their files, not {type(data).__name__}"
        )
    return None, [(str(k), _source(v, f"data['{k}']")) for k, v in data.items()]


def identify(
    model: Model,
    data: Any = None,
    *,
    set: SetValues = None,
    plan: int = _DEFAULTS["plan"],
    starts: int = _DEFAULTS["starts"],
    method: str = _DEFAULTS["method"],
    weights: Optional[str] = None,
    noise_model: str = _DEFAULTS["noise_model"],
    window: Optional[float] = None,
    from_: float = _DEFAULTS["from"],
    threads: Optional[int] = None,
    start: str = "plan",
    tolerance: Optional[float] = None,
    substeps: Optional[int] = None,
    jacobian_memory: Optional[int] = None,
    progress: bool = False,
    profiles: Union[None, bool, Sequence[str]] = None,
    profile_points: int = _DEFAULTS["profile_points"],
    shard: Optional[Tuple[int, int]] = None,
    output: Optional[PathLike] = None,
    cancel: Any = None,
) -> Any:
    """Identifies the parameters with a box from measured data, as
    ``rfeid identify`` with the same options does (same numbers).

    Returns an :class:`Identification`: estimates and standard errors in
    SI units, correlations, the :class:`Verdict`, RESULT.json's document
    and the report. Notes of the reading (a record taken as starting at
    t = 0, a longer one cut, a column read by no sensor, a constant
    signal) are issued as warnings (``UserWarning``), as the command line prints
    them, and kept in its ``notes``.

    ``data`` is a data file (CSV, MAT, UFF: a ``str`` or path), a
    DataFrame with a ``time`` column (or index, s) and a column per sensor
    (SI), or a mapping of names to arrays with ``"time"``, sampled at the
    model's sample rate (a record starting after t = 0 is taken as
    starting there, a longer one is cut, each with a note).

    A model with ``[[experiment]]`` entries is a campaign (SPEC §5), fitted
    as ``rfeid identify`` fits it: every fitted experiment together, the
    validation ones simulated at the estimate (see
    :attr:`Identification.experiments`). Its data are the files the
    experiments name; ``data`` may give some or all of them instead, as a
    dict of experiment name -> data (a path, a DataFrame or a mapping as
    above). A campaign's local searches fit whole records (``window`` is
    refused), and an experiment's own ``from`` replaces ``from_``.

    ``shard=(K, N)`` with ``output=PATH`` runs shard K of N of the LP_τ plan
    only (plan points i with i mod N = K), as ``rfeid identify --shard
    K/N -o PATH`` does, and writes the same shard file (resuming one of
    this run and shard already at ``output``); returns ``output`` as a
    ``str``. :func:`merge` (or ``rfeid merge``) continues from the N
    shards. A shard needs a model loaded from a file and ``data`` a file
    (both recorded in the shard for the merge), and takes neither ``set``,
    ``start="values"`` nor ``profiles`` (give those to the merge).

    Options have the command line's names and defaults:

    - ``plan``: points of the LP_τ plan over the box (100; 1 to 1 000 000);
    - ``starts``: local searches from the best plan points (1; at most
      1000 and the plan);
    - ``method``: ``"lm"`` (Levenberg–Marquardt, the default) or
      ``"bfgs"``;
    - ``weights``: ``"estimated"`` (the default, 1/σ² per sensor) or
      ``"equal"``;
    - ``noise_model``: ``"ar"`` (the default) or ``"white"``;
    - ``window``: the fraction of the record each local search fits first
      (0.15; 0 ≤ window < 1, 0 off);
    - ``from_``: the first time fitted, s (0; ``--from``);
    - ``threads``: worker threads (all cores; results do not depend on it);
    - ``start``: ``"plan"`` or ``"values"`` (one search from the model
      file's values, without the plan);
    - ``set``: parameters fixed for this run (name -> SI number or a
      string with a unit);
    - ``tolerance``: the relative RMS error the integrator's steps are
      chosen for (the model's, else 1e-7; 1e-13 to 1e-2);
    - ``substeps``: integrator steps per sample instead (1 to 1000);
    - ``jacobian_memory``: the most MiB a whole Jacobian may take (256; a
      longer record's goes block by block into its triangular factor, the
      same results to rounding; 0: always);
    - ``progress=True``: shows the plan's bar and the local search's
      iterations on standard error;
    - ``cancel``: a ``threading.Event``; setting it (from another thread,
      say a GUI's) stops the run within about 50 ms and raises
      :class:`Cancelled` (Ctrl-C does the same in the main thread);
    - ``profiles``: after the bounds, the profile likelihoods of these
      identified parameters (a list of names; ``True``: every one; ``None``,
      the default: none), on ``profile_points`` grid points each (20; 2 to
      1000): see :attr:`Identification.profiles`.

    Raises ``ValueError`` for an option out of range (named as the
    keyword: ``plan=0: must be 1 to 1000000``), :class:`ModelError` for a
    bad ``set``, ``tolerance`` or ``substeps``,
    :class:`DataError` for data that do not fit the model (a missing
    column, another sample rate, a value that is not finite: named), and
    :class:`IdentificationError` for a run that cannot be done;
    ``TypeError`` naming the keyword for a value of the wrong type
    (``plan=True``, ``plan=4.0``, ``from_="0.1"``: never converted). The GIL is
    released while it runs; Ctrl-C raises ``KeyboardInterrupt`` within
    about a second and cancels the run.
    """
    if not isinstance(model, Model):
        raise TypeError(f"model: expected rfeid.Model, not {type(model).__name__}")
    if shard is not None:
        return _shard(model, data, shard, output, set=set, plan=plan, starts=starts, method=method,
                      weights=weights, noise_model=noise_model, window=window, from_=from_,
                      threads=threads, start=start, tolerance=tolerance, substeps=substeps,
                      profiles=profiles)
    if output is not None:
        raise TypeError("output: only with shard=(K, N); an identification is returned, not written")
    source, experiments = _data_args(model, data)
    bar = _Bar() if progress else None
    watch = _watch(bar, cancel)
    try:
        native, notes = _rfeid.identify(
            model._native,
            source,
            set=_set_list(set),
            options=_search_options(
                plan=plan, starts=starts, method=method, weights=weights,
                noise_model=noise_model, window=window, from_=from_, threads=threads,
                start=start, jacobian_memory=jacobian_memory, profiles=profiles,
                profile_points=profile_points,
            ),
            tolerance=_float("tolerance", tolerance, True),
            substeps=_int("substeps", substeps, True),
            progress=watch,
            experiments=experiments,
        )
    finally:
        if bar is not None:
            bar.close()
    _warn_notes(notes)
    return Identification(native, notes)


def _search_options(*, plan: Any, starts: Any, method: Any, weights: Any, noise_model: Any,
                    window: Any, from_: Any, threads: Any, start: Any, jacobian_memory: Any,
                    profiles: Any, profile_points: Any) -> Dict[str, Any]:
    """The search's keywords, each of its type (a ``TypeError`` naming the
    keyword otherwise), as the one dict the native ``identify`` and
    ``identify_shard`` take; the native side checks their ranges."""
    return {
        "plan": _int("plan", plan),
        "starts": _int("starts", starts),
        "method": method,
        "weights": weights,
        "noise_model": noise_model,
        "window": _float("window", window, True),
        "from": _float("from_", from_),
        "threads": _int("threads", threads, True),
        "start": start,
        "jacobian_memory": _int("jacobian_memory", jacobian_memory, True),
        "profiles": _profile_names(profiles),
        "profile_points": _int("profile_points", profile_points),
    }


def _shard(model: Model, data: Any, shard: Any, output: Any, *, set: SetValues,
           profiles: Any, tolerance: Any, substeps: Any, **options: Any) -> str:
    """:func:`identify` with ``shard``: writes shard K of N to ``output``."""
    if not (isinstance(shard, tuple) and len(shard) == 2):
        raise TypeError(f"shard={shard!r}: expected a tuple (K, N) with 0 <= K < N")
    k, n = _int("shard[0]", shard[0]), _int("shard[1]", shard[1])
    if output is None:
        raise TypeError("output: needed with shard, the path the shard file is written to")
    if not isinstance(data, (str, os.PathLike)):
        raise TypeError(
            f"data: a shard needs a data file (its path is recorded for the merge), not {type(data).__name__}"
        )
    if set:
        raise ValueError("set with shard: shards share one run's model file; write the values into a copy of it")
    if _profile_names(profiles) is not None:
        raise ValueError("profiles with shard: a shard computes no estimate to profile; give profiles to merge")
    out = os.fspath(output)
    _rfeid.identify_shard(
        model._native, os.fspath(data), (k, n), out,
        options=_search_options(jacobian_memory=None, profiles=None, profile_points=1, **options),
        tolerance=_float("tolerance", tolerance, True),
        substeps=_int("substeps", substeps, True),
    )
    return out


def merge(
    shards: Sequence[PathLike],
    *,
    model: Union[None, Model, PathLike] = None,
    data: Optional[PathLike] = None,
    threads: Optional[int] = None,
    progress: bool = False,
    profiles: Union[None, bool, Sequence[str]] = None,
    profile_points: int = _DEFAULTS["profile_points"],
    cancel: Any = None,
) -> "Identification":
    """Merges the shard files of one run (``identify(shard=...)`` or
    ``rfeid identify --shard``) into its :class:`Identification`, as ``rfeid
    merge`` does: every shard of the run, each complete, with the model and
    data files they record (found as recorded, else beside the first
    shard; ``model`` and ``data`` give them instead), which must still be
    what the shards were computed from. The local searches, bounds and
    verdict then run here, with ``threads`` and ``profiles`` as in
    :func:`identify`. The result equals the single run's in every field
    but the wall times and the thread count. Raises :class:`DataError` for
    shards that do not make one complete run (naming the file) or inputs
    that changed since.
    """
    paths = [os.fspath(p) for p in ([shards] if isinstance(shards, (str, os.PathLike)) else shards)]
    if not paths:
        raise ValueError("shards: no shard files given")
    if isinstance(model, Model):
        if model.path is None:
            raise TypeError("model: a Model loaded from a file (Model.load), whose file the shards hashed")
        model = model.path
    bar = _Bar() if progress else None
    watch = _watch(bar, cancel)
    try:
        native, notes = _rfeid.merge(
            paths,
            None if model is None else os.fspath(model),
            None if data is None else os.fspath(data),
            _int("threads", threads, True),
            watch,
            _profile_names(profiles),
            _int("profile_points", profile_points),
        )
    finally:
        if bar is not None:
            bar.close()
    _warn_notes(notes)
    return Identification(native, notes)


def validate(
    model: Model,
    result: Union["Identification", PathLike],
    data: Any = None,
    *,
    experiment: Optional[str] = None,
    from_: Optional[float] = None,
) -> List[Dict[str, Any]]:
    """Checks an identification on data, as ``rfeid validate --json``
    does (the same list): the model simulated at the estimate (steps chosen
    there) and compared sensor by sensor by the normalised RMS fit, %.

    ``result`` is an :class:`Identification` or a RESULT.json's path;
    ``data`` a data file, DataFrame or mapping with ``time`` (on the
    model, or on ``experiment``'s model when named); without ``data``, the
    named experiment's data file, else every experiment's of a campaign.
    ``from_`` (s) is the first time compared (default: an experiment's
    own ``from``, else 0). Returns a list of dicts, one per data set:
    ``experiment`` (``""`` for data of their own), ``role`` (``"fit"``,
    ``"validation"`` or ``None``), ``sensors`` and ``fit_percent`` (``None``
    for a constant signal); ``pandas.DataFrame(...)`` tabulates it.
    Raises :class:`ModelError` when the result is not of the model,
    :class:`DataError` for data that do not fit, ``ValueError`` for an
    unknown ``experiment`` or a bad ``from_``.
    """
    if not isinstance(model, Model):
        raise TypeError(f"model: expected rfeid.Model, not {type(model).__name__}")
    if isinstance(result, Identification):
        text, label = result.to_json(), "the result"
    else:
        label = os.fspath(result)
        with open(label, encoding="utf-8") as f:
            text = f.read()
    source = None if data is None else _source(data)
    json_text, notes = _rfeid.validate(
        model._native, text, label, source,
        None if experiment is None else str(experiment),
        _float("from_", from_, True),
    )
    _warn_notes(notes)
    return json.loads(json_text)


class Identification:
    """The result of :func:`identify`: estimates and standard errors (SI),
    correlations, the verdict, RESULT.json's document and the report.

    Attributes:
        document: RESULT.json's document as a dict (SI values; see the
            reference of RESULT.json for its fields).
        notes: what reading the data noted, as a list of ``str``; the
            warnings among them begin with ``"warning: "``.

    ``repr()`` is a table of estimates, standard errors, relative standard
    errors in the units the model file uses, and the verdict's reasons;
    Jupyter shows it as an HTML table.
    """

    def __reduce__(self) -> Any:
        raise TypeError(
            "an rfeid.Identification holds its model and data in native memory and cannot be "
            "pickled: pass res.to_json() (or res.document) instead, and read a written "
            "RESULT.json back with rfeid.Identification.load(path)"
        )

    def __init__(self, native: _rfeid.Identification, notes: Sequence[str] = ()) -> None:
        self._native = native
        self.notes: List[str] = list(notes)
        self.document: Dict[str, Any] = json.loads(native.to_json())
        # RESULT.json's document as a dict.

    @property
    def parameter_names(self) -> List[str]:
        """The identified parameters' names (a list of ``str``), in the
        result's order: that of :attr:`correlation`'s rows and columns."""
        return [p["name"] for p in self.document["parameters"]]

    @property
    def estimates(self) -> Dict[str, float]:
        """The estimates: a dict parameter name -> ``float``, in SI units
        (each parameter's :attr:`Parameter.dimension`: N/m, N*s/m, ...)."""
        return {p["name"]: p["estimate"] for p in self.document["parameters"]}

    @property
    def std_errors(self) -> Dict[str, Optional[float]]:
        """The standard errors (Cramér–Rao bounds, eq. 26–29): a dict
        parameter name -> ``float`` in the estimate's SI unit, or ``None``
        where they could not be computed (a singular Fisher matrix)."""
        return {p["name"]: p.get("std_error") for p in self.document["parameters"]}

    @property
    def correlation(self) -> np.ndarray:
        """The estimates' correlation matrix: a numpy array r × r of
        numbers from -1 to 1 (dimensionless), in :attr:`parameter_names`
        order; NaN where undefined."""
        c = self.document.get("correlation")
        r = len(self.parameter_names)
        if c is None:
            return np.full((r, r), np.nan)
        return np.array([[np.nan if v is None else v for v in row] for row in c], dtype=float)

    @property
    def verdict(self) -> Verdict:
        """Returns the :class:`Verdict`: whether the result can be trusted,
        and why not (``"suspect"`` with a reason if no verdict was
        reached)."""
        v = self._native.verdict()
        if v is None:
            return Verdict("suspect", (Reason({"kind": "no_verdict", "message": "no verdict was reached"}),))
        tagged = (self.document.get("verdict") or {}).get("reasons", [])
        if len(tagged) != len(v[1]):
            tagged = [{}] * len(v[1])
        return Verdict(v[0], tuple(Reason(t, w) for t, w in zip(tagged, v[1])))

    @property
    def warnings(self) -> List[Reason]:
        """What the run noticed that does not by itself make the result
        suspect (RESULT.json's ``warnings``): a list of :class:`Reason`,
        each in words with its ``kind`` and values."""
        return [Reason(w) for w in self.document.get("warnings", [])]

    @property
    def experiments(self) -> List[Dict[str, Any]]:
        """A campaign's experiments as RESULT.json lists them (a list of
        dicts: ``name``, ``role``, ``data``, ``samples``, ``sample_rate``,
        ``from``, ``weight``, ``sensors``, ``fits`` in %), fitted and
        validation ones in the model's order; empty for one data set."""
        return list(self.document.get("experiments", []))

    @property
    def profiles(self) -> Dict[str, Dict[str, Any]]:
        """The profile likelihoods asked for (``identify(profiles=...)``): a
        dict parameter name -> dict with ``values`` (the held values, SI),
        ``criterion`` (J minimised over the others, NaN where the refit
        failed) and ``statistic`` (ΔJ/(κ s²), κ the ``variance_ratio``: 1
        unless equal weights met sensors of different noise levels; NaN
        likewise) as numpy arrays in
        increasing value, ``parameters`` (an array points × parameters, SI,
        NaN rows where the refit failed), ``interval`` (the 95 %
        likelihood-ratio interval as (lower, upper), an end ``None`` where it
        is open or unresolved), ``lower`` and ``upper`` (RESULT.json's
        interval ends), ``wald`` (the Wald interval or ``None``),
        ``estimate``, ``std_error``, ``threshold`` (χ²₁(0.95)) and
        ``warnings``. Empty when none were asked."""
        out: Dict[str, Dict[str, Any]] = {}
        r = len(self.parameter_names)
        for p in self.document.get("profiles", []):
            crit = np.array(
                [np.nan if q["criterion"] is None else q["criterion"] for q in p["points"]],
                dtype=float,
            )
            params = np.array(
                [q["parameters"] if q["parameters"] else [np.nan] * r for q in p["points"]],
                dtype=float,
            ).reshape(len(p["points"]), r)
            end = lambda e: e["value"] if e["kind"] == "crossed" else None  # noqa: E731
            out[p["name"]] = {
                "values": np.array([q["value"] for q in p["points"]], dtype=float),
                "criterion": crit,
                "statistic": (crit - p["criterion"])
                / (p["s2"] * p.get("variance_ratio", 1.0)),
                "parameters": params,
                "interval": (end(p["lower"]), end(p["upper"])),
                "lower": p["lower"],
                "upper": p["upper"],
                "wald": None if p.get("wald") is None else tuple(p["wald"]),
                "estimate": p["estimate"],
                "std_error": p.get("std_error"),
                "threshold": p["threshold"],
                "warnings": list(p.get("warnings", [])),
            }
        return out

    @classmethod
    def load(cls, path: PathLike, model: Optional[Model] = None, data: Any = None) -> "Identification":
        """An identification read back from a RESULT.json (``rfeid identify
        -o``, ``rfeid merge`` or :meth:`to_json`), with its model and data,
        so that :meth:`report`, :meth:`frf` and :func:`validate` work on it.

        ``model`` is the :class:`Model` it was computed with (default: the
        model file the result records, found as given or beside the
        RESULT.json); ``data`` its data (a path, a DataFrame or a mapping
        with ``time``; default: the data file the result records, or a
        campaign's experiments' files). The result's ``set`` values are
        applied. Raises :class:`ModelError` when the result is not of the
        model (an estimate of a parameter it lacks), :class:`DataError` for
        a file that is not a result or data that do not fit; warns
        (``UserWarning``) when a file no longer holds what the result
        records.
        """
        path = os.fspath(path)
        with open(path, encoding="utf-8") as f:
            text = f.read()
        try:
            source = json.loads(text.lstrip("\ufeff")).get("source", {})
        except (ValueError, AttributeError):
            source = {}
        base = os.path.dirname(path)

        def recorded(p: Optional[str], what: str) -> str:
            if p is None or p.startswith("built-in"):
                raise TypeError(f"{path}: records no {what} file; give {what}=")
            return p if os.path.exists(p) or os.path.isabs(p) else os.path.join(base, p)

        if model is None:
            model = Model.load(recorded(source.get("model"), "model"))
        if data is None and not model._native.experiments:
            data = recorded(source.get("data"), "data")
        native, notes = _rfeid.load_result(
            text, path, model._native, None if data is None else _source(data)
        )
        _warn_notes(notes)
        return cls(native, notes)

    def to_json(self) -> str:
        """Returns RESULT.json's text (a ``str`` of JSON, SI values): the
        same document as ``rfeid identify -o`` writes for the same run."""
        return self._native.to_json()

    def report(self, directory: PathLike) -> str:
        """Writes the HTML report (report.html and SVG figures) into
        ``directory`` by the rules of ``rfeid identify --report DIR``: a new
        directory (its parent must exist) or one holding only an earlier
        report, which is replaced as a whole (no stale figures stay); a
        directory holding anything else (``"."``, the model or data) is
        refused with ``ValueError``, a failed write raises ``OSError``.
        Returns report.html's path, a ``str``."""
        return os.fspath(self._native.report(os.fspath(directory)))

    def frf(
        self,
        fmin: Optional[float] = None,
        fmax: Optional[float] = None,
        points: Optional[int] = None,
        spacing: str = "log",
        segment: Optional[int] = None,
        measured: bool = True,
    ) -> "Frf":
        """FRFs of the model linearised at rest (or at its static
        equilibrium under gravity) at the estimate, from each excitation to
        each sensor, with the 95 % band from the estimate's covariance
        (delta method, exact derivatives), and with ``measured`` the H1 and
        coherence of the identification's data (Welch, ``segment`` samples
        per segment, a power of two; default: 16 averages).

        Frequencies in Hz from ``fmin`` to ``fmax`` (default: the Nyquist
        frequency), ``points`` of them (default: four in the half-power band
        of the sharpest mode), ``spacing`` ``"log"`` or ``"linear"``.
        Returns an :class:`Frf`; bad values raise ``ValueError``."""
        text, svg = self._native.frf(fmin, fmax, points, spacing, segment, measured)
        return Frf(json.loads(text), svg)

    # Signals and figures at the estimate (rfeid/_signals.py, rfeid/plot.py).

    def signals(self, experiment: Optional[str] = None) -> Signals:
        """The measured record and the model simulated at the estimate (as
        the report simulates it), a :class:`Signals`: ``time`` (s),
        ``measured``, ``fitted`` and ``residual`` (n × sensors, each
        sensor's SI unit), ``from_`` (the first time fitted, s);
        ``to_pandas()`` makes a DataFrame of them. For a campaign: the
        fitted experiment named ``experiment`` (default: the first
        fitted one; validation experiments are not included). Raises
        ``KeyError`` for an experiment that was not fitted."""
        records = self._all_signals()
        if experiment is None:
            return records[0]
        for r in records:
            if r.experiment == experiment:
                return r
        raise KeyError(f"no fitted experiment {experiment!r} (fitted: {[r.experiment for r in records]})")

    def _all_signals(self) -> List[Signals]:
        """Every fitted record at the estimate, simulated once and kept."""
        if getattr(self, "_signals", None) is None:
            self._signals = _signals_of(self._native)
        return self._signals

    @property
    def figures(self) -> Dict[str, Any]:
        """The report's figures without matplotlib: a dict file name
        (``"fit.svg"``, ...) -> an ``IPython.display.SVG`` (Jupyter shows
        it), or the SVG text (a ``str``) where IPython is not installed.
        Rendered as :meth:`report` renders them, nothing written."""
        return _report_figures(self._native)

    def plot_fit(self, *, experiment: Optional[str] = None, figsize: Optional[Tuple[float, float]] = None) -> Any:
        """Measured against fitted per sensor (SI units, time in s), a
        matplotlib ``Figure``: see :func:`rfeid.plot.plot_fit`. Needs
        matplotlib (``pip install "rfeid[plot]"``)."""
        from .plot import plot_fit

        return plot_fit(self, experiment=experiment, figsize=figsize)

    def plot_residual_spectra(
        self,
        *,
        segment: Optional[int] = None,
        experiment: Optional[str] = None,
        measured: bool = True,
        figsize: Optional[Tuple[float, float]] = None,
    ) -> Any:
        """The residuals' PSD per sensor over the fitted part, (SI unit)^2/Hz
        against Hz on log axes (Welch, Hann, ``segment`` samples), a
        matplotlib ``Figure``: see :func:`rfeid.plot.plot_residual_spectra`.
        Needs matplotlib (``pip install "rfeid[plot]"``)."""
        from .plot import plot_residual_spectra

        return plot_residual_spectra(self, segment=segment, experiment=experiment, measured=measured, figsize=figsize)

    def plot_correlation(self, *, annotate: Optional[bool] = None, figsize: Optional[Tuple[float, float]] = None) -> Any:
        """The correlation matrix (dimensionless, colours fixed to [-1, 1],
        values written in up to 20 parameters), a matplotlib ``Figure``:
        see :func:`rfeid.plot.plot_correlation`. Needs matplotlib (``pip
        install "rfeid[plot]"``)."""
        from .plot import plot_correlation

        return plot_correlation(self, annotate=annotate, figsize=figsize)

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


class Frf:
    """FRFs of the linearised model (from :meth:`Identification.frf`).

    Attributes:
        document: the study as a dict: ``linearised_at`` (``"rest"`` or
            ``"static equilibrium"``), ``notes`` (what the linearisation
            keeps of each nonlinear law), ``frequencies_hz`` and ``pairs``
            (each with ``excitation``, ``output``, ``unit``, ``magnitude``,
            ``phase_deg``, ``real``, ``imag``, ``band`` and ``measured``).
        svg: the figure (magnitude, phase, coherence per pair) as SVG text,
            or ``None`` if nothing could be drawn.
    """

    def __init__(self, document: Dict[str, Any], svg: Optional[str]) -> None:
        self.document = document
        self.svg = svg

    @property
    def frequencies(self) -> np.ndarray:
        """The model's frequencies, Hz (numpy array)."""
        return np.asarray(self.document["frequencies_hz"], dtype=float)

    @property
    def pairs(self) -> List[Tuple[str, str]]:
        """The (excitation, output) pairs, in order."""
        return [(p["excitation"], p["output"]) for p in self.document["pairs"]]

    def response(self, output: str, excitation: Optional[str] = None) -> np.ndarray:
        """The model's complex FRF to ``output`` (a sensor's name) from
        ``excitation`` (default: the first), a numpy complex array on
        :attr:`frequencies`, in the reading's unit per newton."""
        p = self._pair(output, excitation)
        return np.asarray(p["real"], dtype=float) + 1j * np.asarray(p["imag"], dtype=float)

    def band(self, output: str, excitation: Optional[str] = None) -> Optional[Tuple[np.ndarray, np.ndarray]]:
        """The 95 % band of |H| to ``output``: (lower, upper) numpy arrays,
        or ``None`` without standard errors."""
        b = self._pair(output, excitation).get("band")
        if b is None:
            return None
        return np.asarray(b["magnitude_lo"], dtype=float), np.asarray(b["magnitude_hi"], dtype=float)

    def _pair(self, output: str, excitation: Optional[str]) -> Dict[str, Any]:
        for p in self.document["pairs"]:
            if p["output"] == output and excitation in (None, p["excitation"]):
                return p
        raise KeyError(f"no FRF to {output!r}" + (f" from {excitation!r}" if excitation else "") + f"; pairs: {self.pairs}")

    def to_pandas(self) -> Any:
        """The FRFs as a long pandas DataFrame, one row per pair, curve and
        frequency, with the columns of ``rfeid frf -o``'s CSV
        (``curve`` is ``"model"`` or ``"H1 measured"``; NaN where absent)."""
        import pandas as pd

        rows: List[Dict[str, Any]] = []
        f = self.document["frequencies_hz"]
        for p in self.document["pairs"]:
            b = p.get("band") or {}
            for k, fk in enumerate(f):
                rows.append(
                    {
                        "excitation": p["excitation"], "output": p["output"], "curve": "model",
                        "frequency_hz": fk, "magnitude": p["magnitude"][k], "phase_deg": p["phase_deg"][k],
                        "real": p["real"][k], "imag": p["imag"][k],
                        "magnitude_lo95": b.get("magnitude_lo", [np.nan] * len(f))[k],
                        "magnitude_hi95": b.get("magnitude_hi", [np.nan] * len(f))[k],
                        "phase_lo95_deg": b.get("phase_lo_deg", [np.nan] * len(f))[k],
                        "phase_hi95_deg": b.get("phase_hi_deg", [np.nan] * len(f))[k],
                        "coherence": np.nan, "random_error": np.nan,
                    }
                )
            for m in p["measured"]:
                for k, fk in enumerate(m["frequencies_hz"]):
                    rows.append(
                        {
                            "excitation": p["excitation"], "output": p["output"], "curve": f"H1 {m['label']}",
                            "frequency_hz": fk, "magnitude": m["magnitude"][k], "phase_deg": m["phase_deg"][k],
                            "real": m["real"][k], "imag": m["imag"][k],
                            "magnitude_lo95": np.nan, "magnitude_hi95": np.nan,
                            "phase_lo95_deg": np.nan, "phase_hi95_deg": np.nan,
                            "coherence": m["coherence"][k], "random_error": m["random_error"][k],
                        }
                    )
        return pd.DataFrame(rows)

    def plot(self, path: PathLike) -> str:
        """Writes the figure (SVG) to ``path``; returns the path, a ``str``."""
        if self.svg is None:
            raise ValueError("the FRFs have no positive magnitude to draw")
        path = os.fspath(path)
        with open(path, "w", encoding="utf-8") as f:
            f.write(self.svg)
        return path

    def _repr_svg_(self) -> Optional[str]:
        return self.svg

    def __repr__(self) -> str:
        d = self.document
        f = d["frequencies_hz"]
        return (
            f"<rfeid.Frf: {len(d['pairs'])} pairs, {len(f)} frequencies {f[0]:.4g}–{f[-1]:.4g} Hz, "
            f"linearised at {d['linearised_at']}>"
        )


def design(
    model: Union[Model, PathLike],
    *,
    set: SetValues = None,
    choose: Optional[int] = None,
    over_box: Optional[int] = None,
    threads: Optional[int] = None,
) -> "Design":
    """What a test will give before it is run, as ``rfeid design`` (SPEC §6).

    Returns a :class:`Design`: the predicted standard errors (SI) and, with
    ``choose``, the sensors chosen and the D-efficiency they are
    guaranteed; the same document as ``rfeid design -o``.

    Predicts the Cramér–Rao standard errors of the placed sensors (each
    sensor's ``noise`` in the model file, its standard deviation in the
    sensor's SI unit) at the parameters' values (or at ``set``, inside the
    box); ``choose=K`` adds the D-optimal K of the candidate sensors
    (``candidate = true``), with a bound on how far from optimal the
    choice can be; ``over_box=N`` chooses for the average over N LP_τ
    points of the box (needs ``choose``); ``threads``: worker threads (all
    cores).

    ``model`` is a :class:`Model`, or the path of a model file: a file is
    read for the design, so before a first test its sensors may all be
    candidates (``candidate = true``), which :meth:`Model.load` refuses;
    ``choose=K`` then chooses all K and compares them with no sensor.

    Raises ``ValueError`` for ``choose=0``, ``threads`` outside 1 to 1024
    or ``over_box`` without ``choose``, ``TypeError`` naming the keyword for
    a value of the wrong type (``choose=True``, ``threads=2.0``), :class:`ModelError` for a model without candidate sensors
    (with ``choose``) or a ``set`` value outside its box. Ctrl-C raises
    ``KeyboardInterrupt`` within about a second.
    """
    if isinstance(model, (str, os.PathLike)):
        native_model = _rfeid.Model.load_for_design(os.fspath(model))
    elif isinstance(model, Model):
        native_model = model._native
    else:
        raise TypeError(
            f"model: expected rfeid.Model or a path, not {type(model).__name__}"
        )
    native, notes = _rfeid.design(
        native_model,
        set=_set_list(set),
        choose=_int("choose", choose, True),
        over_box=_int("over_box", over_box, True),
        threads=_int("threads", threads, True),
    )
    for note in notes:
        warnings.warn(note, stacklevel=2)
    return Design(native)


class Design:
    """The result of :func:`design`: the document of ``rfeid design -o``.

    Attributes:
        document: the design's document as a dict (SI values).

    ``repr()`` lists the predicted relative standard errors and the
    sensors chosen.
    """

    def __reduce__(self) -> Any:
        raise TypeError(
            "an rfeid.Design holds its model in native memory and cannot be pickled: pass "
            "design.to_json() (or design.document) instead"
        )

    def __init__(self, native: _rfeid.Design) -> None:
        self._native = native
        self.document: Dict[str, Any] = json.loads(native.to_json())
        # The design's document as a dict.

    @property
    def chosen(self) -> List[str]:
        """The names of the candidate sensors chosen (a list of ``str``;
        empty without ``choose``)."""
        return list(self.document["chosen"])

    @property
    def std_errors(self) -> Dict[str, Optional[float]]:
        """Predicted standard errors: a dict parameter name -> ``float``
        in the parameter's SI unit (``None`` where undefined), with the
        chosen sensors added to the placed ones (the placed sensors'
        alone without ``choose``)."""
        return {p["name"]: p["std_error"] for p in self.document["parameters"]}

    @property
    def placed_std_errors(self) -> Dict[str, Optional[float]]:
        """Predicted standard errors of the placed sensors alone: a dict
        parameter name -> ``float`` in SI (``None`` where undefined)."""
        return {p["name"]: p["std_error"] for p in self.document["placed"]["parameters"]}

    @property
    def efficiency_at_least(self) -> Optional[float]:
        """The D-efficiency the choice is guaranteed, a fraction from 0 to
        1 (det F of the choice against the best possible, per parameter:
        0.93 means no choice of as many candidates gives more than 1/0.93
        times the information per parameter); ``None`` without
        ``choose``."""
        choice = self.document.get("choice")
        return None if choice is None else choice["efficiency_at_least"]

    def to_json(self) -> str:
        """Returns the design's text (a ``str`` of JSON, SI values): the
        same document as ``rfeid design -o`` writes."""
        return self._native.to_json()

    def report(self, directory: PathLike) -> str:
        """Writes the HTML report (the candidates on the bodies, the
        predicted relative standard errors) into ``directory`` by the rules
        of ``rfeid design --report DIR``: a new directory (its parent must
        exist) or one holding only an earlier report, replaced as a whole;
        anything else (``"."``, the model's directory) is refused with
        ``ValueError``, a failed write raises ``OSError``. Returns
        report.html's path, a ``str``."""
        return os.fspath(self._native.report(os.fspath(directory)))

    def plot(self, *, figsize: Optional[Tuple[float, float]] = None) -> Any:
        """Predicted relative standard errors per parameter (%, log axis),
        placed sensors against with the chosen ones, a matplotlib
        ``Figure``: see :func:`rfeid.plot.plot_design`. Needs matplotlib
        (``pip install "rfeid[plot]"``)."""
        from .plot import plot_design

        return plot_design(self, figsize=figsize)

    def __repr__(self) -> str:
        rel = {p["name"]: p.get("relative_std_error") for p in self.document["parameters"]}
        parts = ", ".join(
            f"{n} {100 * r:.3g} %" if r is not None else f"{n} -" for n, r in rel.items()
        )
        chosen = f", chosen {self.chosen}" if self.chosen else ""
        return f"<rfeid.Design: relative s.e. {parts}{chosen}>"
