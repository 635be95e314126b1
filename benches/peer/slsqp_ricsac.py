#!/usr/bin/env python3
"""The RICSAC refit with SciPy's SLSQP, the published way (a local SQP solver, as MATLAB fmincon in
Vossou & Koulocheris 2018), on exactly the problems `pim batch` solves.

Same data (data/ricsac.csv), same equations (the corrected moment form, as documented in the pim-core crate), same cost
functions Q1, Q2, Q3 (unit weights), same bounds (e in [0, 0.2], mu in [-1.2, 1.2], em in [-1, 0]
or em = 1, |v| <= 20 m/s, |omega| <= 5 rad/s) and the same admissibility conditions:
  - the vehicles approach at the impact centre (at least 1 mm/s),
  - the contact state slides the way the friction sign s assumes,
  - mu between 0 and mu_max, written as the smooth  mu * sigma * Vt >= 0,
  - no kinetic energy created,  T(x) - T(X) >= 0.
The six equations and the known components are equality constraints. Gradients and Jacobians are
analytic. The friction sign s is discrete: each start fixes it.

Per problem (test, cost function, branch) it reports: the best feasible cost over all starts, the
cost from the single midpoint start a typical user would use (estimates as the starting velocities,
e = 0.1, mu = 0, em = -0.5, s from the estimated contact state; its time is the best of three
identical runs, as pim's), the constraint violation, and the times. Output: JSON on stdout.

Usage: slsqp_ricsac.py [DATA.csv] [--tests 1,6,7]
"""
import csv
import json
import math
import sys
import time

import numpy as np
from scipy.optimize import minimize

VB, WB = 20.0, 5.0
E_BOUNDS = (0.0, 0.2)
MU_BOUNDS = (-1.2, 1.2)
FEAS_TOL = 1e-6


class Geometry:
    def __init__(self, row):
        f = {k: float(v) for k, v in row.items() if k not in ("configuration", "vehicle1", "vehicle2", "d1_source", "d2_source")}
        self.m1, self.m2 = f["mass1_kg"], f["mass2_kg"]
        self.i1, self.i2 = f["yaw_inertia1_kgm2"], f["yaw_inertia2_kgm2"]
        a1 = math.radians(f["heading1_deg"] + f["phi1_deg"])
        a2 = math.radians(f["heading2_deg"] + f["phi2_deg"])
        d1, d2 = f["d1_m"], f["d2_m"]
        self.D1, self.D2 = d2 * math.sin(a2), d2 * math.cos(a2)
        self.D3, self.D4 = d1 * math.sin(a1), d1 * math.cos(a1)
        g = math.radians(f["crush_angle_deg"])
        self.c, self.s = math.cos(g), math.sin(g)
        D1, D2, D3, D4, c, s = self.D1, self.D2, self.D3, self.D4, self.c, self.s
        # Relative velocity at C along n and t, as rows over a state.
        self.nrow = np.array([c, s, D3 * c - D4 * s, -c, -s, D1 * c - D2 * s])
        ts, tc = -s, c
        self.trow = np.array([ts, tc, ts * D3 - tc * D4, -ts, -tc, ts * D1 - tc * D2])
        sep = (D4 + D2) * c + (D3 + D1) * s
        self.side = 1.0 if sep >= 0 else -1.0
        self.mass = np.array([self.m1, self.m1, self.i1, self.m2, self.m2, self.i2])
        self.brow = np.array([-self.m1 * D3 / self.i1, self.m1 * D4 / self.i1, 1.0,
                              -self.m2 * D1 / self.i2, self.m2 * D2 / self.i2, -1.0])
        self.initial = np.array([f[k] for k in ("vi1x_mps", "vi1y_mps", "wi1_radps", "vi2x_mps", "vi2y_mps", "wi2_radps")])
        self.final = np.array([f[k] for k in ("vf1x_mps", "vf1y_mps", "wf1_radps", "vf2x_mps", "vf2y_mps", "wf2_radps")])

    def system(self, e, mu, em, sign):
        """F, G (6x6) of F X + G x = 0 and their derivatives with respect to e, mu, em."""
        m1, m2, c, s = self.m1, self.m2, self.c, self.s
        D1, D2, D3, D4 = self.D1, self.D2, self.D3, self.D4
        F = np.zeros((6, 6)); G = np.zeros((6, 6))
        dF = {k: np.zeros((6, 6)) for k in "abc"}; dG = {k: np.zeros((6, 6)) for k in "abc"}  # a=e, b=mu, c=em
        r = np.array([m1, 0, 0, m2, 0, 0.0]); F[0] = r; G[0] = -r
        r = np.array([0, m1, 0, 0, m2, 0.0]); F[1] = r; G[1] = -r
        r = np.array([0, m1 * (D2 + D4), self.i1, m2 * (D1 + D3), 0, self.i2]); F[2] = r; G[2] = -r
        F[3] = self.nrow; G[3] = e * self.nrow; dG["a"][3] = self.nrow
        ms = mu * sign
        r = np.array([0, m1 * (c - ms * s), 0, m2 * (s + ms * c), 0, 0.0]); F[4] = r; G[4] = -r
        dr = np.array([0, -m1 * s * sign, 0, m2 * c * sign, 0, 0.0]); dF["b"][4] = dr; dG["b"][4] = -dr
        w = np.array([0, 0, -1.0, 0, 0, 1.0])
        F[5] = (1 - em) * w - em * self.brow; G[5] = em * self.brow
        dF["c"][5] = -w - self.brow; dG["c"][5] = self.brow
        return F, G, dF, dG


