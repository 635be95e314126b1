"""Frame in, frame out: :func:`fit_frame` refits the rows of a pandas DataFrame in the layout of
``data/ricsac.csv`` and returns the records of ``pim batch --format csv`` as a DataFrame with
fixed columns and dtypes, so that a cohort larger than one machine runs on an existing engine,
e.g. Dask::

    import dask.dataframe as dd
    rows = dd.read_csv("cohort-*.csv")
    records = rows.map_partitions(pim.fit_frame, meta=pim.fit_frame(rows._meta))

:func:`scene_frame` does the same for scene cases: a frame with a column of case files (paths
or TOML texts) in, one whole reconstruction per row out (:data:`SCENE_COLUMNS`)::

    cases = dd.from_pandas(pd.DataFrame({"case": paths}), npartitions=8)
    out = cases.map_partitions(pim.scene_frame, meta=pim.scene_frame(cases._meta))

The functions are plain module-level functions of their arguments (picklable, no global
state): each call parses its rows, answers them and returns their records, on ``threads``
cores.
"""

from __future__ import annotations

import io
import json
from pathlib import Path
from typing import Any, Dict, Optional, Sequence

from . import _pim

# The columns of `pim batch --format csv` and their pandas dtypes. Text columns hold None
# where the record has no value; the two nullable flags are pandas' "boolean".
_TEXT = ("cost_function", "model", "branch", "outcome", "reason", "max_error_component",
         "contact_mode")
_FLAGS = ("sticking", "admissible")
COLUMNS: Sequence[str] = (
    "test", "cost_function", "model", "branch", "best", "outcome", "reason", "e", "mu", "em",
    "mu_max", "mu_ratio", "sticking", "cost", "energy_loss_percent", "dv1_fitted",
    "dv1_measured", "dv2_fitted", "dv2_measured", "max_residual", "admissible",
    "max_error_component", "max_error", "speed1_p05", "speed1_p95", "speed2_p05",
    "speed2_p95", "delta_v1_p05", "delta_v1_p95", "delta_v2_p05", "delta_v2_p95",
    "contact_mode", "et", "friction", "friction_max",
)
"""The columns of :func:`fit_frame`'s result, in order (those of ``pim batch --format csv``)."""


def _dtypes() -> Dict[str, str]:
    out: Dict[str, str] = {}
    for c in COLUMNS:
        if c == "test":
            out[c] = "int64"
        elif c == "best":
            out[c] = "bool"
        elif c in _FLAGS:
            out[c] = "boolean"
        elif c in _TEXT:
            out[c] = "object"
        else:
            out[c] = "float64"
    return out


def fit_frame(
    rows: Any,
    costs: Sequence[str] = ("q1", "q2", "q3"),
    branches: Sequence[str] = ("free", "zero"),
    e_max: float = 0.2,
    moment_form: str = "corrected",
    models: Sequence[str] = ("pim",),
    threads: Optional[int] = 1,
    conditions: str = "corrected",
) -> Any:
    """Refits every row of ``rows`` (a pandas DataFrame with the columns of
    ``data/ricsac.csv``: ``test``, the vehicles, geometry and velocities) under each cost
    function, model and moment branch, and returns one row per record, the same records and
    columns as ``pim batch --format csv`` on a file of those rows (SI; :data:`COLUMNS`, fixed
    dtypes: ``test`` int64, ``best`` bool, ``sticking`` and ``admissible`` nullable boolean, the
    text columns object, the rest float64, NaN where a record has no value).

    ``conditions="v18"`` fits under Vossou & Koulocheris (2018)'s setting, as
    ``pim batch --conditions v18``. ``threads`` defaults to 1: under a distributed scheduler each worker process runs one
    partition at a time; ``None`` uses every core of the machine. An empty frame gives an
    empty result with the same columns and dtypes (Dask's ``meta``). A row that cannot be read
    raises :class:`InputError` naming the row (its line in the frame's CSV text, the header
    being line 1) and the field.

    >>> import pandas as pd
    >>> rows = pd.read_csv("data/ricsac.csv")
    >>> out = fit_frame(rows[rows.test == 7], costs=["q3"])
    >>> list(out.branch), [round(c, 4) for c in out.cost]
    (['free', 'zero'], [10.7218, 2.0077])
    """
    import pandas as pd

    if len(rows) == 0:
        return pd.DataFrame({c: pd.Series(dtype=t) for c, t in _dtypes().items()})
    text = rows.to_csv(index=False)
    return _read(_pim.batch_csv(text, name="<frame>", costs=list(costs),
                                branches=list(branches), threads=threads, e_max=e_max,
                                moment_form=moment_form, models=list(models),
                                conditions=conditions))


