"""Planar Impact Mechanics (Brach) for two-vehicle collision reconstruction, from Python.

The same solver, certified fit and documents as the ``pim`` command, made by the same Rust
code (nothing is re-implemented here). Results are typed objects read from the document that
``pim <command> --format json`` prints for the same input: :func:`fit` returns a
:class:`FitResult` (its ``branches`` and ``best``, each a :class:`Branch` with ``e``, ``mu``,
``em``, ``cost``, ``vehicles``, ``residuals``, ...), :func:`solve` a :class:`SolveResult`,
:func:`uncertainty` an :class:`Uncertainty`, :func:`batch` :class:`Records`. Each has
``to_dict()`` (the document, unchanged), ``to_frame()`` (a pandas DataFrame) and an HTML
table for notebooks; :func:`draw` returns an :class:`SVG` a notebook shows as a picture, and
:mod:`pim.plot` draws intervals and batch results with matplotlib. Units are SI: m/s,
rad/s, kg, m, J, degrees for angles.

    >>> best = fit("examples/cases/ricsac7_fit.toml", cost="q3").best
    >>> best.moment, round(best.e, 3), round(best.vehicles[0].delta_v, 2)
    ('zero', 0.051, 5.36)

A *case* is a case file of the ``pim`` command, given as TOML text, as a path (``str`` or
``os.PathLike``), or as a dict of the same shape::

    [vehicle1]                 # natural form: heading = where the nose points (deg)
    mass = 1036.0              # kg
    yaw_inertia = 1348.0       # kg m^2
    heading = 180.0
    impact_point = { x = 1.4, y = 0.15 }   # m from the CG, x forward, y to the left
    [vehicle2]                 # or: barrier = true (a fixed rigid barrier, nothing else)
    ...
    [impact]
    crush_angle = 0.0          # deg, the crush surface's normal
    [estimates.initial]        # fit: estimated velocities at contact (and [estimates.final])
    vehicle1 = { vx = -9.48, vy = 0.0, omega = 0.0 }

``pim solve --help`` and ``pim fit --help`` describe every section ([units], [sigma],
[known], [bounds], [[observations]], [uncertainty]).

Cost functions (``cost=``), after Vossou & Koulocheris (2018):

* ``"q1"``: the separation velocities are known exactly, the contact velocities estimated;
* ``"q2"``: the contact velocities are known exactly, the separation velocities estimated
  (Brach's fits);
* ``"q3"``: all twelve velocity components estimated;
* ``None``: the case's own ``[known]`` components held fixed, ``[estimates]`` estimated.

Each fit searches both moment branches: ``"free"`` (e_m in [-1, 0]) and ``"zero"`` (e_m = 1,
no moment impulse), and certifies the global optimum of each.

Errors: :class:`InputError` for bad input (the command line's message, naming the file and
field), :class:`NoSolution` when the model has no answer.
"""

from __future__ import annotations

import os
from typing import Any, Callable, Dict, Iterable, List, Literal, Mapping, Optional, Sequence, Union

from . import _pim
from ._frame import COLUMNS, SCENE_COLUMNS, fit_frame, scene_frame
from ._pim import InputError, NoSolution, __version__
from ._base import Motion, Velocities
from ._results import (
    Branch,
    ChiSquare,
    FitResult,
    Interval,
    Records,
    Residual,
    SolveResult,
    Uncertainty,
    Vehicle,
)
from ._damage import CrushVehicle, Damage, DamageFit, EnergyFit
from ._reconstruct import (
    ContactPose,
    CountsTried,
    Evidence,
    EvidenceSource,
    PhaseInterval,
    PhaseSpeeds,
    Reconstruction,
    ReconstructionStudy,
)
from ._runout import (
    RunoutCandidate,
    RunoutEstimate,
    RunoutResidual,
    RunoutResult,
    VehicleRunout,
)

__all__ = [
    "__version__",
    "COLUMNS",
    "CrushVehicle",
    "Damage",
    "DamageFit",
    "EnergyFit",
    "Branch",
    "ChiSquare",
    "FitResult",
    "InputError",
    "Interval",
    "Motion",
    "NoSolution",
    "Records",
    "Report",
    "Residual",
    "RunoutCandidate",
    "RunoutEstimate",
    "RunoutResidual",
    "RunoutResult",
    "ContactPose",
    "CountsTried",
    "Evidence",
    "EvidenceSource",
    "PhaseInterval",
    "PhaseSpeeds",
    "Reconstruction",
    "ReconstructionStudy",
    "reconstruct",
    "reconstruct_uncertainty",
    "SVG",
    "SolveResult",
    "Uncertainty",
    "Vehicle",
    "VehicleRunout",
    "Velocities",
    "batch",
    "draw",
    "edit_case",
    "case_version",
    "fit",
    "fit_frame",
    "scene_frame",
    "SCENE_COLUMNS",
    "predict_dv",
    "records_frame",
    "report",
    "runout",
    "solve",
    "uncertainty",
]

