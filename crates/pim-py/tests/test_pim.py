"""The Python package against the command line: the same documents for the same input."""

import json
import os
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

import pim

REPO = Path(__file__).resolve().parents[3]
PIM = REPO / "target" / "release" / "pim"


@pytest.fixture(scope="session", autouse=True)
def cli():
    if not PIM.exists():
        subprocess.run(["cargo", "build", "--release", "-p", "pim-cli"], cwd=REPO, check=True)
    os.chdir(REPO)


def run_cli(*args):
    out = subprocess.run([str(PIM), *args], capture_output=True, text=True, cwd=REPO)
    return out


def cli_json(*args):
    out = run_cli(*args, "--format", "json")
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)


R7_FIT = "examples/cases/ricsac7_fit.toml"


@pytest.mark.parametrize("cost", ["q1", "q2", "q3"])
def test_fit_equals_the_cli_document(cost):
    assert pim.fit(R7_FIT, cost=cost).to_dict() == cli_json("fit", R7_FIT, "--cost", cost)


def test_the_second_model_fits_as_on_the_command_line():
    got = pim.fit(R7_FIT, cost="q2", model="tangential")
    assert got.to_dict() == cli_json("fit", R7_FIT, "--cost", "q2", "--model", "tangential")
    assert got.model == "tangential" and len(got.branches) == 1
    assert got.branches[0].tangential is not None
    assert got.branches[0].tangential["mode"] in ("stick", "slide")
    records = pim.batch(costs=("q2",), tests=[7], models=("pim", "tangential"))
    assert records == cli_json(
        "batch", "--cost", "q2", "--tests", "7", "--model", "pim,tangential"
    )["records"]
    assert [r["model"] for r in records] == ["pim", "pim", "tangential"]
    with pytest.raises(pim.InputError, match="is not one of \"pim\", \"tangential\""):
        pim.fit(R7_FIT, cost="q2", model="impc")


def test_a_case_as_path_text_or_dict_is_the_same_case():
    text = (REPO / R7_FIT).read_text()
    by_path = pim.fit(Path(R7_FIT), cost="q2", branches=("zero",))
    assert pim.fit(text, cost="q2", branches=["zero"]).to_dict() == by_path.to_dict()
    assert pim.fit(tomllib.loads(text), cost="q2", branches=["zero"]) == by_path
    assert [b.moment for b in by_path.branches] == ["zero"]


def test_solve_equals_the_cli_document_both_moment_forms():
    case = "examples/cases/ricsac7_brach1983.toml"
    assert pim.solve(case).to_dict() == cli_json("solve", case)
    got = pim.solve(case, no_slip=True, moment_form="brach1983").to_dict()
    assert got == cli_json("solve", case, "--no-slip", "--moment-form", "brach1983")


def test_batch_records_equal_the_cli_records_for_any_thread_count():
    records = pim.batch("data/ricsac.csv", costs=["q2", "q3"], threads=1)
    assert records == cli_json("batch", "data/ricsac.csv", "--cost", "q2,q3")["records"]
    assert len(records) == 11 * 2 * 2
    assert pim.batch(costs=("q2",), tests=[7, 9], threads=2) == [
        r for r in records if r["cost_function"] == "q2" and r["test"] in (7, 9)
    ]


def test_uncertainty_and_predict_dv_equal_the_cli_documents():
    case = "examples/cases/ricsac7_uncertainty.toml"
    got = pim.uncertainty(case, cost="q2", draws=40, seed=3, threads=2)
    doc = cli_json("uncertainty", case, "--cost", "q2", "--draws", "40", "--seed", "3")
    assert got.to_dict() == doc
    assert got.draws == 40 and set(got.quantities) >= {"speed1", "speed2", "delta_v1"}
    assert pim.predict_dv(e=0.1) == cli_json("predict-dv", "--e", "0.1")


def test_a_study_reports_its_progress_and_can_be_cancelled():
    case = "examples/cases/ricsac7_uncertainty.toml"
    seen = []

    def watch(done, total, phase):
        seen.append((done, total, phase))

    u = pim.uncertainty(case, cost="q2", draws=40, seed=3, threads=2, progress=watch)
    assert seen and seen[-1] == (40, 40, "draws") and u.cancelled is None
    # Watched or not, the same answer.
    assert u.to_dict() == pim.uncertainty(case, cost="q2", draws=40, seed=3).to_dict()

    def stop_after_a_few(done, total, phase):
        return done >= 3

    asked = 100_000
    c = pim.uncertainty(case, cost="q2", draws=asked, seed=3, threads=1,
                        progress=stop_after_a_few)
    assert c.cancelled is not None and c.cancelled["asked"] == asked
    assert 3 <= c.draws == c.cancelled["done"] < asked and c.feasible_draws <= c.draws
    assert c["speed1"].p05 <= c["speed1"].p95


