"""The native module of rfeid (Rust, PyO3); use the package ``rfeid``.

Arrays cross as little-endian float64 bytes (``numpy.frombuffer`` reads
them); every number is SI (N, m, kg, s, rad and their products).
"""
import os
import pathlib
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union

__version__: str
"""The version of the library and of the command line it was built with."""

class ModelError(ValueError):
    """A model file, or a setting of the model (``set``, ``tolerance``, …), that cannot be used."""

class DataError(ValueError):
    """Measured data that do not fit the model: a missing column, another sample rate, a value that is not finite."""

class IdentificationError(RuntimeError):
    """An identification or simulation that could not be done."""

class Model:
    """A model file, loaded and validated."""

    @staticmethod
    def load(path: Union[str, "os.PathLike[str]"]) -> "Model":
        """Loads a model file (TOML, SPEC §1); returns the model. Raises
        ModelError naming the file, entry and field of a problem."""
    @staticmethod
    def load_for_design(path: Union[str, "os.PathLike[str]"]) -> "Model":
        """Loads a model file for a design: its sensors may all be
        candidates (before a first test)."""
    @staticmethod
    def from_toml(text: str, base_dir: Optional[Union[str, "os.PathLike[str]"]] = None) -> "Model":
        """A model from the text of a model file; relative paths in it
        (signal tables) are found from ``base_dir`` (default: the current
        directory). Returns the model; raises ModelError."""
    @property
    def path(self) -> Optional[pathlib.Path]:
        """The file the model came from (``None`` for a text)."""
    @property
    def notes(self) -> List[str]:
        """What the reading noted (a table's time axis taken on the grid, say)."""
    @property
    def parameters(self) -> List[Dict[str, Any]]:
        """The parameters, each a dict: name, value, min, max (SI; ``None``
        for a fixed one), unit (as written; ``""`` for a bare number),
        unit_scale (one unit in SI), scale (``"linear"`` or ``"log"``),
        dimension (the SI unit as text), identified, per_experiment."""
    @property
    def sensor_names(self) -> List[str]:
        """The sensors' names, in the model's order."""
    @property
    def sensor_units(self) -> List[str]:
        """The sensors' SI units (``"m"``, ``"m/s"``, ``"m/s^2"``), in the model's order."""
    @property
    def sample_rate(self) -> float:
        """The sample rate, Hz."""
    @property
    def duration(self) -> float:
        """The record's length, s."""
    @property
    def n_samples(self) -> int:
        """The number of samples in the record: round(duration × sample_rate)."""
    @property
    def experiments(self) -> List[Tuple[str, str, pathlib.Path]]:
        """The ``[[experiment]]`` entries (a campaign) as (name, role
        ``"fit"`` or ``"validation"``, data file); empty if none."""
    def simulate(
        self,
        set: List[str],
        noise: Optional[float],
        noise_corner: Optional[float],
        seed: int,
        tolerance: Optional[float],
        substeps: Optional[int],
    ) -> Tuple[bytes, bytes, int, int, List[str]]:
        """Simulates at the nominal values with ``set`` (``NAME=VALUE``)
        applied, as ``rfeid simulate`` does: ``noise`` a fraction of each
        sensor's RMS, ``noise_corner`` Hz, ``tolerance`` a relative error,
        ``substeps`` steps per sample. Returns (time, values, n_samples,
        n_sensors, warnings): time in s and values in the sensors' SI units
        as little-endian float64 bytes, values sensor by sensor."""

class Identification:
    """An identification's result with what its report needs."""

    def to_json(self) -> str:
        """Returns the result as RESULT.json holds it (JSON text, SI values)."""
    def verdict(self) -> Optional[Tuple[str, List[str]]]:
        """The verdict (SPEC §4) as (outcome, reasons): the outcome
        ``"trustworthy"``, ``"suspect"`` or ``"model error"``, each reason
        in words; ``None`` when no verdict was reached."""
    def report(self, dir: Union[str, "os.PathLike[str]"]) -> pathlib.Path:
        """Writes the HTML report (report.html and its SVG figures) into
        ``dir``, created if missing (its parent must exist); returns
        report.html's path."""
    def frf(
        self,
        fmin: Optional[float] = None,
        fmax: Optional[float] = None,
        points: Optional[int] = None,
        spacing: str = "log",
        segment: Optional[int] = None,
        measured: bool = True,
    ) -> Tuple[str, Optional[str]]:
        """FRFs of the linearised model at the estimate, with the 95 % band
        and the measured H1 and coherence: (JSON text, SVG text or None)."""
    def report_files(self) -> List[Tuple[str, str]]:
        """The report's files as (name, text), report.html and its SVG
        figures, as ``report`` writes them (nothing written)."""
    def signals(self) -> List[Tuple[str, List[str], List[str], float, float, bytes, bytes, bytes]]:
        """The fitted records with the model simulated at the estimate (as
        the report does), one record or each fitted experiment of a
        campaign: (experiment or ``""``, sensor names, SI units, sample
        rate Hz, first time fitted s, time s, measured, fitted), the arrays
        as little-endian float64 bytes, the signals sensor by sensor."""

def identify(
    model: Model,
    data: Optional[Union[str, "os.PathLike[str]", Tuple[str, bytes, List[str], Sequence[bytes]]]],
    *,
    set: List[str],
    options: Dict[str, Any],
    tolerance: Optional[float],
    substeps: Optional[int],
    progress: Optional[Callable[[int, int, int, int, int, float], None]],
    experiments: Sequence[Tuple[str, Union[str, "os.PathLike[str]", Tuple[str, bytes, List[str], Sequence[bytes]]]]] = (),
) -> Tuple[Identification, List[str]]:
    """Identifies ``model``'s parameters from ``data`` (a data file, or a
    table: label, time in s, column names, columns in SI, the arrays as
    little-endian float64 bytes) as ``rfeid identify`` does; a campaign
    (a model with ``[[experiment]]`` entries) takes ``data=None`` and
    ``experiments``, data by experiment name in place of their files.
    ``options`` holds the search's keywords, one key each (``plan``,
    ``starts``, ``method``, ``weights``, ``noise_model``, ``window``,
    ``from`` in s, ``threads``, ``start``, ``jacobian_memory`` MiB,
    ``profiles``, ``profile_points``); ``tolerance`` is a relative error,
    ``substeps`` steps per sample; ``progress`` is called as
    progress(plan points done, plan points, local search (from 1; 0: the
    plan), local searches, iteration, J) every 50 ms and once at the end.
    Returns the result and the notes of the reading."""

class Design:
    """A design with its model, for the report."""

    def to_json(self) -> str:
        """Returns the design as ``rfeid design -o`` writes it (JSON text, SI values)."""
    def report(self, dir: Union[str, "os.PathLike[str]"]) -> pathlib.Path:
        """Writes the HTML report (the candidates on the bodies, the
        predicted standard errors) into ``dir``, created if missing (its
        parent must exist); returns report.html's path."""

def design(
    model: Model,
    *,
    set: List[str],
    choose: Optional[int],
    over_box: Optional[int],
    threads: Optional[int],
) -> Tuple[Design, List[str]]:
    """Designs a test of ``model`` as ``rfeid design`` does: ``set``
    (``NAME=VALUE``) inside the box, ``choose`` candidates added,
    ``over_box`` LP_τ points. Returns the design and the notes of the
    settings."""