Case = Union[str, "os.PathLike[str]", Dict[str, Any]]
"""A case: TOML text, a path to a case file, or a dict of the same shape."""
PathArg = Union[str, "os.PathLike[str]"]
Cost = Literal["q1", "q2", "q3"]
MomentBranch = Literal["free", "zero"]
MomentForm = Literal["corrected", "brach1983"]
Model = Literal["pim", "tangential"]
Units = Literal["si", "us", "kmh"]
Progress = Callable[[int, int, str], Any]
"""A study's progress callback: ``progress(done, total, phase)``; a true return value cancels."""


def solve(case: Case, no_slip: bool = False, moment_form: MomentForm = "corrected") -> SolveResult:
    """Solves a case forwards ([initial] given) or backwards ([final] given) with its
    [coefficients] (``pim solve``). ``no_slip=True`` uses the no-slip friction basis;
    ``moment_form="brach1983"`` Brach's 1983 moment equation (with its sign error), for
    reproducing old results. Raises :class:`NoSolution` when the model has no answer.

    >>> s = solve("examples/cases/ricsac7_brach1983.toml")
    >>> round(s.vehicles[0].delta_v, 3), s.admissible
    (7.79, False)
    >>> s.reasons[0][:32]
    'mu = 0.968 is not between 0 and '
    """
    return SolveResult._read(_pim.solve(case, no_slip=no_slip, moment_form=moment_form))


def fit(
    case: Case,
    cost: Optional[Cost] = None,
    branches: Sequence[MomentBranch] = ("free", "zero"),
    moment_form: MomentForm = "corrected",
    model: Model = "pim",
) -> FitResult:
    """Fits the coefficients and the twelve velocities of a case (``pim fit``) under a cost
    function, certifying the global optimum of each moment branch (``branches``: ``"free"``,
    e_m in [-1, 0]; ``"zero"``, e_m = 1). ``cost``: ``"q1"`` (separation velocities known,
    contact velocities estimated), ``"q2"`` (contact known, separation estimated), ``"q3"``
    (all twelve estimated) or ``None`` (the case's own [known] components, its
    [estimates.initial] / [estimates.final], observations and sigmas).
    ``model="tangential"`` fits the second model.

    Raises :class:`NoSolution` when no branch has a solution; its ``document`` is the fit's
    document and its ``result`` the :class:`FitResult` read from it.

    >>> f = fit("examples/cases/ricsac7_fit.toml", cost="q2")
    >>> f.best.moment, round(f.best.cost, 4), round(f.branch("free").mu, 4)
    ('zero', 1.0694, 0.8874)
    >>> [b.status for b in f.branches]
    ['optimal', 'optimal']
    """
    try:
        document = _pim.fit(case, cost=cost, branches=list(branches), moment_form=moment_form,
                            model=model)
    except NoSolution as err:
        doc = getattr(err, "document", None)
        if isinstance(doc, dict):
            err.result = FitResult._read(doc)  # type: ignore[attr-defined]
        raise
    return FitResult._read(document)


def batch(
    path: PathArg = "data/ricsac.csv",
    costs: Sequence[Cost] = ("q1", "q2", "q3"),
    branches: Sequence[MomentBranch] = ("free", "zero"),
    threads: Optional[int] = None,
    e_max: float = 0.2,
    moment_form: MomentForm = "corrected",
    tests: Optional[Sequence[int]] = None,
    models: Sequence[Model] = ("pim",),
    conditions: Literal["corrected", "v18"] = "corrected",
) -> Records:
    """Refits every test of a RICSAC-style data file (``pim batch``): one record per test,
    cost function, model and branch, as :class:`Records` (a list of dicts with
    ``to_frame()``), in the same order for any ``threads``. ``conditions="v18"``: Vossou &
    Koulocheris (2018)'s setting (``pim batch --conditions v18``: Brach's 1983 moment
    equation, mu in [0, 1.2] without mu <= mu_max, the free branch only).

    >>> r = batch(costs=["q3"], tests=[7])
    >>> [(x["moment"], x["status"]) for x in r]
    [('free', 'optimal'), ('zero', 'optimal')]
    """
    return Records(_pim.batch(path, costs=list(costs), branches=list(branches), threads=threads,
                              e_max=e_max, moment_form=moment_form,
                              tests=None if tests is None else list(tests),
                              models=list(models), conditions=conditions))


