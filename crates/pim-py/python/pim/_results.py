"""Typed views of the documents the Rust side returns.

Each result object is read from the document that ``pim <command> --format json`` prints for
the same input (SI units throughout): its attributes are that document's fields with Python
types, ``to_dict()`` gives the document back unchanged, ``to_frame()`` a pandas DataFrame, and
``_repr_html_`` the table a notebook shows.
"""

from __future__ import annotations

import copy
import html
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Dict, Iterator, List, Mapping, Optional, Sequence, Tuple

if TYPE_CHECKING:
    from ._damage import Damage, DamageFit

from ._base import Document, Motion, Velocities, _float, _fmt, _table


@dataclass(frozen=True)
class Vehicle:
    """What the crash did to one vehicle: speeds (m/s), delta-V (m/s) with its components
    along and across the vehicle, the principal direction of force (PDOF, degrees from the
    vehicle's heading, and as a clock direction) and the yaw-rate change (rad/s)."""

    heading: float
    speed_initial: float
    speed_final: float
    delta_v: float
    delta_v_longitudinal: float
    delta_v_lateral: float
    pdof: Optional[float]
    clock: Optional[int]
    yaw_rate_change: float

    @classmethod
    def _read(cls, d: Mapping[str, Any]) -> Vehicle:
        clock = d.get("clock")
        return cls(
            heading=float(d["heading"]),
            speed_initial=float(d["speed_initial"]),
            speed_final=float(d["speed_final"]),
            delta_v=float(d["delta_v"]),
            delta_v_longitudinal=float(d["delta_v_longitudinal"]),
            delta_v_lateral=float(d["delta_v_lateral"]),
            pdof=_float(d, "pdof"),
            clock=None if clock is None else int(clock),
            yaw_rate_change=float(d["yaw_rate_change"]),
        )


@dataclass(frozen=True)
class Residual:
    """One estimate or observation against the fit: ``given``, ``fitted``, ``residual`` =
    fitted - given (in ``unit``), its ``weight`` in the cost, ``sigma`` and ``normalised`` =
    residual / sigma when the case states sigmas, and its ``share`` of the cost (0..1)."""

    name: str
    kind: str
    unit: str
    given: float
    fitted: float
    residual: float
    weight: float
    sigma: Optional[float]
    normalised: Optional[float]
    share: Optional[float]

    @classmethod
    def _read(cls, d: Mapping[str, Any]) -> Residual:
        return cls(
            name=str(d["name"]),
            kind=str(d["kind"]),
            unit=str(d["unit"]),
            given=float(d["given"]),
            fitted=float(d["fitted"]),
            residual=float(d["residual"]),
            weight=float(d["weight"]),
            sigma=_float(d, "sigma"),
            normalised=_float(d, "normalised"),
            share=_float(d, "share"),
        )


@dataclass(frozen=True)
class ChiSquare:
    """The fit's chi-square (the cost when every weight is 1/sigma^2), its degrees of freedom
    and the probability ``p_value`` of a chi-square at least this large if the model and the
    sigmas are right (None when the degrees of freedom are not positive)."""

    value: float
    degrees_of_freedom: int
    p_value: Optional[float]