class Problem:
    """One (test, cost, branch): variables z = (U[12], e, mu[, em])."""

    def __init__(self, geo, cost, branch):
        self.g, self.cost, self.branch = geo, cost, branch
        self.est = np.concatenate([geo.initial, geo.final])
        self.known = {"q1": list(range(6, 12)), "q2": list(range(6)), "q3": []}[cost]
        self.estimated = [k for k in range(12) if k not in self.known]
        self.n = 15 if branch == "free" else 14

    def unpack(self, z):
        em = z[14] if self.branch == "free" else 1.0
        return z[:6], z[6:12], z[12], z[13], em

    def objective(self, z):
        d = z[self.estimated] - self.est[self.estimated]
        return float(d @ d)

    def gradient(self, z):
        gr = np.zeros(self.n)
        gr[self.estimated] = 2 * (z[self.estimated] - self.est[self.estimated])
        return gr

    def eq(self, z, sign):
        x, X, e, mu, em = self.unpack(z)
        F, G, _, _ = self.g.system(e, mu, em, sign)
        res = F @ X + G @ x
        fixed = z[self.known] - self.est[self.known]
        return np.concatenate([res, fixed])

    def eq_jac(self, z, sign):
        x, X, e, mu, em = self.unpack(z)
        F, G, dF, dG = self.g.system(e, mu, em, sign)
        J = np.zeros((6 + len(self.known), self.n))
        J[:6, :6] = G; J[:6, 6:12] = F
        J[:6, 12] = dF["a"] @ X + dG["a"] @ x
        J[:6, 13] = dF["b"] @ X + dG["b"] @ x
        if self.branch == "free":
            J[:6, 14] = dF["c"] @ X + dG["c"] @ x
        for i, k in enumerate(self.known):
            J[6 + i, k] = 1.0
        return J

    def ineq(self, z, sign):
        g = self.g
        x, X, e, mu, em = self.unpack(z)
        sigma = -sign * g.side
        return np.array([
            -g.side * (g.nrow @ x) - 1e-3,               # approach
            sigma * (g.trow @ x),                         # sliding direction
            mu * sigma * (g.trow @ X),                    # mu between 0 and mu_max
            0.5 * (g.mass @ (x * x) - g.mass @ (X * X)),  # no energy created
        ])

    def ineq_jac(self, z, sign):
        g = self.g
        x, X, e, mu, em = self.unpack(z)
        sigma = -sign * g.side
        J = np.zeros((4, self.n))
        J[0, :6] = -g.side * g.nrow
        J[1, :6] = sigma * g.trow
        J[2, 6:12] = mu * sigma * g.trow; J[2, 13] = sigma * (g.trow @ X)
        J[3, :6] = g.mass * x; J[3, 6:12] = -g.mass * X
        return J

    def bounds(self):
        b = [(-WB, WB) if k % 3 == 2 else (-VB, VB) for k in range(12)]
        b += [E_BOUNDS, MU_BOUNDS]
        if self.branch == "free":
            b.append((-1.0, 0.0))
        return b

    def violation(self, z, sign):
        v = np.abs(self.eq(z, sign))
        scale = np.concatenate([np.abs(self.eq_jac(z, sign)[:6, :12]) @ np.abs(z[:12]), np.ones(len(self.known))])
        rel = v / np.maximum(scale, 1.0)
        ineq = np.maximum(-self.ineq(z, sign), 0.0)
        ineq[3] /= max(0.5 * self.g.mass @ (z[:6] ** 2), 1.0)
        ineq[2] /= max(abs(z[13]) * np.abs(self.g.trow) @ np.abs(z[6:12]), 1e-9)
        lo = np.array([b[0] for b in self.bounds()]); hi = np.array([b[1] for b in self.bounds()])
        bnd = np.maximum(np.maximum(lo - z, z - hi), 0.0)
        return float(max(rel.max(initial=0.0), ineq.max(initial=0.0), bnd.max(initial=0.0)))

    def solve(self, z0, sign):
        t0 = time.perf_counter()
        r = minimize(
            self.objective, z0, jac=self.gradient, method="SLSQP", bounds=self.bounds(),
            constraints=[
                {"type": "eq", "fun": self.eq, "jac": self.eq_jac, "args": (sign,)},
                {"type": "ineq", "fun": self.ineq, "jac": self.ineq_jac, "args": (sign,)},
            ],
            options={"maxiter": 500, "ftol": 1e-12},
        )
        dt = time.perf_counter() - t0
        return r, self.violation(r.x, sign), dt

    def start(self, e, mu, em):
        z = np.concatenate([self.est, [e, mu]] + ([[em]] if self.branch == "free" else []))
        return np.clip(z, [b[0] for b in self.bounds()], [b[1] for b in self.bounds()])

    def measured_sign(self):
        g = self.g
        vn, vt = g.nrow @ g.initial, g.trow @ g.initial
        return (1.0 if vn >= 0 else -1.0) * (1.0 if vt >= 0 else -1.0)