def uncertainty(
    case: Case,
    cost: Optional[Cost] = None,
    draws: Optional[int] = None,
    seed: Optional[int] = None,
    threads: Optional[int] = None,
    model: Model = "pim",
    progress: Optional[Progress] = None,
) -> Uncertainty:
    """Propagates the case's stated uncertainties ([sigma], [uncertainty]) through the fit
    by a seeded parametric bootstrap (``pim uncertainty``): ``draws`` refits (default 200)
    from ``seed`` (default 1), the same numbers for any ``threads``. ``model="tangential"``
    fits the second model in every draw (its quantities ``e``, ``et``, ``friction`` in the
    places of ``mu`` and ``em``). ``progress(done, total, phase)`` is called about every
    50 ms while the draws run; a true return value cancels the study, which then returns the
    draws finished (``cancelled`` says how many of how many); Ctrl-C stops the draws and
    raises ``KeyboardInterrupt``.

    >>> u = uncertainty("examples/cases/ricsac7_uncertainty.toml", cost="q2", draws=20)
    >>> u.feasible_draws, u["speed1"].unit, u["speed1"].p05 < u["speed1"].p95
    (20, 'm/s', True)
    """
    return Uncertainty._read(_pim.uncertainty(case, cost=cost, draws=draws, seed=seed,
                                              threads=threads, model=model, progress=progress))


def predict_dv(path: PathArg = "data/ricsac.csv", e: float = 0.0) -> Dict[str, Any]:
    """Brach (1984) section 6: delta-V predicted from the impact speeds, masses and energy
    loss for every test of a data file (``pim predict-dv``), as its document (``tests``: one
    dict per test)."""
    return _pim.predict_dv(path, e=e)


class SVG(str):
    """SVG text that a notebook shows as a picture (``_repr_svg_``); otherwise a ``str``."""

    def _repr_svg_(self) -> str:
        return str(self)


def edit_case(path: PathArg, values: Mapping[str, Union[float, bool, str]],
              write: bool = True, if_version: Optional[str] = None) -> str:
    """Changes values of a case file in place (``pim set``): ``values`` maps dotted paths as the
    file writes them (``"scene.vehicle1.rest.x"``, ``"observations.0.sigma"``) to numbers in
    the file's own units, booleans or text. The edited case is checked with every check
    ``pim fit`` makes (:class:`InputError` otherwise, the file untouched); with ``write`` the
    file is written back with its comments, key order and number formatting kept everywhere
    else, as ``pim set`` writes it (beside the file, then renamed over it; its mode kept; under
    the file's lock, so that two writers never lose a change). With ``if_version`` (from
    :func:`case_version`) nothing is written, and :class:`OSError` raised, if the file changed
    since that version. Returns the edited text.

    >>> text = edit_case("examples/cases/reconstruction_us.toml",
    ...                  {"scene.vehicle1.rest.x": 12.0}, write=False)
    >>> "rest = { x = 12.0, y = 2.9, heading = 144.0 }" in text
    True
    """
    return _pim.edit_case(path, dict(values), write=write, if_version=if_version)


def case_version(path: PathArg) -> str:
    """The version of a case file: the SHA-256 of its text (64 hex digits), as ``pim set
    --print-version`` prints it; :func:`edit_case` takes it as ``if_version``."""
    return _pim.case_version(path)


def draw(
    case: Case,
    no_slip: bool = False,
    moment_form: MomentForm = "corrected",
    units: Optional[Units] = None,
) -> SVG:
    """The scale diagram of ``pim draw`` as :class:`SVG` text (a ``str`` a notebook shows as a
    picture), labelled in the case's units or ``units`` (``"si"``, ``"us"``, ``"kmh"``).

    >>> svg = draw("examples/cases/side_impact.toml")
    >>> svg.startswith("<svg"), svg._repr_svg_() == svg
    (True, True)
    """
    return SVG(_pim.draw(case, no_slip=no_slip, moment_form=moment_form, units=units))


RunoutSource = Literal["final", "solve", "fit", "scene"]


