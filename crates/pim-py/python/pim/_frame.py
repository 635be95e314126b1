"""Frame in, frame out: :func:`fit_frame` refits the rows of a pandas DataFrame in the layout of
``data/ricsac.csv`` and returns the records of ``pim batch --format csv`` as a DataFrame with
fixed columns and dtypes, so that a cohort larger than one machine runs on an existing engine,
e.g. Dask::

    import dask.dataframe as dd
    rows = dd.read_csv("cohort-*.csv")
    records = rows.map_partitions(pim.fit_frame, meta=pim.fit_frame(rows._meta))

The function is a plain module-level function of its arguments (picklable, no global state):
each call parses its rows, fits them and returns their records, on ``threads`` cores.
"""

from __future__ import annotations

import io
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
