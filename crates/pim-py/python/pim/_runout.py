"""Typed results of :func:`pim.runout`: each vehicle's run-out to rest and, when the scene gave
the evidence, the estimate of its separation velocities (every count of turns a candidate)."""

from __future__ import annotations

import copy
from dataclasses import dataclass, field
from typing import Any, Dict, Mapping, Optional, Tuple

from ._base import _fmt, _table

Document = Dict[str, Any]


@dataclass(frozen=True)
class RunoutResidual:
    """One piece of the scene's evidence against a run-out: its display ``name``, ``value`` =
    fitted - given (m, degrees for headings, or the friction coefficient), its ``sigma``, ``z``
    = value / sigma, and what it is: ``what`` (``"rest_x"``, ``"rest_y"``, ``"rest_heading"``,
    ``"mark"``, ``"mark_heading"``, ``"friction"``) with the mark's ``index`` (from 0)."""

    name: str
    value: float
    sigma: float
    z: float
    what: str
    index: Optional[int]

    @classmethod
    def _read(cls, d: Mapping[str, Any]) -> RunoutResidual:
        what = d["what"]
        index = what.get("index")
        return cls(
            str(d["name"]),
            float(d["value"]),
            float(d["sigma"]),
            float(d["z"]),
            str(what["kind"]),
            None if index is None else int(index),
        )


@dataclass(frozen=True)
class RunoutCandidate:
    """The best separation state for one count of turns: ``separation`` (x, y, heading deg, vx,
    vy m/s, yaw_rate rad/s), the ``friction``, the ``cost`` (sum of squared z), whether it is
    ``consistent`` with the evidence as well as the best (within 1e-6) or not excluded by it
    (``plausible``: within 4), the standard errors ``sigma`` of the unknowns (None where the
    evidence leaves one free), the ``free`` directions, every ``residual`` and the ``reason``
    when it does not reach the evidence."""

    turns: Optional[int]
    separation: Dict[str, float]
    friction: float
    cost: float
    consistent: bool
    plausible: bool
    sigma: Tuple[Optional[float], ...]
    free: Tuple[Tuple[float, ...], ...]
    residuals: Tuple[RunoutResidual, ...]
    reason: Optional[str]

    @classmethod
    def _read(cls, d: Mapping[str, Any]) -> RunoutCandidate:
        return cls(
            turns=None if d["turns"] is None else int(d["turns"]),
            separation={k: float(v) for k, v in d["separation"].items()},
            friction=float(d["friction"]),
            cost=float(d["cost"]),
            consistent=bool(d["consistent"]),
            plausible=bool(d["plausible"]),
            sigma=tuple(None if s is None else float(s) for s in d["sigma"]),
            free=tuple(tuple(float(x) for x in f) for f in d["free"]),
            residuals=tuple(RunoutResidual._read(r) for r in d["residuals"]),
            reason=d.get("reason"),
        )


@dataclass(frozen=True)
class RunoutEstimate:
    """The separation velocities estimated from the scene: the ``unknowns`` (``vx``, ``vy``,
    ``yaw_rate`` and ``friction`` when it is estimated), one candidate per count of turns (the
    lowest cost first), and what the evidence leaves ``undetermined``, in words."""

    unknowns: Tuple[str, ...]
    candidates: Tuple[RunoutCandidate, ...]
    runouts: int
    undetermined: Tuple[str, ...]

    @property
    def consistent(self) -> Tuple[RunoutCandidate, ...]:
        """The candidates that reach the evidence equally well."""
        return tuple(c for c in self.candidates if c.consistent)

    @classmethod
    def _read(cls, d: Mapping[str, Any]) -> RunoutEstimate:
        return cls(
            unknowns=tuple(str(u) for u in d["unknowns"]),
            candidates=tuple(RunoutCandidate._read(c) for c in d["candidates"]),
            runouts=int(d["runouts"]),
            undetermined=tuple(str(u) for u in d["undetermined"]),
        )