def runout(
    case: Case,
    source: Optional[RunoutSource] = None,
    cost: Optional[Cost] = None,
    sample: float = 0.1,
    draw: bool = False,
    every: float = 0.5,
    units: Optional[Units] = None,
    wheels: bool = False,
) -> RunoutResult:
    """Each vehicle of a case with ``[runout]`` from its separation velocities to rest, or its
    separation velocities estimated from ``[scene.vehicleN]`` (``pim runout``). ``source``:
    ``"final"``, ``"solve"``, ``"fit"`` (with ``cost``) or ``"scene"``; by default the first the
    case has. The path is sampled every ``sample`` seconds (:meth:`VehicleRunout.path_frame`;
    with ``wheels=True`` each sample carries each wheel's load, slip angle and tyre force);
    ``draw=True`` adds the plan view as ``svg`` (outlines every ``every`` seconds, labelled in
    ``units``). A motion case (``[start.vehicleN]``, no impact: a vehicle from a stated state, as
    PC-Crash runs one) starts from its stated state (``source`` ``"start"``). Raises
    :class:`NoSolution` (its ``document`` the run-out's) when a run-out reaches its time limit or
    no candidate reaches the scene's evidence.

    >>> r = runout("examples/cases/runout_spin.toml")
    >>> r.source, [v.end for v in r.vehicles]
    ('solve', ['rest', 'rest'])
    >>> round(r.vehicles[1].rotation, 1), round(r.vehicles[1].distance, 2)
    (272.7, 8.79)
    >>> e = runout("examples/cases/runout_scene.toml").vehicles[0].estimate
    >>> [c.turns for c in e.consistent], round(e.candidates[0].separation["yaw_rate"], 2)
    ([1], 7.34)
    """
    document, svg = _pim.runout(
        case, source=source, cost=cost, sample=sample, draw=draw, every=every, units=units,
        wheels=wheels,
    )
    return RunoutResult._read(document, None if svg is None else SVG(svg))


def reconstruct(
    case: Case,
    branches: Sequence[MomentBranch] = ("free", "zero"),
    model: Model = "pim",
    draw: bool = False,
    units: Optional[Units] = None,
) -> Reconstruction:
    """The three phases of a case with scene evidence in one fit (``pim fit`` of such a case):
    the separation velocities whose run-outs end at the scene's rest positions and marks, the
    impact fitted exactly through them, the pre-impact skids and EDR speeds; every count of
    turns to rest compared. ``draw=True`` adds the scene to scale as ``svg`` (labelled in
    ``units``). Raises :class:`NoSolution` (its ``document`` the reconstruction's) when no
    admissible impact reaches the evidence.

    >>> r = reconstruct("examples/cases/reconstruction_us.toml")
    >>> [round(v.contact / 0.44704, 1) for v in r.vehicles], r.branch
    ([38.1, 27.2], 'zero')
    >>> round(r.vehicle(1).before_braking / 0.44704, 1), [c.turns for c in r.counts if c.state == "best"]
    (48.6, [(0, 0)])
    """
    document, svg = _pim.reconstruct(
        case, branches=list(branches), model=model, draw=draw, units=units
    )
    return Reconstruction._read(document, None if svg is None else SVG(svg))


def reconstruct_uncertainty(
    case: Case,
    draws: Optional[int] = None,
    seed: Optional[int] = None,
    threads: Optional[int] = None,
    model: Model = "pim",
    progress: Optional[Progress] = None,
) -> ReconstructionStudy:
    """Intervals through all three phases (``pim uncertainty`` of a case with scene
    evidence): ``draws`` (default 200) refits of the whole reconstruction with the estimates,
    observations, EDR speeds, rest positions, headings, marks, the road friction
    (``[runout] friction_sigma``) and ``[uncertainty]`` drawn, from ``seed`` (default 1).
    ``progress`` and Ctrl-C as for :func:`uncertainty`.

    >>> u = reconstruct_uncertainty("examples/cases/reconstruction_us.toml", draws=20)
    >>> q = u["vehicle1.speed_at_contact"]
    >>> u.feasible_draws, q.p05 < q.nominal < q.p95, q.dominated_by[0][0]
    (20, True, 'road friction')
    """
    return ReconstructionStudy._read(
        _pim.reconstruct_uncertainty(case, draws=draws, seed=seed, threads=threads, model=model,
                                     progress=progress)
    )