def run(problem):
    out = {}
    s0 = problem.measured_sign()
    # Timed like pim's fits: the best of three identical runs.
    runs = [problem.solve(problem.start(0.1, 0.0, -0.5), s0) for _ in range(3)]
    r, viol, _ = runs[0]
    dt = min(t for _, _, t in runs)
    out["single_start"] = {"cost": float(r.fun), "violation": viol, "feasible": viol <= FEAS_TOL, "seconds": dt,
                           "success": bool(r.success), "message": r.message}
    best, total, n = None, 0.0, 0
    ems = [-0.9, -0.5, -0.1] if problem.branch == "free" else [1.0]
    for sign in (1.0, -1.0):
        for e in (0.02, 0.1, 0.18):
            for mu in (-0.6, -0.1, 0.3, 0.7, 1.0):
                for em in ems:
                    r, viol, dt = problem.solve(problem.start(e, mu, em), sign)
                    total += dt; n += 1
                    if viol <= FEAS_TOL and (best is None or r.fun < best["cost"]):
                        x = r.x
                        best = {"cost": float(r.fun), "violation": viol, "e": float(x[12]), "mu": float(x[13]),
                                "em": float(x[14]) if problem.branch == "free" else 1.0, "sign": sign}
    out["multi_start"] = {"best": best, "starts": n, "seconds": total}
    return out


def main(argv):
    path, tests = "data/ricsac.csv", None
    args = list(argv)
    while args:
        a = args.pop(0)
        if a == "--tests":
            tests = {int(t) for t in args.pop(0).split(",")}
        else:
            path = a
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    records = []
    for row in rows:
        if tests and int(row["test"]) not in tests:
            continue
        geo = Geometry(row)
        for cost in ("q1", "q2", "q3"):
            for branch in ("free", "zero"):
                rec = {"test": int(row["test"]), "cost_function": cost, "branch": branch}
                rec.update(run(Problem(geo, cost, branch)))
                records.append(rec)
    json.dump({"data": path, "records": records}, sys.stdout, indent=1)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main(sys.argv[1:])
