"""pim.fit_frame: frame in, frame out, and the same records under Dask's distributed scheduler
(a local cluster of two worker processes) as `pim batch` on a file of the same rows."""

import pickle
import subprocess
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import pim
from pim._frame import _read

REPO = Path(__file__).resolve().parents[3]
KEYS = ["test", "cost_function", "model", "branch"]


def cohort(copies: int) -> pd.DataFrame:
    """RICSAC's rows `copies` times over, each copy a distinct test number with its measured
    separation velocities moved by a seeded 0.1 m/s noise (distinct problems, not repeats)."""
    rows = pd.read_csv(REPO / "data" / "ricsac.csv")
    rng = np.random.default_rng(7)
    parts = []
    for k in range(copies):
        part = rows.copy()
        part["test"] = part["test"] + 100 * k
        if k:
            for c in ("vf1x_mps", "vf1y_mps", "vf2x_mps", "vf2y_mps"):
                part[c] = (part[c] + rng.normal(0.0, 0.1, len(part))).round(3)
        parts.append(part)
    return pd.concat(parts, ignore_index=True)


def same(a: pd.DataFrame, b: pd.DataFrame) -> None:
    a = a.sort_values(KEYS).reset_index(drop=True)
    b = b.sort_values(KEYS).reset_index(drop=True)
    pd.testing.assert_frame_equal(a, b)


def test_columns_and_dtypes_are_fixed():
    rows = pd.read_csv(REPO / "data" / "ricsac.csv")
    full = pim.fit_frame(rows)
    empty = pim.fit_frame(rows.head(0))
    assert list(full.columns) == list(pim.COLUMNS) == list(empty.columns)
    assert dict(full.dtypes) == dict(empty.dtypes)
    # Infeasible rows (Q1 of tests 1, 6, 7, 10, 11) have no numbers but keep the dtypes.
    one = pim.fit_frame(rows[rows.test == 1], costs=["q1"])
    assert list(one.outcome) == ["infeasible", "infeasible"]
    assert dict(one.dtypes) == dict(full.dtypes)
    assert one.cost.isna().all() and one.sticking.isna().all()


def test_same_records_as_pim_batch(tmp_path):
    rows = cohort(3)
    path = tmp_path / "rows.csv"
    rows.to_csv(path, index=False)
    ours = pim.fit_frame(rows)
    assert len(ours) == 6 * len(rows)
    # The records of the command line on a file of the same rows.
    exe = REPO / "target" / "release" / "pim"
    if not exe.exists():
        subprocess.run(["cargo", "build", "--release", "-p", "pim-cli"], cwd=REPO, check=True)
    out = subprocess.run([str(exe), "batch", str(path), "--format", "csv"],
                         capture_output=True, text=True, check=False)
    assert out.returncode == 0, out.stderr
    same(ours, _read(out.stdout))
    # And the typed records of pim.batch, field by field where both have them.
    records = pim.batch(path)
    by_key = {(r["test"], r["cost_function"], r["model"], r["moment_branch"]): r for r in records}
    for row in ours.itertuples():
        r = by_key[(row.test, row.cost_function, row.model, row.branch)]
        assert row.outcome == r["outcome"]
        for c in ("cost", "e", "mu", "em"):
            v = getattr(row, c)
            assert (pd.isna(v) and r.get(c) is None) or v == pytest.approx(r[c], rel=1e-12)


def test_picklable_and_an_input_error_names_the_row():
    f = pickle.loads(pickle.dumps(pim.fit_frame))
    rows = pd.read_csv(REPO / "data" / "ricsac.csv")
    bad = rows.copy()
    bad.loc[2, "mass1_kg"] = -5.0
    with pytest.raises(pim.InputError, match=r"<frame>:4: column 5 `mass1_kg`: must be a number"):
        f(bad)


def test_dask_local_cluster_of_two_workers():
    dd = pytest.importorskip("dask.dataframe")
    distributed = pytest.importorskip("distributed")
    rows = cohort(30)  # 330 crashes, 1,980 fits
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        frame = dd.from_pandas(rows, npartitions=6)
        lazy = frame.map_partitions(pim.fit_frame, meta=pim.fit_frame(rows.head(0)))
        start = time.perf_counter()
        out = lazy.compute()
        seconds = time.perf_counter() - start
        assert len(client.scheduler_info()["workers"]) == 2
    assert len(out) == 6 * len(rows) == 1980
    same(out.reset_index(drop=True), pim.fit_frame(rows, threads=None))
    print(f"dask, 2 workers: {len(rows)} crashes, {len(out)} records in {seconds:.2f} s")