def test_input_errors_carry_the_cli_message(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text((REPO / R7_FIT).read_text().replace("mass = 1955.0", "mass = -5.0"))
    out = run_cli("fit", str(bad), "--cost", "q2")
    assert out.returncode == 2
    with pytest.raises(pim.InputError) as err:
        pim.fit(str(bad), cost="q2")
    assert out.stderr.strip() == f"pim: {err.value}"
    with pytest.raises(pim.InputError, match="q4"):
        pim.fit(R7_FIT, cost="q4")
    with pytest.raises(pim.InputError, match="missing.csv"):
        pim.batch("missing.csv")


@pytest.mark.parametrize(
    "kwargs, words",
    [
        ({"draws": -5}, "draws = -5: expected a whole number from 1 to 1000000"),
        ({"draws": 0}, "draws = 0: expected a whole number from 1 to 1000000"),
        ({"draws": 2**64}, "draws = 18446744073709551616: expected a whole number"),
        ({"draws": 2.5}, "draws = 2.5: expected a whole number"),
        ({"draws": True}, "draws = True: expected a whole number"),
        ({"seed": -1}, "seed = -1: expected a whole number from 0 to 18446744073709551615"),
        ({"threads": 0}, "threads = 0: expected a whole number from 1 to 256"),
        ({"threads": 100000}, "threads = 100000: expected a whole number from 1 to 256"),
    ],
)
def test_arguments_out_of_range_are_input_errors_and_value_errors(kwargs, words):
    # Checked before any work, with the range; an InputError is a ValueError.
    assert issubclass(pim.InputError, ValueError)
    with pytest.raises(pim.InputError) as err:
        pim.uncertainty(R7_FIT, **kwargs)
    assert words in str(err.value)
    with pytest.raises(ValueError):
        pim.uncertainty(R7_FIT, **kwargs)


def test_no_solution_is_an_exception_with_the_document(tmp_path):
    # RICSAC 6 under Q1: no admissible solution in either branch (as in the batch).
    case = "examples/cases/ricsac6_geometry.toml"
    text = (REPO / case).read_text()
    fixed = "\n".join(
        line for line in text.splitlines()
        if not (line.startswith(("vehicle1 = { d", "vehicle2 = { d", "crush_angle = [")))
    )
    path = tmp_path / "r6.toml"
    path.write_text(fixed)
    assert run_cli("fit", str(path), "--cost", "q1").returncode == 3
    with pytest.raises(pim.NoSolution) as err:
        pim.fit(str(path), cost="q1")
    doc = err.value.document
    cli = run_cli("fit", str(path), "--cost", "q1", "--format", "json")
    assert doc == json.loads(cli.stdout)
    assert doc["best"] is None and all(b["status"] == "infeasible" for b in doc["branches"])
    # A backward solve with e = 0 has no answer either (exit status 3 on the command line).
    solve_case = (REPO / "examples/cases/ricsac7_brach1983.toml").read_text()
    back = tmp_path / "back.toml"
    back.write_text(solve_case.replace("e = 0.015", "e = 0.0").replace("[initial]  ", "[final]  "))
    assert run_cli("solve", str(back)).returncode == 3
    with pytest.raises(pim.NoSolution, match="restitution"):
        pim.solve(str(back))


def test_records_frame_of_the_batch():
    records = pim.batch(costs=["q1", "q2", "q3"])
    frame = pim.records_frame(records)
    assert frame.shape[0] == 66
    for column in ["test", "cost_function", "moment", "e", "mu", "em", "cost",
                   "energy_loss_pct", "delta_v_vehicle1_mps", "final_vehicle1_vx_mps",
                   "final_vehicle1_omega_radps", "vehicle1_pdof_deg"]:
        assert column in frame.columns, column
    q2 = frame[(frame.cost_function == "q2") & frame.best]
    assert len(q2) == 11
    # The numbers are the records' own.
    r = next(x for x in records if x["test"] == 9 and x["cost_function"] == "q2" and x["best"])
    row = q2[q2.test == 9].iloc[0]
    assert row.e == r["e"] and row.delta_v_vehicle1_mps == r["delta_v"]["vehicle1"]
    # Named velocity errors; no placeholder or twin columns.
    assert row.velocity_error_vf1x_mps == r["velocity_error"][6]
    assert row.velocity_error_wf2_radps == r["velocity_error"][11]
    for gone in ["initial", "final", "vehicles", "impulse", "moment_branch",
                 "vehicle1_delta_v_mps", "velocity_error_1"]:
        assert gone not in frame.columns, gone
    # Empty only where every record says "none": no error, and no fallback from the convex
    # route (all 66 RICSAC fits take it).
    assert not [c for c in frame.columns if frame[c].isna().all() and c != "error"
                and c not in ("delta_v_relative_error", "velocity_error",
                              "certificate_method_fallback")]
    assert (frame.certificate_method_route == "convex").all()


def test_records_frame_without_pandas_says_how_to_get_it(monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)
    with pytest.raises(ImportError, match="pip install pandas"):
        pim.records_frame([{"e": 0.1}])


def test_help_explains_the_cost_functions_and_the_case():
    doc = pim.fit.__doc__
    for word in ["q1", "q2", "q3", "[estimates.initial]", "free", "zero", "NoSolution"]:
        assert word in doc, word
    assert "q3" in pim.__doc__ and "[vehicle1]" in pim.__doc__


@pytest.mark.parametrize("case", ["examples/cases/ricsac7_brach1983.toml", R7_FIT])
def test_draw_equals_the_svg_of_pim_draw(case, tmp_path):
    out = tmp_path / "d.svg"
    assert run_cli("draw", case, "--output", str(out)).returncode == 0
    svg = pim.draw(case)
    assert svg == out.read_text()
    assert svg.startswith("<svg") and "impact centre" in svg
    # A notebook shows it as a picture.
    assert isinstance(svg, pim.SVG) and svg._repr_svg_() == str(svg)


def test_the_second_model_solves_as_on_the_command_line(tmp_path):
    text = (REPO / "examples/cases/ricsac7_brach1983.toml").read_text()
    case = tomllib.loads(text)
    case["coefficients"] = {"e": 0.1, "et": 0.0, "friction": 0.5}
    got = pim.solve(case)
    assert got.model is not None
    assert got.model["name"] == "tangential" and got.model["mode"] == "slide"
    path = tmp_path / "t.toml"
    path.write_text(text.replace("e = 0.015", "e = 0.1").replace("mu = 0.968", "et = 0.0")
                    .replace("em = -0.774", "friction = 0.5"))
    assert got.to_dict() == cli_json("solve", str(path))


def test_a_barrier_case_solves_and_draws_as_on_the_command_line():
    case = "examples/cases/barrier_small_overlap.toml"
    got = pim.solve(case)
    assert got.to_dict() == cli_json("solve", case)
    assert got.barrier is True and got.model is None
    assert got.final.vehicle2 == pim.Motion(0.0, 0.0, 0.0)
    assert "barrier (fixed, rigid)" in pim.draw(case)


def test_documents_say_they_are_si_and_draw_takes_units():
    doc = pim.solve("examples/cases/tbone_sae_us.toml")
    assert doc.units["system"] == "SI" and doc.units["speed"] == "m/s"
    assert pim.fit(R7_FIT, cost="q2").units["energy"] == "J"
    us = pim.draw("examples/cases/tbone_sae_us.toml")
    si = pim.draw("examples/cases/tbone_sae_us.toml", units="si")
    assert "60.00 mph" in us and "26.82 m/s" in si
    with pytest.raises(pim.InputError, match="accepted"):
        pim.draw(R7_FIT, units="furlongs")


def test_records_frame_in_us_units_converts_the_suffixed_columns():
    pytest.importorskip("pandas")
    fit = pim.fit("examples/cases/tbone_sae_us.toml", cost="q3")
    si = pim.records_frame(fit)
    us = pim.records_frame(fit, units="us")
    assert "vehicle1_speed_initial_mph" in us.columns and "vehicle1_speed_initial_mps" not in us.columns
    assert us["vehicle1_speed_initial_mph"].tolist() == pytest.approx(
        (si["vehicle1_speed_initial_mps"] / 0.44704).tolist(), rel=1e-12
    )
    assert us["energy_loss_ftlbf"].tolist() == pytest.approx(
        (si["energy_loss_j"] / (4.4482216152605 * 0.3048)).tolist(), rel=1e-12
    )
    assert us["e"].tolist() == si["e"].tolist()
    # The best branch's contact speed of the 60 mph pickup reads in mph.
    assert fit.best is not None
    best = us[us.moment == fit.best.moment]
    assert abs(best["vehicle1_speed_initial_mph"].iloc[0] - 59.86) < 0.01
    with pytest.raises(pim.InputError, match="accepted"):
        pim.records_frame(fit, units="furlongs")


def test_the_package_has_a_version():
    assert pim.__version__ == "0.1.0"


def test_a_dict_case_is_named_without_lines_of_a_text_the_caller_never_wrote():
    case = tomllib.loads((REPO / R7_FIT).read_text())
    case["vehicle1"]["mass"] = -5.0
    with pytest.raises(pim.InputError) as err:
        pim.fit(case, cost="q2")
    message = str(err.value)
    assert message.startswith("<dict>: vehicle1.mass: must be a number between 100 and 1000000 kg")


def test_every_docstring_example_runs(monkeypatch):
    import doctest

    monkeypatch.chdir(REPO)
    failures, tried = doctest.testmod(pim)
    assert tried >= 2 and failures == 0


def test_report_is_the_page_of_pim_report(tmp_path):
    case = "examples/cases/tbone_sae_us.toml"
    out = tmp_path / "r.html"
    args = ("--cost", "q3", "--draws", "30")
    assert run_cli("report", case, *args, "-o", str(out)).returncode == 0
    r = pim.report(case, cost="q3", draws=30)
    assert r.html == out.read_text()
    assert r._repr_html_() == r.html and "Each value given against the fit" in r.markdown
    with pytest.raises(pim.InputError, match="draws = -1"):
        pim.report(case, draws=-1)


def test_uncertainty_of_the_tangential_model_equals_the_cli():
    u = pim.uncertainty("examples/cases/ricsac7_uncertainty.toml", cost="q2", draws=30,
                        model="tangential")
    assert "et" in u.quantities and "friction" in u.quantities and "mu" not in u.quantities
    assert u.quantities["friction"].unit == "-"
    cli = cli_json("uncertainty", "examples/cases/ricsac7_uncertainty.toml", "--cost", "q2",
                   "--draws", "30", "--model", "tangential")
    assert u.to_dict() == cli


def test_batch_under_v18_conditions_equals_the_cli():
    records = pim.batch(tests=[10], conditions="v18")
    assert [r["moment"] for r in records] == ["free"] * 3
    q2 = next(r for r in records if r["cost_function"] == "q2")
    assert round(q2["cost"], 2) == 6.91 and q2["mu"] > q2["mu_max"]
    cli = cli_json("batch", "--tests", "10", "--conditions", "v18")
    assert list(records) == cli["records"]
    with pytest.raises(pim.InputError, match="conditions"):
        pim.batch(tests=[10], conditions="v19")  # type: ignore[arg-type]


RUNOUT_SPIN = "examples/cases/runout_spin.toml"
RUNOUT_SCENE = "examples/cases/runout_scene.toml"


@pytest.mark.parametrize("case", [RUNOUT_SPIN, RUNOUT_SCENE])
def test_runout_equals_the_cli_document(case):
    r = pim.runout(case)
    assert r.to_dict() == cli_json("runout", case)
    assert isinstance(r, pim.RunoutResult)


def test_runout_results_are_typed_and_the_path_is_a_frame():
    r = pim.runout(RUNOUT_SPIN, sample=0.05)
    car = r.vehicles[1]
    assert car.end == "rest" and car.vehicle == 2
    frame = car.path_frame()
    assert list(frame.columns) == ["t", "x", "y", "heading", "speed", "yaw_rate"]
    assert frame["t"].is_monotonic_increasing
    assert abs(frame["t"].iloc[-1] - car.time) < 1e-12
    assert abs(frame["x"].iloc[-1] - car.rest["x"]) < 1e-12
    assert abs(car.tyre_work - car.initial_energy) < 1e-6 * car.initial_energy
    # The scene's estimate: one count of turns fits, the others are listed with their costs.
    est = pim.runout(RUNOUT_SCENE).vehicles[0].estimate
    assert est is not None
    assert est.unknowns == ("vx", "vy", "yaw_rate")
    assert len(est.candidates) == 7
    assert [c.turns for c in est.consistent] == [1]
    assert all(s is not None for s in est.candidates[0].sigma)
    assert any("does not exclude" in u for u in est.undetermined)
    whats = [(r.what, r.index) for r in est.candidates[0].residuals]
    assert whats[:3] == [("rest_x", None), ("rest_y", None), ("rest_heading", None)]


def test_runout_draws_the_plan_view_of_the_cli(tmp_path):
    svg = tmp_path / "spin.svg"
    out = run_cli("runout", RUNOUT_SPIN, "--draw", str(svg))
    assert out.returncode == 0, out.stderr
    r = pim.runout(RUNOUT_SPIN, draw=True)
    assert r.svg == svg.read_text()
    assert r.svg is not None and r.svg._repr_svg_() == r.svg


def test_runout_time_limit_and_bad_input(tmp_path):
    case = tomllib.loads(Path(RUNOUT_SPIN).read_text())
    case["runout"]["time_limit"] = 0.5
    with pytest.raises(pim.NoSolution) as e:
        pim.runout(case)
    assert "time limit" in str(e.value)
    assert e.value.document["vehicles"][0]["end"] == "time_limit"
    case["runout"]["time_limit"] = 60.0
    case["runout"]["friction"] = 0.0
    with pytest.raises(pim.InputError, match="runout.friction"):
        pim.runout(case)
    with pytest.raises(pim.InputError, match="source"):
        pim.runout(RUNOUT_SPIN, source="rest")
    with pytest.raises(pim.InputError, match="sample"):
        pim.runout(RUNOUT_SPIN, sample=0.0)


def test_reconstruct_matches_the_command():
    """pim.reconstruct equals `pim fit --format json` of a scene case; pim.fit of it points
    to pim.reconstruct; the scene is drawn."""
    case = str(REPO / "examples" / "cases" / "reconstruction_us.toml")
    r = pim.reconstruct(case, draw=True)
    cli = cli_json("fit", case)
    assert r.document == cli
    assert abs(r.vehicle(1).contact - cli["best"]["vehicles"][0]["speed_at_contact"]) == 0.0
    assert r.svg is not None and r.svg.lstrip().startswith("<")
    # Each row of the evidence says what it is; names are for display.
    sources = [(e.source.kind, e.source.vehicle, e.source.what, e.source.index) for e in r.evidence]
    assert ("edr", 2, None, 0) in sources and ("friction", None, None, 0) in sources
    assert ("scene", 1, "rest_heading", None) in sources and ("scene", 2, "mark", 0) in sources
    assert [e.source.component for e in r.evidence if e.source.kind == "estimate"] == [2, 5]
    with pytest.raises(pim.InputError, match="pim.reconstruct"):
        pim.fit(case)


def test_the_pose_at_contact_fitted():
    """A case with [contact_sigma]: each value of the pose stated and fitted, as `pim fit`
    gives it; the sedan's y at contact known to better than its prior's foot."""
    case = str(REPO / "examples" / "cases" / "reconstruction_pose_us.toml")
    r = pim.reconstruct(case)
    cli = cli_json("fit", case)
    assert r.document == cli
    names = [p.name for p in r.contact_pose]
    assert names == [
        "vehicle1.heading",
        "vehicle1.position.x",
        "vehicle1.position.y",
        "vehicle2.heading",
        "vehicle2.impact_point.x",
    ]
    y = r.contact_pose[2]
    assert y.quantity == "length" and y.sigma < 0.6 * y.prior_sigma
    assert abs(y.prior_sigma - 0.3048) < 1e-12
    assert pim.reconstruct(str(REPO / "examples" / "cases" / "reconstruction_us.toml")).contact_pose == ()


def test_reconstruct_uncertainty():
    case = str(REPO / "examples" / "cases" / "reconstruction_us.toml")
    u = pim.reconstruct_uncertainty(case, draws=12, seed=3)
    cli = cli_json("uncertainty", case, "--draws", "12", "--seed", "3")
    assert u.document == cli
    q = u["vehicle2.speed_at_contact"]
    assert q.p05 <= q.p50 <= q.p95 and u.feasible_draws == 12
    # The reported interval: the draws' widened to the profile's ends (the document's).
    lo, hi = q.reported
    assert [lo, hi] == cli["intervals"]["vehicle2.speed_at_contact"]
    assert lo <= q.p05 and hi >= q.p95
    assert lo <= cli["profiles"]["vehicle2.speed_at_contact"]["lower"]["speed"]
    e = u["e"]
    assert e.reported == (e.p05, e.p95)


def test_a_scene_case_is_answered_with_its_reconstruction():
    """Never the contact estimates' answer for a scene case: the report is the
    reconstruction's (38.095 and 27.196 mph, as `pim fit`), the impact-only study points to
    reconstruct_uncertainty."""
    case = str(REPO / "examples" / "cases" / "reconstruction_us.toml")
    rep = pim.report(case, draws=0)
    rows = {
        line.split("|")[1].strip(): [c.strip() for c in line.split("|")[2:5]]
        for line in rep.markdown.splitlines()
        if line.startswith("| 1 |") or line.startswith("| 2 |")
    }
    # The sedan's contact speed lies on the rounding edge of its two decimals (38.0950).
    assert rows["1"][0] == "48.62" and abs(float(rows["1"][1]) - 38.095) < 0.006
    assert rows["1"][2] == "18.06"
    assert rows["2"] == ["-", "27.20", "30.26"]
    assert "## Evidence and residuals" in rep.markdown
    with pytest.raises(pim.InputError, match="reconstruct_uncertainty"):
        pim.uncertainty(case)


def test_edit_case_changes_one_value_and_keeps_the_file(tmp_path):
    original = (REPO / "examples/cases/reconstruction_us.toml").read_text()
    case = tmp_path / "case.toml"
    case.write_text(original)
    text = pim.edit_case(case, {"scene.vehicle1.rest.x": 12.0,
                                "runout.vehicle1.wheels.front_right": "locked"})
    assert case.read_text() == text
    changed = [(a, b) for a, b in zip(original.splitlines(), text.splitlines()) if a != b]
    assert len(changed) == 2 and len(text.splitlines()) == len(original.splitlines())
    assert changed[1][1].startswith("rest = { x = 12.0, y = 2.9, heading = 144.0 }     # ft")
    # The edited file answers as the command answers it.
    assert pim.reconstruct(case).document == cli_json("fit", str(case))
    # A value the case refuses: the command's message, the file untouched.
    with pytest.raises(pim.InputError, match="vehicle1.mass"):
        pim.edit_case(case, {"vehicle1.mass": -5.0})
    assert case.read_text() == text


def test_edit_case_refuses_what_pim_fit_refuses_and_a_changed_file(tmp_path):
    original = (REPO / "examples/cases/reconstruction_us.toml").read_text()
    case = tmp_path / "case.toml"
    case.write_text(original)
    # A value `pim fit` refuses (the road friction out of its range): its message, nothing written.
    with pytest.raises(pim.InputError, match="runout.friction: must be a number between 0.01"):
        pim.edit_case(case, {"runout.friction": 5.0})
    assert case.read_text() == original
    version = pim.case_version(case)
    assert len(version) == 64
    # Another editor changes the file: a write over the version read is refused.
    changed = original.replace("friction = 0.72", "friction = 0.65")
    case.write_text(changed)
    with pytest.raises(OSError, match="changed on disk"):
        pim.edit_case(case, {"vehicle1.mass": 3500.0}, if_version=version)
    assert case.read_text() == changed
    # Over the version now, it goes through; the file keeps its mode.
    case.chmod(0o600)
    pim.edit_case(case, {"vehicle1.mass": 3500.0}, if_version=pim.case_version(case)[:12])
    assert "mass = 3500.0" in case.read_text() and "friction = 0.65" in case.read_text()
    assert case.stat().st_mode & 0o777 == 0o600


def test_runout_wheels_in_the_path_and_its_frame():
    case = "examples/cases/runout_spin.toml"
    r = pim.runout(case, wheels=True)
    assert r.to_dict() == cli_json("runout", case, "--wheels")
    frame = r.vehicles[0].path_frame()
    assert {"fl_load_n", "rr_slip_angle_deg", "fr_force_x_n", "rl_force_y_n"} <= set(frame.columns)
    assert "wheels" not in pim.runout(case).to_dict()["vehicles"][0]["path"][0]


def test_runout_of_a_motion_case_equals_the_cli_document():
    case = "examples/motion/malibu_us.toml"
    r = pim.runout(case, wheels=True)
    assert r.to_dict() == cli_json("runout", case, "--wheels")
    assert r.source == "start"
    frame = r.vehicles[0].path_frame()
    # Steering left, then braking: the heading grows, the front left wheel (inside) unloads.
    assert frame["heading"].iloc[-1] > 80.0
    assert frame["fl_load_n"].iloc[20] < frame["fr_load_n"].iloc[20]
    with pytest.raises(pim.InputError, match="motion case"):
        pim.solve(case)
