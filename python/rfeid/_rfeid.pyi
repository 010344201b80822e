"""The native module of rfeid (Rust, PyO3); use the package ``rfeid``."""
import pathlib
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union

__version__: str

class ModelError(ValueError):
    """A model file or a setting of the model that cannot be used."""

class DataError(ValueError):
    """Measured data that do not fit the model."""

class IdentificationError(RuntimeError):
    """An identification or simulation that could not be done."""

class Model:
    @staticmethod
    def load(path: str) -> "Model": ...
    @staticmethod
    def from_toml(text: str, base_dir: Optional[str] = None) -> "Model": ...
    @property
    def path(self) -> Optional[pathlib.Path]: ...
    @property
    def notes(self) -> List[str]: ...
    @property
    def parameters(self) -> List[Dict[str, Any]]: ...
    @property
    def sensor_names(self) -> List[str]: ...
    @property
    def sensor_units(self) -> List[str]: ...
    @property
    def sample_rate(self) -> float: ...
    @property
    def duration(self) -> float: ...
    @property
    def n_samples(self) -> int: ...
    @property
    def experiments(self) -> List[str]: ...
    def simulate(
        self,
        set: List[str],
        noise: Optional[float],
        noise_corner: Optional[float],
        seed: int,
        tolerance: Optional[float],
        substeps: Optional[int],
    ) -> Tuple[bytes, bytes, int, int, List[str]]: ...

class Identification:
    def to_json(self) -> str: ...
    def verdict(self) -> Optional[Tuple[str, List[str]]]: ...
    def report(self, dir: str) -> pathlib.Path: ...

def identify(
    model: Model,
    data: Union[str, Tuple[str, bytes, List[str], Sequence[bytes]]],
    *,
    set: List[str],
    plan: int,
    starts: int,
    method: str,
    weights: Optional[str],
    noise_model: str,
    window: Optional[float],
    from_: float,
    threads: Optional[int],
    start: str,
    tolerance: Optional[float],
    substeps: Optional[int],
    jacobian_memory: Optional[int],
    progress: Optional[Callable[[int, int, int, int, int, float], None]],
) -> Tuple[Identification, List[str]]: ...

class Design:
    def to_json(self) -> str: ...
    def report(self, dir: str) -> pathlib.Path: ...

def design(
    model: Model,
    *,
    set: List[str],
    choose: Optional[int],
    over_box: Optional[int],
    threads: Optional[int],
) -> Tuple[Design, List[str]]: ...
