"""Typed results of :func:`pim.reconstruct` and :func:`pim.reconstruct_uncertainty`: the
three phases of a collision (pre-impact, impact, run-out) in one fit, and its intervals."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Dict, Mapping, Optional, Tuple

Document = Dict[str, Any]


def _opt(x: Any) -> Optional[float]:
    return None if x is None else float(x)


@dataclass(frozen=True)
class PhaseSpeeds:
    """One vehicle through the phases (m/s): ``before_braking`` (with a pre-impact skid),
    ``contact``, ``separation``, ``rest`` (0 with a scene); its ``turns`` to rest, where it
    came to ``rest`` (x, y m, heading deg) and the run-out's ``distance`` (m) and ``time``
    (s)."""

    vehicle: int
    before_braking: Optional[float]
    contact: float
    separation: float
    rest_speed: Optional[float]
    turns: Optional[int]
    rest: Optional[Dict[str, float]]
    distance: Optional[float]
    time: Optional[float]

    @classmethod
    def _read(cls, d: Mapping[str, Any]) -> PhaseSpeeds:
        rest = d.get("rest")
        return cls(
            vehicle=int(d["vehicle"]),
            before_braking=_opt(d.get("speed_before_braking")),
            contact=float(d["speed_at_contact"]),
            separation=float(d["speed_at_separation"]),
            rest_speed=_opt(d.get("speed_at_rest")),
            turns=None if d.get("turns") is None else int(d["turns"]),
            rest=None if rest is None else {k: float(v) for k, v in rest.items()},
            distance=_opt(d.get("runout_distance")),
            time=_opt(d.get("runout_time")),
        )


def _int(x: Any) -> Optional[int]:
    return None if x is None else int(x)


@dataclass(frozen=True)
class EvidenceSource:
    """What a row of the evidence table is: its identity (tell rows apart by it; the name is
    for display). ``kind`` is ``"estimate"``, ``"observation"``, ``"edr"``, ``"combination"``,
    ``"nonlinear"``, ``"friction"``, ``"scene"`` or ``"contact_prior"``; ``vehicle`` (1 or 2)
    for ``edr`` and ``scene``; ``index`` (from 0) the observation, EDR record, combination,
    nonlinear evidence, fitted friction, pose prior or, for a scene row, mark; ``component``
    (0-11, the contact velocities then the separation's) for an estimate; ``what`` for a scene
    row: ``"rest_x"``, ``"rest_y"``, ``"rest_heading"``, ``"mark"``, ``"mark_heading"``."""

    kind: str
    vehicle: Optional[int] = None
    index: Optional[int] = None
    component: Optional[int] = None
    what: Optional[str] = None

    @classmethod
    def _read(cls, d: Mapping[str, Any]) -> EvidenceSource:
        what = d.get("what")
        index = d.get("index")
        if what is not None:
            index = what.get("index")
        return cls(
            kind=str(d["kind"]),
            vehicle=_int(d.get("vehicle")),
            index=_int(index),
            component=_int(d.get("component")),
            what=None if what is None else str(what["kind"]),
        )


@dataclass(frozen=True)
class Evidence:
    """One piece of evidence against the reconstruction: its display ``name``, its ``phase``
    (``"pre_impact"``, ``"impact"``, ``"run_out"``), ``residual`` = fitted - given (m/s,
    rad/s, m or deg), its ``sigma``, ``z``, its ``share`` of the chi-square in percent, and
    its ``source`` (what it is)."""

    name: str
    phase: str
    residual: float
    sigma: float
    z: float
    share: float
    source: EvidenceSource

    @classmethod
    def _read(cls, d: Mapping[str, Any]) -> Evidence:
        return cls(
            str(d["name"]),
            str(d["phase"]),
            float(d["residual"]),
            float(d["sigma"]),
            float(d["z"]),
            float(d["share_percent"]),
            EvidenceSource._read(d["source"]),
        )


@dataclass(frozen=True)
class CountsTried:
    """One combination of counts of turns to rest (one per scene vehicle): the scenes alone
    at the best their search found (a lower bound where it found each count's minimum), the
    momentum bound, the ``chi_square`` reached when
    refined, and its ``state`` (``"best"``, ``"refined"``, ``"abandoned"``,
    ``"not_refined"``, ``"no_impact"``) with the ``reason``."""

    turns: Tuple[Optional[int], ...]
    scene_alone: float
    momentum_bound: Optional[float]
    chi_square: Optional[float]
    state: str
    reason: Optional[str]

    @classmethod
    def _read(cls, d: Mapping[str, Any]) -> CountsTried:
        return cls(
            turns=tuple(None if t is None else int(t) for t in d["turns"]),
            scene_alone=float(d["scene_alone"]),
            momentum_bound=_opt(d.get("momentum_bound")),
            chi_square=_opt(d.get("chi_square")),
            state=str(d["state"]),
            reason=d.get("reason"),
        )


@dataclass(frozen=True)
class ContactPose:
    """One value of the pose at contact the reconstruction fitted (``[contact_sigma]``): its
    ``name`` (``vehicle1.heading``, ``vehicle2.impact_point.x``, ...), ``quantity``
    (``"length"``, m, or ``"angle"``, deg; the natural frame), the value ``stated`` in the case,
    the ``fitted`` one with its standard deviation ``sigma`` after the fit, the prior's
    ``prior_sigma`` and ``z``, fitted minus stated over the prior's deviation."""

    name: str
    quantity: str
    stated: float
    fitted: float
    sigma: float
    prior_sigma: float
    z: float

    @classmethod
    def _read(cls, d: Mapping[str, Any]) -> ContactPose:
        return cls(
            str(d["name"]),
            str(d["quantity"]),
            float(d["stated"]),
            float(d["fitted"]),
            float(d["sigma"]),
            float(d["prior_sigma"]),
            float(d["z"]),
        )


@dataclass(frozen=True)
class Reconstruction:
    """A reconstruction: the impact's ``e``, ``mu``, ``em`` and ``branch``, the whole
    ``chi_square`` with its degrees of freedom and ``p_value``, each vehicle's speeds through the
    phases (``vehicles``), every piece of ``evidence``, every combination of counts of turns
    compared (``counts``), how it was found (``method``), what is ``proven`` and what the
    evidence leaves ``undetermined``; ``contact_pose`` the pose at contact where the case fits
    it (``[contact_sigma]``, else empty); ``svg`` the scene to scale when drawn; ``document``
    the JSON of ``pim fit``."""

    e: float
    mu: float
    em: float
    branch: str
    energy_loss_percent: float
    chi_square: float
    degrees_of_freedom: int
    p_value: Optional[float]
    vehicles: Tuple[PhaseSpeeds, ...]
    evidence: Tuple[Evidence, ...]
    counts: Tuple[CountsTried, ...]
    method: str
    proven: str
    undetermined: Tuple[str, ...]
    contact_pose: Tuple[ContactPose, ...] = ()
    svg: Optional[str] = field(default=None, repr=False)
    document: Document = field(default_factory=dict, repr=False)

    def vehicle(self, n: int) -> PhaseSpeeds:
        """Vehicle ``n`` (1 or 2)."""
        return next(v for v in self.vehicles if v.vehicle == n)

    def _repr_svg_(self) -> Optional[str]:
        return self.svg

    @classmethod
    def _read(cls, d: Document, svg: Optional[str] = None) -> Reconstruction:
        b = d["best"]
        return cls(
            e=float(b["e"]),
            mu=float(b["mu"]),
            em=float(b["em"]),
            branch=str(b["branch"]),
            energy_loss_percent=float(b["energy_loss_percent"]),
            chi_square=float(b["chi_square"]),
            degrees_of_freedom=int(b["degrees_of_freedom"]),
            p_value=_opt(b.get("p_value")),
            vehicles=tuple(PhaseSpeeds._read(v) for v in b["vehicles"]),
            evidence=tuple(Evidence._read(x) for x in b["evidence"]),
            counts=tuple(CountsTried._read(c) for c in d["counts"]),
            method=str(d["method"]),
            proven=str(d["proven"]),
            undetermined=tuple(str(u) for u in d["undetermined"]),
            contact_pose=tuple(ContactPose._read(p) for p in b.get("contact_pose", [])),
            svg=svg,
            document=d,
        )


@dataclass(frozen=True)
class PhaseInterval:
    """One quantity of a reconstruction's study: the nominal value, the 5/50/95 % percentiles,
    mean and standard deviation over the draws (speeds m/s), and the inputs that dominate it
    (first-order index, largest first)."""

    name: str
    nominal: float
    p05: float
    p50: float
    p95: float
    mean: float
    sd: float
    dominated_by: Tuple[Tuple[str, float], ...]
    reported: Tuple[float, float] = (float("nan"), float("nan"))
    """The 90 % interval the study reports: for a speed at contact the draws' ``p05`` to
    ``p95`` widened on each side to its profile interval's end (the speed at which the best
    reconstruction's chi-square has risen 2.71 above the answer's); for the others ``p05`` to
    ``p95``."""


@dataclass(frozen=True)
class ReconstructionStudy:
    """Intervals through all three phases: ``draws`` asked, ``feasible_draws`` with an answer,
    one :class:`PhaseInterval` per quantity (``e``, ``mu``, ``em``, ``energy_loss_percent``,
    ``vehicleN.speed_before_braking`` / ``speed_at_contact`` / ``speed_at_separation``), the
    ``inputs`` drawn."""

    draws: int
    seed: int
    feasible_draws: int
    quantities: Dict[str, PhaseInterval]
    inputs: Tuple[str, ...]
    document: Document = field(default_factory=dict, repr=False)
    cancelled: Optional[Dict[str, Any]] = None
    """Set when the study was cancelled: ``phase``, ``done`` and ``asked``."""

    def __getitem__(self, name: str) -> PhaseInterval:
        return self.quantities[name]

    @classmethod
    def _read(cls, d: Document) -> ReconstructionStudy:
        sens = {s["quantity"]: s["inputs"] for s in d["sensitivity"]}
        q = {
            name: PhaseInterval(
                name=name,
                nominal=float(d["nominal"][name]),
                p05=float(s["p05"]),
                p50=float(s["p50"]),
                p95=float(s["p95"]),
                mean=float(s["mean"]),
                sd=float(s["sd"]),
                dominated_by=tuple((str(a), float(b)) for a, b in sens.get(name, [])),
                reported=(
                    float(d.get("intervals", {}).get(name, [s["p05"], s["p95"]])[0]),
                    float(d.get("intervals", {}).get(name, [s["p05"], s["p95"]])[1]),
                ),
            )
            for name, s in d["quantities"].items()
        }
        return cls(
            draws=int(d["draws"]),
            seed=int(d["seed"]),
            feasible_draws=int(d["feasible_draws"]),
            quantities=q,
            inputs=tuple(str(i) for i in d["inputs"]),
            document=d,
            cancelled=d.get("cancelled"),
        )
