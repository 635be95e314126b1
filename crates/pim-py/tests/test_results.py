"""Typed results, their frames and notebook reprs, the matplotlib helpers, the type stubs, and
the example notebook run by a real Jupyter kernel."""

import doctest
import importlib
import json
import subprocess
import sys
from pathlib import Path

import pytest

import pim

REPO = Path(__file__).resolve().parents[3]
TBONE = "examples/cases/tbone_sae_us.toml"
R7_FIT = "examples/cases/ricsac7_fit.toml"


@pytest.fixture(autouse=True)
def at_repo(monkeypatch):
    monkeypatch.chdir(REPO)


def test_a_fit_reads_every_number_of_its_document():
    fit = pim.fit(TBONE)
    doc = fit.to_dict()
    assert fit.cost_function == doc["cost_function"] and fit.model == "pim"
    assert fit.best is not None and fit.best.moment == doc["best"]
    assert fit.best is fit.branch(doc["best"])
    for branch, b in zip(fit.branches, doc["branches"]):
        assert (branch.moment, branch.status) == (b["moment"], b["status"])
        assert (branch.e, branch.mu, branch.em, branch.cost) == (b["e"], b["mu"], b["em"], b["cost"])
        assert branch.energy_loss_percent == b["energy_loss_percent"]
        assert branch.initial is not None and branch.final is not None
        assert branch.initial.vehicle1.vx == b["initial"]["vehicle1"]["vx"]
        assert branch.final.vehicle2.omega == b["final"]["vehicle2"]["omega"]
        assert [v.delta_v for v in branch.vehicles] == [v["delta_v"] for v in b["vehicles"]]
        assert [v.pdof for v in branch.vehicles] == [v["pdof"] for v in b["vehicles"]]
        assert branch.chi_square is not None
        assert branch.chi_square.value == b["chi_square"]["value"]
        assert branch.chi_square.degrees_of_freedom == b["chi_square"]["degrees_of_freedom"]
        assert len(branch.residuals) == len(b["residuals"]) == 12
        for r, rd in zip(branch.residuals, b["residuals"]):
            assert (r.name, r.given, r.fitted, r.residual, r.sigma, r.normalised) == (
                rd["name"], rd["given"], rd["fitted"], rd["residual"], rd["sigma"], rd["normalised"]
            )
        # The squares of the normalised residuals sum to the chi-square.
        chi = sum(r.normalised**2 for r in branch.residuals if r.normalised is not None)
        assert chi == pytest.approx(branch.chi_square.value, rel=1e-9)
    with pytest.raises(KeyError, match="its branches: 'free', 'zero'"):
        fit.branch("half")
    # to_dict() is a copy: changing it leaves the result alone.
    doc["branches"][0]["e"] = 99.0
    assert fit.branches[0].e != 99.0 and fit.to_dict()["branches"][0]["e"] != 99.0


def test_frames_of_a_fit_a_solve_and_a_study():
    pytest.importorskip("pandas")
    fit = pim.fit(TBONE)
    frame = fit.to_frame(units="us")
    assert list(frame["moment"]) == ["free", "zero"]
    best = fit.best
    assert best is not None
    row = frame[frame.moment == best.moment].iloc[0]
    assert row["delta_v_vehicle1_mph"] == pytest.approx(best.vehicles[0].delta_v / 0.44704, rel=1e-12)
    residuals = best.residual_frame()
    assert len(residuals) == 12 and list(residuals["residual"]) == [r.residual for r in best.residuals]
    assert best.to_frame().shape[0] == 1

    solved = pim.solve("examples/cases/ricsac7_brach1983.toml")
    frame = solved.to_frame()
    assert list(frame["vehicle"]) == [1, 2]
    assert list(frame["delta_v_mps"]) == [v.delta_v for v in solved.vehicles]
    assert solved.admissible is False and "mu_max" in solved.reasons[0]

    study = pim.uncertainty("examples/cases/ricsac7_uncertainty.toml", cost="q2", draws=30)
    frame = study.to_frame()
    assert list(frame.index) == ["e", "mu", "em", "speed1", "speed2", "delta_v1", "delta_v2",
                                 "energy_loss_percent"]
    doc = study.to_dict()
    for name, q in doc["quantities"].items():
        assert frame.loc[name, "p05"] == q["p05"] and frame.loc[name, "p95"] == q["p95"]
        assert study[name].nominal == doc["nominal"][name]
    assert frame.loc["speed1", "unit"] == "m/s" and frame.loc["energy_loss_percent", "unit"] == "%"

    records = pim.batch(costs=["q2"], tests=[7, 10])
    assert isinstance(records, list) and len(records.to_frame()) == len(records) == 4


