"""The fitted records at the estimate (:class:`Signals`), and the report's
figures without matplotlib (:func:`report_figures`)."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Dict, List

import numpy as np


@dataclass
class Signals:
    """A fitted record with the model simulated at the estimate, as
    :meth:`rfeid.Identification.signals` returns it (the simulation the
    report draws: the same numbers as its fit figure).

    Attributes:
        experiment: the campaign's experiment, or ``""`` for one record.
        time: the sample instants, s (a numpy array of n floats from 0 in
            steps of 1/``sample_rate``).
        names: the sensors' names, in the model's order.
        units: the sensors' SI units (``"m"``, ``"m/s"``, ``"m/s^2"``).
        measured: the measured readings, a numpy array n × sensors (column
            i the sensor ``names[i]`` in ``units[i]``).
        fitted: the model at the estimate, n × sensors, likewise.
        sample_rate: Hz.
        from_: the first time fitted, s (RESULT.json's ``from``, or the
            experiment's); the samples before it were not fitted.
    """

    experiment: str
    time: np.ndarray
    names: List[str]
    units: List[str]
    measured: np.ndarray
    fitted: np.ndarray
    sample_rate: float
    from_: float

    @property
    def residual(self) -> np.ndarray:
        """measured − fitted, n × sensors, in each sensor's SI unit."""
        return self.measured - self.fitted

    @property
    def first_fitted(self) -> int:
        """The index of the first sample fitted (the one at ``from_``)."""
        dt = 1.0 / self.sample_rate
        return int(np.searchsorted(self.time, self.from_ - 0.5 * dt))

    def to_pandas(self) -> Any:
        """Returns a pandas DataFrame indexed by ``time`` (s) with
        two-level columns: ``"measured"``, ``"fitted"`` and ``"residual"``,
        each with a column per sensor (SI), so ``df["residual"]["knee_ax"]``
        is one sensor's residual. Needs pandas."""
        import pandas as pd

        parts = {"measured": self.measured, "fitted": self.fitted, "residual": self.residual}
        frame = pd.concat(
            {k: pd.DataFrame(v, columns=self.names) for k, v in parts.items()}, axis=1
        )
        frame.index = pd.Index(self.time, name="time")
        return frame

    def __repr__(self) -> str:
        what = f"experiment {self.experiment}, " if self.experiment else ""
        return (
            f"<rfeid.Signals: {what}{len(self.time)} samples × {len(self.names)} sensors "
            f"({', '.join(self.names)}), fitted from {self.from_:g} s>"
        )


def _floats(data: bytes) -> np.ndarray:
    return np.frombuffer(data, dtype="<f8").astype(np.float64)


def signals_of(native: Any) -> List[Signals]:
    """Every fitted record of a native Identification, as :class:`Signals`."""
    out = []
    for experiment, names, units, rate, start, time, measured, fitted in native.signals():
        t = _floats(time)
        n, c = len(t), len(names)
        out.append(
            Signals(
                experiment=experiment,
                time=t,
                names=list(names),
                units=list(units),
                measured=_floats(measured).reshape(c, n).T.copy(),
                fitted=_floats(fitted).reshape(c, n).T.copy(),
                sample_rate=rate,
                from_=start,
            )
        )
    return out


def report_figures(native: Any) -> Dict[str, Any]:
    """The report's SVG figures: file name -> an ``IPython.display.SVG``
    (shown by Jupyter), or the SVG text where IPython is not installed."""
    try:
        from IPython.display import SVG
    except ImportError:
        SVG = None
    out: Dict[str, Any] = {}
    for name, text in native.report_files():
        if name.endswith(".svg"):
            out[name] = text if SVG is None else SVG(data=text)
    return out