class Report:
    """The report of a crash, as ``pim report`` writes it: ``html`` (one self-contained page,
    figures inline) and ``markdown``; a notebook shows the page (``_repr_html_``)."""

    def __init__(self, html: str, markdown: str) -> None:
        self.html = html
        self.markdown = markdown

    def _repr_html_(self) -> str:
        return self.html

    def save(self, path: PathArg) -> None:
        """Writes the HTML page to ``path``."""
        with open(path, "w", encoding="utf-8") as f:
            f.write(self.html)


def report(
    case: Case,
    cost: Optional[Cost] = None,
    draws: Optional[int] = None,
    seed: Optional[int] = None,
    units: Optional[Units] = None,
    solve: bool = False,
) -> Report:
    """The report of a crash (``pim report``): a fit case is fitted under ``cost``, a solve
    case solved (``solve=True`` picks the solve of a case that holds both); with [sigma] or
    [uncertainty] the answer's ranges come from ``draws`` refits (default 200, 0 for none).

    >>> r = report("examples/cases/side_impact.toml")
    >>> r.html.startswith("<!DOCTYPE html>"), "## Answer" in r.markdown
    (True, True)
    """
    html, markdown = _pim.report(case, cost=cost, draws=draws, seed=seed, units=units,
                                 solve=solve)
    return Report(html, markdown)


# The twelve velocity components, in the order of the records' 12-element lists.
_COMPONENTS = ["vi1x", "vi1y", "wi1", "vi2x", "vi2y", "wi2",
               "vf1x", "vf1y", "wf1", "vf2x", "vf2y", "wf2"]


def _flatten(prefix: str, value: Any, out: Dict[str, Any]) -> None:
    if prefix == "velocity_error" and isinstance(value, list) and len(value) == 12:
        for name, v in zip(_COMPONENTS, value):
            out[f"velocity_error_{name}"] = v
        return
    if isinstance(value, dict):
        for k, v in value.items():
            _flatten(f"{prefix}_{k}" if prefix else str(k), v, out)
    elif isinstance(value, list) and value and all(isinstance(v, (int, float)) for v in value):
        for i, v in enumerate(value, start=1):
            out[f"{prefix}_{i}"] = v
    elif isinstance(value, list):
        # Lists of records (constraints, ranges): kept whole in one cell.
        out[prefix] = value
    else:
        out[prefix] = value


# Unit suffixes of the flat columns: (test on the name, suffix), first match wins. Angles are
# degrees, velocities m/s, yaw rates rad/s, energies J, impulses N s (moment: N m s).
_UNIT_RULES: List[Any] = [
    (lambda n: n.endswith("_percent"), "pct"),
    (lambda n: n.startswith("velocity_error_w"), "radps"),
    (lambda n: n.startswith("velocity_error_v"), "mps"),
    (lambda n: n.endswith(("heading", "pdof", "_phi", "crush_angle")), "deg"),
    (lambda n: n.endswith(("omega", "yaw_rate_change")), "radps"),
    (lambda n: n.endswith(("_vx", "_vy", "speed_initial", "speed_final")), "mps"),
    (lambda n: "delta_v" in n and "relative" not in n and "detail" not in n, "mps"),
    (lambda n: n.endswith("energy_loss"), "j"),
    (lambda n: n == "impulse_moment", "nms"),
    (lambda n: n.startswith("impulse_"), "ns"),
    (lambda n: n.endswith("_d"), "m"),
]


def _with_unit(name: str) -> str:
    for test, unit in _UNIT_RULES:
        if test(name):
            if unit == "pct":
                return name[: -len("_percent")] + "_pct"
            return f"{name}_{unit}"
    return name


# Conversions of the SI suffixes for ``records_frame(..., units=)``: suffix -> (new suffix,
# factor). Exact definitions: 1 mph = 0.44704 m/s, 1 ft = 0.3048 m, 1 lbf = 4.4482216152605 N.
_LBF = 4.4482216152605
_CONVERT: Dict[str, Dict[str, Any]] = {
    "si": {},
    "us": {
        "mps": ("mph", 1.0 / 0.44704),
        "radps": ("degps", 180.0 / 3.141592653589793),
        "j": ("ftlbf", 1.0 / (_LBF * 0.3048)),
        "ns": ("lbfs", 1.0 / _LBF),
        "nms": ("lbfsft", 1.0 / (_LBF * 0.3048)),
        "m": ("ft", 1.0 / 0.3048),
    },
    "kmh": {
        "mps": ("kmh", 3.6),
        "radps": ("degps", 180.0 / 3.141592653589793),
    },
}