def _read(text: str) -> Any:
    """The records of ``pim batch --format csv`` as a frame with :data:`COLUMNS`' dtypes."""
    import pandas as pd

    dtypes = _dtypes()
    frame = pd.read_csv(io.StringIO(text), dtype={c: t for c, t in dtypes.items()
                                                  if t not in ("bool", "boolean")},
                        keep_default_na=False, na_values=[""])
    flags = frame[["best", *_FLAGS]].replace({"true": True, "false": False})
    frame["best"] = flags["best"].astype("bool")
    for c in _FLAGS:
        frame[c] = flags[c].astype("boolean")
    for c in _TEXT:
        frame[c] = frame[c].astype(object).where(frame[c].notna(), None)
    return frame[list(COLUMNS)]


SCENE_COLUMNS: Sequence[str] = (
    "case", "status", "reason", "chi_square", "degrees_of_freedom", "p_value", "e", "mu", "em",
    "energy_loss_percent", "v1_before_braking", "v1_contact", "v1_separation", "v1_turns",
    "v2_before_braking", "v2_contact", "v2_separation", "v2_turns", "road_friction",
)
"""The columns of :func:`scene_frame`'s result, in order: the case, its status (``found``,
``inconsistent``, ``no_solution``, or ``failed`` for a case that cannot be read or has no scene)
and reason, the chi-square, degrees of freedom and p, the coefficients and energy loss, each
vehicle's speed where its braking began, at contact and at separation (m/s) and its full turns
to rest, and the fitted road friction (NaN where the case holds it)."""

_SCENE_TEXT = ("case", "status", "reason")


def _scene_dtypes() -> Dict[str, str]:
    return {c: ("object" if c in _SCENE_TEXT else "float64") for c in SCENE_COLUMNS}


def scene_frame(rows: Any, column: str = "case", threads: Optional[int] = 1) -> Any:
    """Reconstructs the scene case of every row of ``rows`` (a pandas DataFrame whose
    ``column`` holds a case file's path or its TOML text) and returns one row per case with
    :data:`SCENE_COLUMNS` (SI, fixed dtypes: the text columns object, the rest float64, NaN
    where a case has no value): what ``pim fit`` of each file answers, in the rows' order.
    The cases are reconstructed in parallel on ``threads`` cores (``None``: every core; 1 by
    default, for one partition per worker under Dask). A case that cannot be read, or has no
    scene evidence, is a row with status ``failed`` and its reason, not an exception. An empty
    frame gives an empty result with the same columns and dtypes (Dask's ``meta``).

    >>> import pandas as pd
    >>> out = scene_frame(pd.DataFrame({"case": ["examples/cases/reconstruction_us.toml"]}))
    >>> list(out.status), [round(v / 0.44704, 1) for v in (out.v1_contact[0], out.v2_contact[0])]
    (['found'], [38.1, 27.2])
    """
    import pandas as pd

    if column not in rows.columns:
        from ._pim import InputError

        raise InputError(f"scene_frame: no column {column!r}; the frame has {list(rows.columns)}")
    names, texts, unread = [], [], {}
    for i, value in enumerate(rows[column]):
        s = str(value)
        if "\n" not in s and "=" not in s:
            try:
                texts.append(Path(s).read_text())
            except OSError as e:
                unread[i] = {"case": s, "status": "failed",
                             "reason": f"{s}: cannot be read: {e.strerror}"}
                continue
            names.append(s)
        else:
            names.append(f"<row {i}>")
            texts.append(s)
    dtypes = _scene_dtypes()
    if not names and not unread:
        return pd.DataFrame({c: pd.Series(dtype=t) for c, t in dtypes.items()})
    answered = iter(json.loads(_pim.reconstruct_many(names, texts, threads=threads))
                    if names else [])
    records = [unread[i] if i in unread else next(answered) for i in range(len(rows))]
    frame = pd.DataFrame([{c: r.get(c) for c in SCENE_COLUMNS} for r in records],
                         columns=list(SCENE_COLUMNS))
    for c, t in dtypes.items():
        if t == "float64":
            frame[c] = pd.to_numeric(frame[c], errors="coerce").astype("float64")
        else:
            frame[c] = frame[c].astype(object).where(frame[c].notna(), None)
    return frame