@dataclass(frozen=True, repr=False)
class Branch:
    """One moment branch of a fit (``moment``: ``"free"``, e_m in [-1, 0]; ``"zero"``,
    e_m = 1, no moment impulse; the tangential model has one branch).

    ``status`` is ``"optimal"`` (certified global optimum of the branch), ``"infeasible"``
    (no admissible solution; ``reason`` says why), ``"limit_reached"`` or ``"check_failed"``;
    the numbers are None unless the branch has a solution."""

    moment: str
    status: str
    reason: Optional[str]
    e: Optional[float]
    mu: Optional[float]
    em: Optional[float]
    cost: Optional[float]
    initial: Optional[Velocities]
    final: Optional[Velocities]
    energy_loss: Optional[float]
    energy_loss_percent: Optional[float]
    mu_max: Optional[float]
    mu_ratio: Optional[float]
    vehicles: Tuple[Vehicle, ...]
    admissible: Optional[bool]
    residuals: Tuple[Residual, ...]
    chi_square: Optional[ChiSquare]
    tangential: Optional[Dict[str, Any]]
    _document: Document = field(repr=False, compare=False)

    def __repr__(self) -> str:
        if self.cost is None:
            return f"Branch(moment={self.moment!r}, status={self.status!r}, reason={self.reason!r})"
        return (f"Branch(moment={self.moment!r}, status={self.status!r}, e={_fmt(self.e)}, "
                f"mu={_fmt(self.mu)}, em={_fmt(self.em)}, cost={_fmt(self.cost)})")

    @property
    def optimal(self) -> bool:
        """True when the branch has a certified optimum."""
        return self.status == "optimal"

    @classmethod
    def _read(cls, d: Document) -> Branch:
        chi = d.get("chi_square")
        reason = d.get("reason")
        return cls(
            moment=str(d["moment"]),
            status=str(d["status"]),
            reason=None if reason is None else str(reason),
            e=_float(d, "e"),
            mu=_float(d, "mu"),
            em=_float(d, "em"),
            cost=_float(d, "cost"),
            initial=Velocities._read(d.get("initial")),
            final=Velocities._read(d.get("final")),
            energy_loss=_float(d, "energy_loss"),
            energy_loss_percent=_float(d, "energy_loss_percent"),
            mu_max=_float(d, "mu_max"),
            mu_ratio=_float(d, "mu_ratio"),
            vehicles=tuple(Vehicle._read(v) for v in d.get("vehicles") or ()),
            admissible=d.get("admissible"),
            residuals=tuple(Residual._read(r) for r in d.get("residuals", ())),
            chi_square=None
            if chi is None
            else ChiSquare(
                float(chi["value"]), int(chi["degrees_of_freedom"]), _float(chi, "p_value")
            ),
            tangential=d.get("tangential"),
            _document=d,
        )

    def to_dict(self) -> Document:
        """The branch as the fit document holds it (a copy)."""
        return copy.deepcopy(self._document)

    def to_frame(self, units: str = "si") -> Any:
        """A one-row DataFrame (the columns of :func:`pim.records_frame`)."""
        from . import records_frame

        return records_frame([self._document], units=units)

    def residual_frame(self) -> Any:
        """The residual table as a DataFrame: one row per estimate and observation."""
        import pandas as pd

        return pd.DataFrame([r.__dict__ for r in self.residuals])

    def _summary_row(self) -> List[Any]:
        dv: List[Optional[float]] = [v.delta_v for v in self.vehicles] or [None, None]
        chi = None if self.chi_square is None else self.chi_square.value
        return [self.moment, self.status, self.e, self.mu, self.em, self.cost, chi,
                self.energy_loss_percent, dv[0], dv[1]]

    def _repr_html_(self) -> str:
        head = _table(_BRANCH_HEADER, [self._summary_row()], f"branch {self.moment}")
        if not self.residuals:
            return head
        rows = [[r.name, r.kind, r.unit, r.given, r.fitted, r.residual, r.sigma, r.normalised,
                 r.share] for r in self.residuals]
        return head + _table(
            ["input", "kind", "unit", "given", "fitted", "residual", "sigma", "residual/sigma",
             "share of cost"],
            rows,
        )


_BRANCH_HEADER = ["moment impulse", "status", "e", "mu", "em", "cost", "chi-square",
                  "energy loss %", "delta-V 1 m/s", "delta-V 2 m/s"]


@dataclass(frozen=True, repr=False)
class FitResult:
    """The document of ``pim fit``: one :class:`Branch` per moment branch searched, and
    ``best``, the admissible branch of lowest cost (None when no branch has a solution);
    ``damage`` (a :class:`DamageFit`) when the case gives ``[damage]``."""

    model: str
    cost_function: Optional[str]
    branches: Tuple[Branch, ...]
    best: Optional[Branch]
    notes: Tuple[str, ...]
    units: Dict[str, str]
    damage: Optional[DamageFit]
    _document: Document = field(repr=False, compare=False)

    @classmethod
    def _read(cls, d: Document) -> FitResult:
        from ._damage import DamageFit
        branches = tuple(Branch._read(b) for b in d["branches"])
        best = next((b for b in branches if b.moment == d.get("best")), None)
        cost = d.get("cost_function")
        return cls(
            model=str(d.get("model", "pim")),
            cost_function=None if cost is None else str(cost),
            branches=branches,
            best=best,
            notes=tuple(str(n) for n in d.get("notes", ())),
            units=dict(d.get("units", {})),
            damage=DamageFit._read(d.get("damage")),
            _document=d,
        )

    def __repr__(self) -> str:
        best = None if self.best is None else self.best.moment
        return (f"FitResult(model={self.model!r}, cost_function={self.cost_function!r}, "
                f"best={best!r}, branches={list(self.branches)!r})")

    def branch(self, moment: str) -> Branch:
        """The branch named ``moment`` (``"free"`` or ``"zero"``)."""
        for b in self.branches:
            if b.moment == moment:
                return b
        names = ", ".join(repr(b.moment) for b in self.branches)
        raise KeyError(f"no branch {moment!r} in this fit; its branches: {names}")

    def __iter__(self) -> Iterator[Branch]:
        return iter(self.branches)

    def to_dict(self) -> Document:
        """The document of ``pim fit --format json`` (a copy)."""
        return copy.deepcopy(self._document)

    def to_frame(self, units: str = "si") -> Any:
        """One row per branch (the columns of :func:`pim.records_frame`)."""
        from . import records_frame

        return records_frame(self._document, units=units)

    def _repr_html_(self) -> str:
        best = self.best.moment if self.best else "none (no branch has a solution)"
        cost = self.cost_function if self.cost_function not in (None, "custom") else "of the case"
        caption = f"fit ({self.model}, cost {cost}); best: {best}"
        return _table(_BRANCH_HEADER, [b._summary_row() for b in self.branches], caption)