@dataclass(frozen=True)
class VehicleRunout:
    """One vehicle from separation to rest: ``separation`` and ``rest`` (m, degrees, m/s,
    rad/s), ``end`` (``"rest"`` or ``"time_limit"``), ``distance`` along the path (m),
    ``time`` (s), ``rotation`` (deg) and whole ``turns``, the ``friction``, the scene's
    ``evidence`` against the run-out and, when estimated, the ``estimate``. :meth:`path_frame`
    gives the path sampled in time as a pandas DataFrame."""

    vehicle: int
    separation: Dict[str, float]
    rest: Dict[str, float]
    end: str
    distance: float
    time: float
    rotation: float
    turns: int
    friction: float
    wheels: Tuple[Any, ...]
    initial_energy: float
    tyre_work: float
    evidence: Tuple[RunoutResidual, ...]
    estimate: Optional[RunoutEstimate]
    path: Tuple[Dict[str, Any], ...] = field(repr=False)

    def path_frame(self) -> Any:
        """The path as a pandas DataFrame: columns ``t`` (s), ``x``, ``y`` (m), ``heading``
        (deg), ``speed`` (m/s), ``yaw_rate`` (rad/s), one row per sample; with
        ``runout(..., wheels=True)`` also each wheel's ``{w}_load_n``, ``{w}_slip_angle_deg``,
        ``{w}_force_x_n`` and ``{w}_force_y_n`` (body frame) for ``w`` in ``fl``, ``fr``,
        ``rl``, ``rr``."""
        try:
            import pandas as pd
        except ImportError as e:  # pragma: no cover - the message is the point
            raise ImportError("path_frame needs pandas: pip install pandas") from e
        columns = ["t", "x", "y", "heading", "speed", "yaw_rate"]
        rows = []
        for p in self.path:
            row = {c: p[c] for c in columns}
            for name, w in zip(("fl", "fr", "rl", "rr"), p.get("wheels") or ()):
                row[f"{name}_load_n"] = w["load"]
                row[f"{name}_slip_angle_deg"] = w["slip_angle"]
                row[f"{name}_force_x_n"] = w["force_x"]
                row[f"{name}_force_y_n"] = w["force_y"]
            rows.append(row)
        return pd.DataFrame(rows, columns=list(rows[0]) if rows else columns)

    @classmethod
    def _read(cls, d: Mapping[str, Any]) -> VehicleRunout:
        est = d.get("estimate")
        return cls(
            vehicle=int(d["vehicle"]),
            separation={k: float(v) for k, v in d["separation"].items()},
            rest={k: float(v) for k, v in d["rest"].items()},
            end=str(d["end"]),
            distance=float(d["distance"]),
            time=float(d["time"]),
            rotation=float(d["rotation"]),
            turns=int(d["turns"]),
            friction=float(d["friction"]),
            wheels=tuple(d["wheels"]),
            initial_energy=float(d["initial_energy"]),
            tyre_work=float(d["tyre_work"]),
            evidence=tuple(RunoutResidual._read(r) for r in d["evidence"]),
            estimate=None if est is None else RunoutEstimate._read(est),
            path=tuple(
                {k: (tuple(dict(w) for w in v) if k == "wheels" else float(v))
                 for k, v in p.items()}
                for p in d["path"]
            ),
        )


@dataclass(frozen=True, repr=False)
class RunoutResult:
    """The document of ``pim runout``: where the separation velocities came from
    (``source``: ``"final"``, ``"solve"``, ``"fit"`` or ``"scene"``), one
    :class:`VehicleRunout` per vehicle with a run-out, ``notes``, and the plan view ``svg``
    when it was asked for (``draw=True``)."""

    source: str
    vehicles: Tuple[VehicleRunout, ...]
    notes: Tuple[str, ...]
    svg: Optional[str]
    _document: Document = field(repr=False, compare=False)

    @classmethod
    def _read(cls, d: Document, svg: Optional[str]) -> RunoutResult:
        return cls(
            source=str(d["source"]),
            vehicles=tuple(VehicleRunout._read(v) for v in d["vehicles"]),
            notes=tuple(str(n) for n in d.get("notes", ())),
            svg=svg,
            _document=d,
        )

    def __repr__(self) -> str:
        rests = ", ".join(
            f"vehicle {v.vehicle}: ({_fmt(v.rest['x'], 3)}, {_fmt(v.rest['y'], 3)}, "
            f"{_fmt(v.rest['heading'], 4)} deg)"
            for v in self.vehicles
        )
        return f"RunoutResult(source={self.source!r}, rest=[{rests}])"

    def to_dict(self) -> Document:
        """The document of ``pim runout --format json`` (a copy)."""
        return copy.deepcopy(self._document)

    def _repr_html_(self) -> str:
        rows = [
            [v.vehicle, v.separation["vx"], v.separation["vy"], v.separation["yaw_rate"],
             v.rest["x"], v.rest["y"], v.rest["heading"], v.distance, v.time, v.end]
            for v in self.vehicles
        ]
        return _table(
            ["vehicle", "vx m/s", "vy m/s", "yaw rate rad/s", "rest x m", "rest y m",
             "rest heading deg", "distance m", "time s", "end"],
            rows,
            f"run-out (separation velocities: {self.source})",
        )