def test_notebook_reprs_are_tables_and_pictures():
    fit = pim.fit(TBONE)
    page = fit._repr_html_()
    assert page.startswith("<table>") and "best: zero" in page and "moment impulse" in page
    assert fit.best is not None
    assert f"{fit.best.cost:.4g}" in page
    branch_page = fit.best._repr_html_()
    assert "residual/sigma" in branch_page and "final.vehicle2.omega" in branch_page
    assert "NOT admissible" in pim.solve("examples/cases/ricsac7_brach1983.toml")._repr_html_()
    study = pim.uncertainty("examples/cases/ricsac7_uncertainty.toml", cost="q2", draws=20)
    assert "20 of 20 draws" in study._repr_html_()
    assert "-0<" not in page and "-0<" not in study._repr_html_()
    assert pim.draw(TBONE)._repr_svg_().startswith("<svg")
    # The text repr is one short line per branch, not the whole document.
    assert len(repr(fit)) < 400 and "best='zero'" in repr(fit)


def test_a_fit_without_solution_carries_its_typed_result(tmp_path):
    text = (REPO / "examples/cases/ricsac6_geometry.toml").read_text()
    fixed = "\n".join(
        line for line in text.splitlines()
        if not line.startswith(("vehicle1 = { d", "vehicle2 = { d", "crush_angle = ["))
    )
    path = tmp_path / "r6.toml"
    path.write_text(fixed)
    with pytest.raises(pim.NoSolution) as err:
        pim.fit(str(path), cost="q1")
    result = err.value.result
    assert isinstance(result, pim.FitResult) and result.best is None
    assert [b.status for b in result.branches] == ["infeasible", "infeasible"]
    assert all(b.cost is None and b.reason for b in result.branches)


def test_plots_draw_the_numbers_of_the_results():
    pytest.importorskip("pandas")
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    import pim.plot

    study = pim.uncertainty(TBONE, draws=40)
    ax = pim.plot.intervals(study, units="us")
    bars = sorted(ax.patches, key=lambda p: -p.get_y())
    for bar, name in zip(bars, ["speed1", "speed2", "delta_v1", "delta_v2"]):
        q = study[name]
        assert bar.get_x() == pytest.approx(q.p05 / 0.44704, rel=1e-12)
        assert bar.get_width() == pytest.approx((q.p95 - q.p05) / 0.44704, rel=1e-12)
    assert "mph" in ax.get_xlabel()
    with pytest.raises(ValueError, match="mix units"):
        pim.plot.intervals(study, quantities=["speed1", "mu"])
    with pytest.raises(ValueError, match="no quantity 'speed3'"):
        pim.plot.intervals(study, quantities=["speed3"])

    records = pim.batch(costs=["q1", "q2"], tests=[1, 7])
    ax = pim.plot.batch(records, "cost")
    heights = sorted(round(p.get_height(), 9) for p in ax.patches)
    best = sorted(round(r["cost"], 9) for r in records if r["best"])
    assert heights == best
    # Tests 1 and 7 have no solution under Q1: marked x on the axis, not bars of height 0.
    assert len(ax.patches) == len(best) == 2
    marks = [line for line in ax.lines if line.get_marker() == "x"]
    assert sum(len(line.get_xdata()) for line in marks) == 2
    matplotlib.pyplot.close("all")


def test_plot_doctests_run():
    pytest.importorskip("matplotlib")
    import pim.plot

    failures, tried = doctest.testmod(pim.plot)
    assert tried >= 4 and failures == 0
    failures, tried = doctest.testmod(importlib.import_module("pim._results"))
    assert failures == 0


def test_the_package_type_checks_against_its_stubs():
    pytest.importorskip("mypy")
    run = subprocess.run([sys.executable, "-m", "mypy", "--strict", "-p", "pim"],
                         capture_output=True, text=True, cwd=REPO / "crates" / "pim-py" / "tests")
    assert run.returncode == 0, run.stdout + run.stderr
    # The stubs of the compiled module agree with it (names, parameters, defaults).
    run = subprocess.run([sys.executable, "-m", "mypy.stubtest", "pim._pim"],
                         capture_output=True, text=True, cwd=REPO / "crates" / "pim-py" / "tests")
    assert run.returncode == 0, run.stdout + run.stderr
    # A user's script that reads the typed results checks clean too.
    script = REPO / "crates" / "pim-py" / "tests" / "typed_use.py"
    run = subprocess.run([sys.executable, "-m", "mypy", "--strict", str(script)],
                         capture_output=True, text=True, cwd=REPO)
    assert run.returncode == 0, run.stdout + run.stderr