@dataclass(frozen=True, repr=False)
class SolveResult:
    """The document of ``pim solve``: the velocities at contact and separation, per-vehicle
    delta-V and PDOF, energy, impulse, and whether the solution is physically admissible
    (``reasons`` says why not). ``barrier`` is True for a rigid barrier (vehicle 2 fixed);
    ``model`` describes the second model (its coefficients and mode) when the case uses it,
    and is None for PIM; ``damage`` (a :class:`Damage`) when the case gives ``[damage]``."""

    direction: str
    coefficients: Dict[str, float]
    initial: Velocities
    final: Velocities
    vehicles: Tuple[Vehicle, ...]
    energy_loss: float
    energy_loss_percent: float
    impulse: Dict[str, float]
    mu_max: Optional[float]
    mu_ratio: Optional[float]
    admissible: bool
    reasons: Tuple[str, ...]
    barrier: bool
    model: Optional[Dict[str, Any]]
    units: Dict[str, str]
    damage: Optional[Damage]
    _document: Document = field(repr=False, compare=False)

    @classmethod
    def _read(cls, d: Document) -> SolveResult:
        from ._damage import Damage
        initial = Velocities._read(d["initial"])
        final = Velocities._read(d["final"])
        assert initial is not None and final is not None
        return cls(
            direction=str(d["direction"]),
            coefficients={k: float(v) for k, v in d["coefficients"].items()},
            initial=initial,
            final=final,
            vehicles=tuple(Vehicle._read(v) for v in d["vehicles"]),
            energy_loss=float(d["energy"]["loss"]),
            energy_loss_percent=float(d["energy"]["loss_percent"]),
            impulse={k: float(v) for k, v in d["impulse"].items()},
            mu_max=_float(d, "mu_max"),
            mu_ratio=_float(d, "mu_ratio"),
            admissible=bool(d["admissible"]),
            reasons=tuple(str(r) for r in d.get("reasons", ())),
            barrier=bool(d.get("barrier", False)),
            model=d.get("model"),
            units=dict(d.get("units", {})),
            damage=Damage._read(d.get("damage")),
            _document=d,
        )

    def __repr__(self) -> str:
        dv = ", ".join(_fmt(v.delta_v) for v in self.vehicles)
        return (f"SolveResult(direction={self.direction!r}, coefficients={self.coefficients!r}, "
                f"delta_v=[{dv}], energy_loss_percent={_fmt(self.energy_loss_percent)}, "
                f"admissible={self.admissible})")

    def to_dict(self) -> Document:
        """The document of ``pim solve --format json`` (a copy)."""
        return copy.deepcopy(self._document)

    def to_frame(self, units: str = "si") -> Any:
        """One row per vehicle: speeds, delta-V, PDOF and yaw-rate change."""
        from . import records_frame

        rows = [dict(vehicle=i, **v.__dict__) for i, v in enumerate(self.vehicles, start=1)]
        return records_frame(rows, units=units)

    def _repr_html_(self) -> str:
        c = self.coefficients
        caption = (f"solve ({self.direction}): e = {_fmt(c.get('e'))}, mu = {_fmt(c.get('mu'))}, "
                   f"em = {_fmt(c.get('em'))}; energy loss {_fmt(self.energy_loss_percent, 3)} %"
                   + ("" if self.admissible else "; NOT admissible: " + "; ".join(self.reasons)))
        rows = [[i, v.speed_initial, v.speed_final, v.delta_v, v.pdof, v.yaw_rate_change]
                for i, v in enumerate(self.vehicles, start=1)]
        return _table(["vehicle", "speed at contact m/s", "speed at separation m/s",
                       "delta-V m/s", "PDOF deg", "yaw-rate change rad/s"], rows, caption)


# Units of the quantities of an uncertainty study.
QUANTITY_UNITS: Dict[str, str] = {
    "e": "-", "mu": "-", "em": "-", "et": "-", "friction": "-",
    "speed1": "m/s", "speed2": "m/s", "delta_v1": "m/s", "delta_v2": "m/s",
    "energy_loss_percent": "%",
}


def _order(name: str) -> int:
    names = list(QUANTITY_UNITS)
    return names.index(name) if name in names else len(names)


