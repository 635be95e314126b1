"""pim.scene_frame: a frame of scene cases in, one whole reconstruction per row out, the same
answers as `pim fit` of each file, and the same frame under Dask's scheduler."""

import json
import subprocess
from pathlib import Path

import pandas as pd
import pytest

import pim

REPO = Path(__file__).resolve().parents[3]
SCENES = [str(REPO / "examples/cases" / n) for n in
          ("reconstruction_us.toml", "reconstruction_damage_us.toml", "runout_scene.toml")]


def pim_fit(path: str) -> dict:
    out = subprocess.run([str(REPO / "target/release/pim"), "fit", path, "--format", "json"],
                         capture_output=True, text=True, check=False)
    return json.loads(out.stdout)


def test_every_row_is_the_reconstruction_pim_fit_gives():
    rows = pd.DataFrame({"case": SCENES})
    out = pim.scene_frame(rows, threads=None)
    assert list(out.columns) == list(pim.SCENE_COLUMNS)
    assert list(out.case) == SCENES
    for _, r in out.iterrows():
        doc = pim_fit(r.case)
        assert r.status == doc["status"]
        cars = doc["best"]["vehicles"]
        assert r.v1_contact == cars[0]["speed_at_contact"]
        assert r.v2_contact == cars[1]["speed_at_contact"]
        assert r.chi_square == doc["best"]["chi_square"]
    # The fitted friction where the case gives its sigma, NaN where it holds it.
    us = out.set_index("case").road_friction
    assert 0.6 < us[SCENES[0]] < 0.85


def test_failures_are_rows_and_the_dtypes_are_fixed():
    text = (REPO / "examples/cases/reconstruction_us.toml").read_text()
    rows = pd.DataFrame({"case": [text, "no/such/file.toml",
                                  str(REPO / "examples/cases/ricsac7_fit.toml")]})
    out = pim.scene_frame(rows)
    assert list(out.status) == ["found", "failed", "failed"]
    assert out.case[0] == "<row 0>"
    assert "cannot be read" in out.reason[1]
    assert "no scene evidence" in out.reason[2]
    assert out.v1_contact.dtype == "float64" and out.case.dtype == object
    empty = pim.scene_frame(rows.head(0))
    assert list(empty.columns) == list(pim.SCENE_COLUMNS)
    assert (empty.dtypes == out.dtypes).all()
    with pytest.raises(pim.InputError, match="no column 'path'"):
        pim.scene_frame(rows, column="path")


def test_dask_gives_the_same_frame():
    dd = pytest.importorskip("dask.dataframe")
    rows = pd.DataFrame({"case": SCENES * 2})
    lazy = dd.from_pandas(rows, npartitions=3).map_partitions(
        pim.scene_frame, meta=pim.scene_frame(rows.head(0)))
    out = lazy.compute(scheduler="processes", num_workers=2).reset_index(drop=True)
    pd.testing.assert_frame_equal(out, pim.scene_frame(rows, threads=None))
