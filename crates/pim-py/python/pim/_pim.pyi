"""Type stubs of the compiled part of the package (``pim._pim``); users call the wrappers
of the package ``pim``, which return typed results."""

import os
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union

__all__ = [
    "__version__",
    "InputError",
    "NoSolution",
    "solve",
    "report",
    "fit",
    "batch",
    "batch_csv",
    "uncertainty",
    "predict_dv",
    "draw",
    "edit_case",
    "case_version",
    "runout",
    "reconstruct",
    "reconstruct_uncertainty",
    "reconstruct_many",
]

__version__: str

_Case = Union[str, "os.PathLike[str]", Dict[str, Any]]
_PathArg = Union[str, "os.PathLike[str]"]

class InputError(ValueError):
    """Bad input or an argument out of range; the message names the file, line and field."""

class NoSolution(Exception):
    """The model has no answer; for a fit, ``document`` holds the fit's document."""

    document: Dict[str, Any]

def solve(case: _Case, no_slip: bool = ..., moment_form: str = ...) -> Dict[str, Any]: ...
def fit(
    case: _Case,
    cost: Optional[str] = ...,
    branches: Sequence[str] = ...,
    moment_form: str = ...,
    model: str = ...,
) -> Dict[str, Any]: ...
def batch(
    path: _PathArg = ...,
    costs: Sequence[str] = ...,
    branches: Sequence[str] = ...,
    threads: Optional[int] = ...,
    e_max: float = ...,
    moment_form: str = ...,
    tests: Optional[Sequence[int]] = ...,
    models: Sequence[str] = ...,
    conditions: str = ...,
) -> List[Dict[str, Any]]: ...
def reconstruct_many(
    names: Sequence[str], texts: Sequence[str], threads: Optional[int] = ...
) -> str: ...
def batch_csv(
    text: str,
    name: str = ...,
    costs: Sequence[str] = ...,
    branches: Sequence[str] = ...,
    threads: Optional[int] = ...,
    e_max: float = ...,
    moment_form: str = ...,
    models: Sequence[str] = ...,
    conditions: str = ...,
) -> str: ...
def uncertainty(
    case: _Case,
    cost: Optional[str] = ...,
    draws: Optional[int] = ...,
    seed: Optional[int] = ...,
    threads: Optional[int] = ...,
    model: str = ...,
    progress: Optional[Callable[[int, int, str], Any]] = ...,
) -> Dict[str, Any]: ...
def predict_dv(path: _PathArg = ..., e: float = ...) -> Dict[str, Any]: ...
def report(
    case: _Case,
    cost: Optional[str] = ...,
    draws: Optional[int] = ...,
    seed: Optional[int] = ...,
    units: Optional[str] = ...,
    solve: bool = ...,
) -> Tuple[str, str]: ...
def draw(
    case: _Case,
    no_slip: bool = ...,
    moment_form: str = ...,
    units: Optional[str] = ...,
) -> str: ...
def runout(
    case: _Case,
    source: Optional[str] = ...,
    cost: Optional[str] = ...,
    sample: float = ...,
    draw: bool = ...,
    every: float = ...,
    units: Optional[str] = ...,
    wheels: bool = ...,
) -> Tuple[Dict[str, Any], Optional[str]]: ...
def reconstruct(
    case: _Case,
    branches: List[str] = ...,
    model: str = ...,
    draw: bool = ...,
    units: Optional[str] = ...,
) -> Tuple[Dict[str, Any], Optional[str]]: ...
def reconstruct_uncertainty(
    case: _Case,
    draws: Optional[int] = ...,
    seed: Optional[int] = ...,
    threads: Optional[int] = ...,
    model: str = ...,
    progress: Optional[Callable[[int, int, str], Any]] = ...,
) -> Dict[str, Any]: ...
def edit_case(
    path: _PathArg, values: Dict[str, Any], write: bool = ..., if_version: Optional[str] = ...
) -> str: ...
def case_version(path: _PathArg) -> str: ...