@dataclass(frozen=True)
class Interval:
    """One quantity of an uncertainty study: the nominal fit's value, the 5/50/95 %
    percentiles, mean and standard deviation over the draws, the linearised standard
    deviation, and two flags: ``not_determined`` (the data leave it free) and
    ``reaches_bound`` (the search bound that ends the range, or None)."""

    name: str
    unit: str
    nominal: Optional[float]
    p05: Optional[float]
    p50: Optional[float]
    p95: Optional[float]
    mean: Optional[float]
    sd: Optional[float]
    linearised_sd: Optional[float]
    not_determined: bool
    reaches_bound: Optional[Any]


@dataclass(frozen=True, repr=False)
class Uncertainty:
    """The document of ``pim uncertainty``: ``draws`` refits of the case with its stated
    uncertainties drawn, summarised per quantity in ``quantities`` (an :class:`Interval`
    each), with the share of draws in each branch and the inputs that drive each quantity."""

    draws: int
    seed: int
    feasible_draws: int
    nominal_branch: Optional[str]
    quantities: Dict[str, Interval]
    branch_share: Dict[str, float]
    sensitivity: Tuple[Dict[str, Any], ...]
    units: Dict[str, str]
    _document: Document = field(repr=False, compare=False)
    cancelled: Optional[Dict[str, Any]] = None
    """Set when the study was cancelled: ``phase``, ``done`` and ``asked`` (``draws`` is then
    the draws finished)."""

    @classmethod
    def _read(cls, d: Document) -> Uncertainty:
        nominal = d.get("nominal") or {}
        lin = d.get("linearised_sd") or {}
        quantities = {
            name: Interval(
                name=name,
                unit=QUANTITY_UNITS.get(name, ""),
                nominal=_float(nominal, name),
                p05=_float(q, "p05"),
                p50=_float(q, "p50"),
                p95=_float(q, "p95"),
                mean=_float(q, "mean"),
                sd=_float(q, "sd"),
                linearised_sd=_float(lin, name),
                not_determined=bool(q.get("not_determined", False)),
                reaches_bound=q.get("reaches_bound"),
            )
            for name, q in sorted(d["quantities"].items(), key=lambda kv: _order(kv[0]))
        }
        branch = d.get("nominal_branch")
        return cls(
            draws=int(d["draws"]),
            seed=int(d["seed"]),
            feasible_draws=int(d["feasible_draws"]),
            nominal_branch=None if branch is None else str(branch),
            quantities=quantities,
            branch_share={k: float(v) for k, v in (d.get("branch_share") or {}).items()},
            sensitivity=tuple(d.get("sensitivity", ())),
            units=dict(d.get("units", {})),
            _document=d,
            cancelled=d.get("cancelled"),
        )

    def __repr__(self) -> str:
        ranges = ", ".join(f"{q.name}: {_fmt(q.p05)}..{_fmt(q.p95)}"
                           for q in self.quantities.values())
        return (f"Uncertainty(draws={self.draws}, feasible_draws={self.feasible_draws}, "
                f"5-95 %: {ranges})")

    def __getitem__(self, name: str) -> Interval:
        return self.quantities[name]

    def to_dict(self) -> Document:
        """The document of ``pim uncertainty --format json`` (a copy)."""
        return copy.deepcopy(self._document)

    def to_frame(self) -> Any:
        """One row per quantity (index: its name): unit, nominal, p05, p50, p95, mean, sd,
        linearised_sd, not_determined, reaches_bound."""
        import pandas as pd

        rows = [q.__dict__ for q in self.quantities.values()]
        return pd.DataFrame(rows).set_index("name")

    def _repr_html_(self) -> str:
        caption = (f"uncertainty: {self.feasible_draws} of {self.draws} draws with a solution "
                   f"(seed {self.seed})")
        rows = [[q.name, q.unit, q.nominal, q.p05, q.p50, q.p95,
                 "not determined" if q.not_determined else
                 ("ended by a bound" if q.reaches_bound else "")]
                for q in self.quantities.values()]
        return _table(["quantity", "unit", "nominal", "5 %", "50 %", "95 %", "note"], rows,
                      caption)


class Records(List[Document]):
    """The records of :func:`pim.batch`: a list of dicts (one per test, cost function, model
    and branch, as ``pim batch --format json`` prints them) with ``to_frame()``."""

    def to_frame(self, units: str = "si") -> Any:
        """The records as a DataFrame (see :func:`pim.records_frame`)."""
        from . import records_frame

        return records_frame(list(self), units=units)

    def _repr_html_(self) -> str:
        rows = [[r.get("test"), r.get("cost_function"), r.get("model"), r.get("moment"),
                 r.get("status"), r.get("e"), r.get("mu"), r.get("em"), r.get("cost")]
                for r in self]
        return _table(["test", "cost", "model", "moment impulse", "status", "e", "mu", "em",
                       "cost"], rows, f"{len(self)} records")