def records_frame(
    records: Union[Iterable[Mapping[str, Any]], Mapping[str, Any], FitResult, Records],
    units: str = "si",
) -> Any:
    """A pandas DataFrame with one row per record and flat, unit-suffixed columns.

    ``records`` is what :func:`batch` returns, a :class:`FitResult` or fit document (its
    branches become the rows), or any list of flat or nested dicts. Nested fields are joined with ``_``
    (``initial_vehicle1_vx_mps``, ``vehicles_1_delta_v_mps``); lists of numbers become one
    column per element. Units: ``_mps`` m/s, ``_radps`` rad/s, ``_deg`` degrees, ``_j``
    joules, ``_ns`` newton seconds, ``_m`` metres, ``_pct`` percent.

    Columns that repeat another (``moment_branch``) or only stand for a nested field absent
    from every row are left out; the velocity errors are named by component
    (``velocity_error_vf1x_mps``).

    ``units="us"`` converts those columns to mph (``_mph``), deg/s (``_degps``), ft lbf
    (``_ftlbf``), lbf s (``_lbfs``) and feet (``_ft``); ``units="kmh"`` speeds to km/h and yaw
    rates to deg/s. The documents themselves are always SI (their ``units`` says so).

    pandas is optional for the package and needed here: ``pip install pandas``.
    """
    try:
        import pandas as pd
    except ImportError as exc:  # pragma: no cover - exercised without pandas
        raise ImportError(
            "pim.records_frame needs pandas, which is not installed: pip install pandas "
            "(or pip install 'pim[pandas]')"
        ) from exc
    if units not in _CONVERT:
        raise InputError(f"units = {units!r}: not an accepted value; accepted: 'si', 'us', 'kmh'")
    convert = _CONVERT[units]
    if isinstance(records, FitResult):
        records = records.to_dict()
    given: Iterable[Mapping[str, Any]]
    if isinstance(records, Mapping):
        if "branches" not in records:
            raise InputError("records: a dict must be a fit document (with 'branches'); give "
                             "other records as a list of dicts")
        given = [dict(b, cost_function=records.get("cost_function")) for b in records["branches"]]
    else:
        given = records
    rows = []
    for r in given:
        flat: Dict[str, Any] = {}
        for k, v in r.items():
            if k == "vehicles" and isinstance(v, list):
                for i, veh in enumerate(v, start=1):
                    _flatten(f"vehicle{i}", veh, flat)
            else:
                _flatten(k, v, flat)
        row: Dict[str, Any] = {}
        for k, v in flat.items():
            name = _with_unit(k)
            suffix = name.rsplit("_", 1)[-1]
            if suffix in convert and name != k:
                new, factor = convert[suffix]
                name = name[: -len(suffix)] + new
                if isinstance(v, (int, float)) and not isinstance(v, bool):
                    v = v * factor
            row[name] = v
        rows.append(row)
    frame = pd.DataFrame(rows)
    return _without_placeholders_and_twins(frame)


def _without_placeholders_and_twins(frame: Any) -> Any:
    """Drops the columns that say nothing the others do not: a nested field absent from every
    row (``initial`` of records whose others have ``initial_vehicle1_vx_mps``), and the
    records' duplicates (``moment_branch`` beside ``moment``, ``vehicle1_delta_v_*`` beside
    ``delta_v_vehicle1_*``) when equal in every row."""
    drop: List[str] = []
    columns = list(frame.columns)
    for c in columns:
        if frame[c].isna().all():
            base = c.rsplit("_", 1)[0] if c.rsplit("_", 1)[-1] in _SUFFIXES else c
            # `vehicles` is flattened as vehicle1_*, vehicle2_*.
            stem = "vehicle1" if base == "vehicles" else base
            if any(o != c and o.startswith(stem + "_") for o in columns):
                drop.append(c)
    twins = [("moment_branch", "moment")]
    for c in columns:
        for k in ("1", "2"):
            prefix = f"vehicle{k}_delta_v_"
            if c.startswith(prefix) and c.count("_") == 3:
                twins.append((c, f"delta_v_vehicle{k}_" + c[len(prefix):]))
    for twin, kept in twins:
        if twin in frame and kept in frame and frame[twin].equals(frame[kept]):
            drop.append(twin)
    return frame.drop(columns=sorted(set(drop)))


_SUFFIXES = {"mps", "radps", "deg", "j", "ns", "nms", "m", "pct",
             "mph", "kmh", "degps", "ftlbf", "lbfs", "lbfsft", "ft"}