def test_the_example_notebook_runs_in_a_kernel():
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    pytest.importorskip("ipykernel")
    pytest.importorskip("matplotlib")
    path = REPO / "examples" / "notebook.ipynb"
    nb = nbformat.read(path, as_version=4)
    client = nbclient.NotebookClient(nb, timeout=300, kernel_name="python3",
                                     resources={"metadata": {"path": str(path.parent)}})
    client.execute()
    code = [c for c in nb.cells if c.cell_type == "code"]
    kinds = [set().union(*(o.get("data", {}).keys() for o in c.outputs)) for c in code]
    assert all(not any(o.output_type == "error" for o in c.outputs) for c in code)
    # fit -> table, residuals -> table, diagram -> picture, plots -> images.
    src = [c.source for c in code]
    at = {s.splitlines()[-1]: k for s, k in zip(src, kinds)}
    assert "text/html" in at["fit"]
    assert "text/html" in at["fit.best.residual_frame()"]
    assert "image/svg+xml" in at["pim.draw(case)"]
    assert sum("image/png" in k for k in kinds) == 2
    # The table the notebook shows is the fit of this process.
    fit_out = next(c for c in code if c.source.endswith("fit")).outputs[0]["data"]["text/html"]
    fit = pim.fit(TBONE)
    assert fit._repr_html_() == fit_out


def test_the_guide_python_chapter_runs():
    pytest.importorskip("pandas")
    failures, tried = doctest.testfile(
        str(REPO / "docs" / "python.md"),
        module_relative=False,
        optionflags=doctest.NORMALIZE_WHITESPACE,
    )
    assert tried >= 8 and failures == 0


R7_DAMAGE = "examples/cases/ricsac7_damage.toml"


def test_the_damage_of_a_fit_and_a_solve_is_typed_and_equals_the_command():
    fit = pim.fit(R7_DAMAGE, cost="q2")
    cli = subprocess.run([str(REPO / "target/release/pim"), "fit", R7_DAMAGE, "--cost", "q2",
                          "--format", "json"], capture_output=True, text=True, check=True)
    doc = json.loads(cli.stdout)
    assert fit.to_dict()["damage"] == doc["damage"]
    d = fit.damage
    assert d is not None and d.evidence and d.at_fit is not None and d.with_energy is not None
    v1, v2 = d.at_fit.vehicles
    assert v1 is not None and v2 is not None
    assert (v1.side, v2.side) == ("front", "right")
    assert v1.crush_energy == doc["damage"]["at_fit"]["vehicles"][0]["crush_energy"]
    # Neades' row 7.1 integrated exactly: 24.0 kJ before the direction-of-force factor.
    assert v1.crush_energy == pytest.approx(24_030, abs=50)
    assert d.at_fit.crush_energy == pytest.approx(v1.energy + v2.energy, rel=1e-12)
    assert d.with_energy.cost >= d.with_energy.lower_bound
    assert d.with_energy.energy_z == doc["damage"]["with_energy"]["energy_z"]
    # A dict case with one measured profile: the other's crush from the force balance.
    text = (REPO / R7_DAMAGE).read_text()
    text = text.replace("width = 276\ndepths = [0, 28, 45, 53, 54, 20]\n", "")
    text = text.replace("[estimates.initial]", "[coefficients]\ne = 0.1\nmu = 0.3\nem = 1.0\n\n[initial]")
    head, _, _ = text.partition("[estimates.final]")
    _, _, tail = text.partition("[damage]")
    solved = pim.solve(head + "[damage]" + tail)
    assert solved.damage is not None
    w1, w2 = solved.damage.vehicles
    assert w1 is not None and w2 is not None and w1.measured and not w2.measured
    # A1 + B1 C1 = A2 + B2 C2 at every point (N/cm, N/cm^2; depths in m).
    for c1, c2 in zip(w1.depths, w2.depths):
        assert max(624 + 23 * 100 * c1 - 246, 0.0) == pytest.approx(46 * 100 * c2, abs=1e-9)
