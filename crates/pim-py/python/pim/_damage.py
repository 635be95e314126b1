"""Typed views of the damage in a solve's and a fit's documents (``damage``): each vehicle's
crush energy beside PIM's energy loss and CRASH3's delta-V beside PIM's, and the fit that takes
the crush energy as evidence. SI units: J, m, m/s, degrees."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Dict, Mapping, Optional, Tuple

from ._base import Velocities


def _opt(d: Mapping[str, Any], key: str) -> Optional[float]:
    v = d.get(key)
    return None if v is None else float(v)


@dataclass(frozen=True)
class CrushVehicle:
    """One vehicle's crush at a pair of states: the profile (``depths`` across ``width``, m),
    its energy before (``crush_energy``) and after (``energy``) the direction-of-force factor
    ``pdof_factor`` = 1 + tan^2(alpha) (alpha the force's angle from the face's normal, held at
    45 deg), its standard deviation, the barrier-equivalent speed, the impulse's moment arm
    about the CG and its effective-mass factor, CRASH3's delta-V and PIM's. ``measured`` is
    False when the depths follow from the other vehicle's by the force balance."""

    side: str
    measured: bool
    depths: Tuple[float, ...]
    width: float
    crush_energy: float
    pdof: float
    pdof_from: str
    alpha: float
    pdof_factor: float
    energy: float
    energy_sigma: float
    barrier_equivalent_speed: float
    moment_arm: float
    effective_mass_factor: float
    crash3_delta_v: float
    pim_delta_v: float

    @classmethod
    def _read(cls, d: Mapping[str, Any]) -> CrushVehicle:
        return cls(
            side=str(d["side"]),
            measured=bool(d["measured"]),
            depths=tuple(float(c) for c in d["depths"]),
            width=float(d["width"]),
            crush_energy=float(d["crush_energy"]),
            pdof=float(d["pdof"]),
            pdof_from=str(d["pdof_from"]),
            alpha=float(d["alpha"]),
            pdof_factor=float(d["pdof_factor"]),
            energy=float(d["energy"]),
            energy_sigma=float(d["energy_sigma"]),
            barrier_equivalent_speed=float(d["barrier_equivalent_speed"]),
            moment_arm=float(d["moment_arm"]),
            effective_mass_factor=float(d["effective_mass_factor"]),
            crash3_delta_v=float(d["crash3_delta_v"]),
            pim_delta_v=float(d["pim_delta_v"]),
        )


@dataclass(frozen=True)
class Damage:
    """Both vehicles' crush against PIM's energy loss at one pair of states. ``relation``:
    ``"energy_loss"`` (CRASH3's convention) or ``"compression"`` (the loss is (1 - e^2) of the
    crush energy); ``difference`` = ``energy_loss`` - ``expected_loss``, ``z`` the same in
    standard deviations (None without one)."""

    relation: str
    vehicles: Tuple[Optional[CrushVehicle], ...]
    crush_energy: float
    crush_energy_sigma: float
    e: float
    expected_loss: float
    expected_loss_sigma: float
    energy_loss: float
    difference: float
    z: Optional[float]
    relation_note: str
    warnings: Tuple[str, ...]

    @classmethod
    def _read(cls, d: Optional[Mapping[str, Any]]) -> Optional[Damage]:
        if d is None:
            return None
        return cls(
            relation=str(d["relation"]),
            vehicles=tuple(None if v is None else CrushVehicle._read(v) for v in d["vehicles"]),
            crush_energy=float(d["crush_energy"]),
            crush_energy_sigma=float(d["crush_energy_sigma"]),
            e=float(d["e"]),
            expected_loss=float(d["expected_loss"]),
            expected_loss_sigma=float(d["expected_loss_sigma"]),
            energy_loss=float(d["energy_loss"]),
            difference=float(d["difference"]),
            z=_opt(d, "z"),
            relation_note=str(d["relation_note"]),
            warnings=tuple(str(w) for w in d.get("warnings", ())),
        )


@dataclass(frozen=True)
class EnergyFit:
    """The fit with the crush energy as evidence: its coefficients and velocities, the whole
    cost and the case's evidence alone, the energy's residual in standard deviations
    (``energy_z``, PIM's loss minus the expected), ``lower_bound`` (the certified optimum
    without the energy: no answer costs less), ``proven`` (the cost meets it), and the crush
    at this answer."""

    moment: str
    e: float
    mu: float
    em: float
    initial: Velocities
    final: Velocities
    cost: float
    cost_without_energy: float
    energy_z: float
    chi_square: Optional[Dict[str, Any]]
    velocity_sigma_assumed: bool
    lower_bound: float
    proven: bool
    fits: int
    damage: Optional[Damage]
    delta_v: Tuple[float, float]
    energy_loss: float

    @classmethod
    def _read(cls, d: Optional[Mapping[str, Any]]) -> Optional[EnergyFit]:
        if d is None:
            return None
        initial = Velocities._read(d["initial"])
        final = Velocities._read(d["final"])
        assert initial is not None and final is not None
        dv = d["delta_v"]
        return cls(
            moment=str(d["moment"]),
            e=float(d["e"]),
            mu=float(d["mu"]),
            em=float(d["em"]),
            initial=initial,
            final=final,
            cost=float(d["cost"]),
            cost_without_energy=float(d["cost_without_energy"]),
            energy_z=float(d["energy_z"]),
            chi_square=d.get("chi_square"),
            velocity_sigma_assumed=bool(d["velocity_sigma_assumed"]),
            lower_bound=float(d["lower_bound"]),
            proven=bool(d["proven"]),
            fits=int(d["fits"]),
            damage=Damage._read(d.get("damage")),
            delta_v=(float(dv[0]), float(dv[1])),
            energy_loss=float(d["energy_loss"]),
        )


@dataclass(frozen=True)
class DamageFit:
    """The damage of a fit: the crush at its best answer (``at_fit``) and, when the crush
    energy is evidence, the fit with it (``with_energy``; else ``not_evidence`` says why)."""

    at_fit: Optional[Damage]
    evidence: bool
    not_evidence: Optional[str]
    with_energy: Optional[EnergyFit]

    @classmethod
    def _read(cls, d: Optional[Mapping[str, Any]]) -> Optional[DamageFit]:
        if d is None:
            return None
        why = d.get("not_evidence")
        return cls(
            at_fit=Damage._read(d.get("at_fit")),
            evidence=bool(d["evidence"]),
            not_evidence=None if why is None else str(why),
            with_energy=EnergyFit._read(d.get("with_energy")),
        )
