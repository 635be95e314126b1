"""Type stubs of the package pim (see the module docstring for the case format)."""

import os
from typing import Any, Dict, List, Literal, Optional, Sequence, Union

__version__: str

Case = Union[str, "os.PathLike[str]", Dict[str, Any]]
Cost = Literal["q1", "q2", "q3"]
Branch = Literal["free", "zero"]
MomentForm = Literal["corrected", "brach1983"]
Model = Literal["pim", "tangential"]

class InputError(ValueError):
    """Bad input or an argument out of range; the message names the file, line and field."""

class NoSolution(Exception):
    """The model has no answer; for a fit, ``document`` holds the fit's document."""

    document: Dict[str, Any]

def solve(case: Case, no_slip: bool = False, moment_form: MomentForm = "corrected") -> Dict[str, Any]:
    """Solve a case forwards ([initial]) or backwards ([final]) with its [coefficients]."""

def fit(
    case: Case,
    cost: Optional[Cost] = None,
    branches: Sequence[Branch] = ("free", "zero"),
    moment_form: MomentForm = "corrected",
    model: Model = "pim",
) -> Dict[str, Any]:
    """Fit the coefficients (and velocities) of a case under a cost function."""

def batch(
    path: Union[str, "os.PathLike[str]"] = "data/ricsac.csv",
    costs: Sequence[Cost] = ("q1", "q2", "q3"),
    branches: Sequence[Branch] = ("free", "zero"),
    threads: Optional[int] = None,
    e_max: float = 0.2,
    moment_form: MomentForm = "corrected",
    tests: Optional[Sequence[int]] = None,
    models: Sequence[Model] = ("pim",),
) -> List[Dict[str, Any]]:
    """Refit every test of a RICSAC-style data file; one record per test, cost, model and branch."""

def uncertainty(
    case: Case,
    cost: Optional[Cost] = None,
    draws: int = 200,
    seed: int = 1,
    threads: Optional[int] = None,
) -> Dict[str, Any]:
    """Parametric bootstrap of the case's stated uncertainties through the fit."""

def predict_dv(path: Union[str, "os.PathLike[str]"] = "data/ricsac.csv", e: float = 0.0) -> Dict[str, Any]:
    """Brach (1984) section 6: delta-V predicted for every test of a data file."""

class Report:
    """The report of a crash: ``html`` (one self-contained page) and ``markdown``."""

    html: str
    markdown: str
    def _repr_html_(self) -> str: ...
    def save(self, path: Union[str, "os.PathLike[str]"]) -> None: ...

def report(
    case: Case,
    cost: Optional[Literal["q1", "q2", "q3"]] = None,
    draws: Optional[int] = None,
    seed: Optional[int] = None,
    units: Optional[Literal["si", "us", "kmh"]] = None,
    solve: bool = False,
) -> Report:
    """The report of ``pim report`` for a case (HTML and Markdown)."""

class SVG(str):
    """SVG text that a notebook shows as a picture; otherwise a ``str``."""

    def _repr_svg_(self) -> str: ...

def draw(
    case: Case,
    no_slip: bool = False,
    moment_form: MomentForm = "corrected",
    units: Optional[Literal["si", "us", "kmh"]] = None,
) -> SVG:
    """The scale diagram of ``pim draw`` as SVG text, labelled in the case's units or ``units``."""

def records_frame(
    records: Union[List[Dict[str, Any]], Dict[str, Any]],
    units: Literal["si", "us", "kmh"] = "si",
) -> Any:
    """A pandas DataFrame with one row per record and flat, unit-suffixed columns (SI, or
    converted to ``units`` with the suffixes renamed: ``_mph``, ``_degps``, ``_ftlbf``, ...)."""
