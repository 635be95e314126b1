#!/usr/bin/env python3
"""Runs the RICSAC refit with `pim batch` and with SciPy's SLSQP (slsqp_ricsac.py) on the same
machine in one run, and prints per problem (test, cost function, moment branch): our cost,
SLSQP's best cost over its starts and its single midpoint-start cost, who is lower, both times and
their ratios; then totals. Exits 1 if SLSQP reaches a lower feasible cost than pim anywhere (beyond
1e-6 relative), or finds a feasible point where pim reports none.

Usage (from the repository root, after `cargo build --release -p pim-cli`):
    benches/peer/.venv/bin/python benches/peer/compare.py [--tests 1,6,7] [--json OUT.json]

Our times: `pim batch --timing --threads 1`, one moment branch per run so that each problem is
timed on its own; the best of three runs per problem (the process is warm after the first).
"""
import json
import os
import statistics
import subprocess
import sys
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
PIM = os.path.join(ROOT, "target", "release", "pim")
TOL = 1e-6


def run_pim(branch, tests):
    best = {}
    for _ in range(3):
        cmd = [PIM, "batch", "data/ricsac.csv", "--timing", "--threads", "1", "--branch", branch, "--format", "json"]
        if tests:
            cmd += ["--tests", tests]
        out = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
        if out.returncode not in (0, 1):
            sys.exit(f"pim failed: {out.stderr}")
        for r in json.loads(out.stdout)["records"]:
            key = (r["test"], r["cost_function"], r["moment_branch"])
            t = r["fit_seconds"]
            if key not in best or t < best[key]["seconds"]:
                best[key] = {"cost": r.get("cost"), "outcome": r["outcome"], "seconds": t,
                             "e": r.get("e"), "mu": r.get("mu"), "em": r.get("em")}
    return best


def main(argv):
    tests, json_out = None, None
    args = list(argv)
    while args:
        a = args.pop(0)
        if a == "--tests":
            tests = args.pop(0)
        elif a == "--json":
            json_out = args.pop(0)
    if not os.path.exists(PIM):
        sys.exit("build pim first: cargo build --release -p pim-cli")
    t0 = time.time()
    ours = {}
    for branch in ("free", "zero"):
        ours.update(run_pim(branch, tests))
    cmd = [sys.executable, os.path.join(ROOT, "benches", "peer", "slsqp_ricsac.py"), "data/ricsac.csv"]
    if tests:
        cmd += ["--tests", tests]
    peer = json.loads(subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, check=True).stdout)["records"]
    rows, bad = [], []
    print("test cost branch |   pim cost  SLSQP best  SLSQP 1-start | lower |  pim ms  1-start ms  multi ms | 1-start/pim  multi/pim")
    for p in peer:
        key = (p["test"], p["cost_function"], p["branch"])
        o = ours[key]
        best = p["multi_start"]["best"]
        single = p["single_start"]
        ours_cost = o["cost"] if o["outcome"] in ("optimal", "limit_reached") else None
        peer_cost = best["cost"] if best else None
        if peer_cost is not None and (ours_cost is None or peer_cost < ours_cost - TOL * (1 + abs(ours_cost))):
            lower = "SLSQP"
            bad.append(key)
        elif ours_cost is not None and (peer_cost is None or ours_cost < peer_cost - TOL * (1 + abs(peer_cost))):
            lower = "pim"
        else:
            lower = "same"
        ms, s1, sm = o["seconds"] * 1e3, single["seconds"] * 1e3, p["multi_start"]["seconds"] * 1e3
        fmt = lambda c: f"{c:10.4f}" if c is not None else "      none"
        s1c = f"{single['cost']:10.4f}" + ("" if single["feasible"] else "!") if single["feasible"] else "  infeas.  "
        print(f"{key[0]:>4} {key[1]:<4} {key[2]:<5}  | {fmt(ours_cost)}  {fmt(peer_cost)}  {s1c:>12} | {lower:<5} | {ms:7.2f}  {s1:10.2f}  {sm:8.0f} | {s1 / ms:11.1f}  {sm / ms:9.0f}")
        rows.append({"test": key[0], "cost_function": key[1], "branch": key[2], "pim_cost": ours_cost,
                     "slsqp_best_cost": peer_cost, "slsqp_single_cost": single["cost"] if single["feasible"] else None,
                     "lower": lower, "pim_seconds": o["seconds"], "slsqp_single_seconds": single["seconds"],
                     "slsqp_multi_seconds": p["multi_start"]["seconds"], "slsqp_starts": p["multi_start"]["starts"]})
    med = lambda k: statistics.median(r[k] for r in rows)
    single_worse = sum(1 for r in rows if r["pim_cost"] is not None and (r["slsqp_single_cost"] is None or r["slsqp_single_cost"] > r["pim_cost"] + TOL * (1 + r["pim_cost"])))
    print()
    print(f"problems: {len(rows)}; pim lower: {sum(r['lower'] == 'pim' for r in rows)}, same: {sum(r['lower'] == 'same' for r in rows)}, SLSQP lower: {len(bad)}")
    print(f"SLSQP single midpoint start: not feasible or worse than pim in {single_worse} of {len(rows)} problems")
    print(f"median time per problem: pim {med('pim_seconds') * 1e3:.2f} ms, SLSQP single start {med('slsqp_single_seconds') * 1e3:.2f} ms "
          f"(ratio {med('slsqp_single_seconds') / med('pim_seconds'):.1f}), SLSQP multi-start {med('slsqp_multi_seconds') * 1e3:.0f} ms "
          f"(ratio {med('slsqp_multi_seconds') / med('pim_seconds'):.0f})")
    print(f"total: pim {sum(r['pim_seconds'] for r in rows):.3f} s, SLSQP single starts {sum(r['slsqp_single_seconds'] for r in rows):.3f} s, "
          f"SLSQP all starts {sum(r['slsqp_multi_seconds'] for r in rows):.1f} s; wall time of this comparison {time.time() - t0:.0f} s")
    ratios = [r["slsqp_single_seconds"] / r["pim_seconds"] for r in rows if r["pim_seconds"] > 0]
    print(f"per problem, SLSQP single start / pim: median {statistics.median(ratios):.1f}; "
          f"at least 10 in {sum(q >= 10 for q in ratios)} of {len(ratios)}; "
          f"pim slower in {sum(q < 1 for q in ratios)}")
    for cost in sorted({r["cost_function"] for r in rows}):
        sub = [r for r in rows if r["cost_function"] == cost]
        m = lambda k: statistics.median(r[k] for r in sub)
        multi = [r["slsqp_multi_seconds"] / r["pim_seconds"] for r in sub if r["pim_seconds"] > 0]
        print(f"  {cost} ({len(sub)} problems): median pim {m('pim_seconds') * 1e3:.3f} ms, "
              f"SLSQP single start {m('slsqp_single_seconds') * 1e3:.2f} ms, "
              f"multi-start / pim median {statistics.median(multi):.0f} (least {min(multi):.1f})")
    if json_out:
        with open(json_out, "w") as f:
            json.dump(rows, f, indent=1)
    if bad:
        print(f"SLSQP found lower costs in {bad}: a bug in the certified search", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
