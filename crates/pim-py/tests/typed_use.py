"""A script as a user writes it against the package, type-checked with ``mypy --strict`` by
the test suite (not run as a test itself)."""

from typing import List, Optional

import pim


def best_delta_v(case: str) -> Optional[List[float]]:
    fit: pim.FitResult = pim.fit(case, cost="q3")
    best: Optional[pim.Branch] = fit.best
    if best is None:
        return None
    return [v.delta_v for v in best.vehicles]


def speeds(case: str) -> List[float]:
    solved: pim.SolveResult = pim.solve(case)
    return [solved.initial.vehicle1.speed, solved.final.vehicle2.speed]


def range_of_speed1(case: str) -> Optional[float]:
    study: pim.Uncertainty = pim.uncertainty(case, draws=50, seed=2)
    q: pim.Interval = study["speed1"]
    if q.p05 is None or q.p95 is None:
        return None
    return q.p95 - q.p05


def worst_residual(case: str) -> str:
    best = pim.fit(case).best
    assert best is not None
    worst: pim.Residual = max(best.residuals, key=lambda r: abs(r.normalised or 0.0))
    return worst.name


def costs(path: str) -> List[float]:
    records: pim.Records = pim.batch(path, costs=["q2"])
    return [float(r["cost"]) for r in records if r["best"]]


svg: pim.SVG = pim.draw("examples/cases/side_impact.toml", units="kmh")
report: pim.Report = pim.report("examples/cases/side_impact.toml")


def rest_and_estimate(case: str) -> Optional[float]:
    r: pim.RunoutResult = pim.runout(case, sample=0.2)
    car: pim.VehicleRunout = r.vehicles[0]
    est: Optional[pim.RunoutEstimate] = car.estimate
    if est is None:
        return car.rest["x"]
    first: pim.RunoutCandidate = est.candidates[0]
    return first.separation["vx"]


def contact_speeds(case: str) -> List[float]:
    r: pim.Reconstruction = pim.reconstruct(case)
    first: pim.PhaseSpeeds = r.vehicle(1)
    ev: pim.Evidence = max(r.evidence, key=lambda e: e.share)
    tried: List[pim.CountsTried] = [c for c in r.counts if c.state == "best"]
    assert ev.phase in ("pre_impact", "impact", "run_out") and tried
    return [first.contact] + [v.contact for v in r.vehicles[1:]]


def contact_interval(case: str) -> float:
    u: pim.ReconstructionStudy = pim.reconstruct_uncertainty(case, draws=10)
    q: pim.PhaseInterval = u["vehicle1.speed_at_contact"]
    return q.p95 - q.p05
