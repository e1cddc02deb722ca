"""Type stubs of the swimbot package (see ``swimbot/__init__.py``)."""

from os import PathLike
from typing import Any, Dict, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

class SwimbotError(ValueError):
    """Bad input: the message names the file, the case and the field."""

class Dataset:
    @property
    def name(self) -> str: ...
    @property
    def source(self) -> str: ...
    @property
    def ids(self) -> list[str]: ...
    @property
    def note(self) -> Optional[str]: ...
    def __len__(self) -> int: ...
    @classmethod
    def from_pandas(
        cls, df: Any, setup: Optional[Mapping[str, Any]] = ..., name: str = ...
    ) -> Dataset: ...

_Path = Union[str, PathLike[str]]
_DataLike = Union[Dataset, _Path, None]
_Floats = Union[float, npt.ArrayLike]

def load(path: _Path, decimal_comma: bool = ...) -> Dataset: ...
def paper() -> Dataset: ...

class _Result:
    def to_dict(self) -> dict[str, Any]: ...
    def to_pandas(self) -> Any: ...
    @property
    def figures(self) -> list[str]: ...
    def _repr_html_(self) -> str: ...

class Comparison(_Result):
    @property
    def mare(self) -> float: ...
    @property
    def mare_percent(self) -> float: ...
    @property
    def chi2_reduced(self) -> float: ...
    @property
    def model(self) -> str: ...

class Diagnosis(_Result):
    @property
    def trends(self) -> list[dict[str, Any]]: ...
    @property
    def verdict(self) -> Any: ...

class Fit(_Result):
    @property
    def estimates(self) -> list[dict[str, Any]]: ...
    @property
    def comparison(self) -> dict[str, Any]: ...
    @property
    def mare(self) -> float: ...
    @property
    def mare_percent(self) -> float: ...
    @property
    def chi2_reduced(self) -> float: ...

class Audit(_Result):
    @property
    def flags(self) -> list[dict[str, Any]]: ...

def compare(
    ds: _DataLike = ...,
    preset: Optional[str] = ...,
    effects: Sequence[str] = ...,
    effect_files: Sequence[_Path] = ...,
    input_uncertainty: bool = ...,
    mc_draws: int = ...,
) -> Comparison: ...
def diagnose(
    ds: _DataLike = ...,
    preset: Optional[str] = ...,
    effects: Sequence[str] = ...,
    effect_files: Sequence[_Path] = ...,
    discovery: bool = ...,
    pairs: bool = ...,
    input_uncertainty: bool = ...,
    extra_args: Sequence[str] = ...,
) -> Diagnosis: ...
def fit(
    ds: _DataLike = ...,
    effects: Sequence[str] = ...,
    preset: Optional[str] = ...,
    effect_files: Sequence[_Path] = ...,
    cases: Sequence[str] = ...,
) -> Fit: ...
def audit(
    ds: _DataLike = ...,
    preset: Optional[str] = ...,
    effects: Sequence[str] = ...,
    family_samples: Optional[int] = ...,
    seed: Optional[int] = ...,
) -> Audit: ...
def sweep(
    wavelength_mm: Optional[_Floats] = ...,
    amplitude_mm: Optional[_Floats] = ...,
    tail_length_mm: Optional[_Floats] = ...,
    frequency_hz: Optional[_Floats] = ...,
    *,
    data: Optional[Dataset] = ...,
    case: Optional[str] = ...,
    preset: Optional[str] = ...,
    effects: Sequence[str] = ...,
    study: Optional[Study] = ...,
) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...

MAX_SWEEP_GEOMETRIES: int

class Study:
    @classmethod
    def init(
        cls,
        path: _Path,
        data: _Path,
        preset: str = ...,
        likelihood: str = ...,
        force: bool = ...,
        diagnose: bool = ...,
    ) -> Study: ...
    @classmethod
    def open(cls, path: _Path = ...) -> Study: ...
    @property
    def path(self) -> str: ...
    @property
    def dataset(self) -> Dataset: ...
    def steps(self) -> Dict[str, Any]: ...
    def add(
        self, effect: str, refit_all: bool = ..., force: bool = ..., diagnose: bool = ...
    ) -> Dict[str, Any]: ...
    def undo(self) -> Dict[str, Any]: ...
    def apply_to(self, ds: Dataset) -> Dict[str, Any]: ...
    def report(self, directory: _Path = ...) -> str: ...
    def sweep(self, **kwargs: Any) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
    def summary(self) -> list[dict[str, Any]]: ...
    def _repr_html_(self) -> str: ...
