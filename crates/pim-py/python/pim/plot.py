"""Optional matplotlib figures of the package's results (``pip install matplotlib``).

* :func:`intervals`: the 5-95 % range of each quantity of an :class:`~pim.Uncertainty`, its
  median and the nominal fit, with the range written beside each bar;
* :func:`batch`: one value per test and cost function of :func:`pim.batch`'s records (best
  branch), grouped bars as in ``pim batch --out``'s figures, infeasible fits marked ``x``.

Each function draws on ``ax`` (a new figure when None) and returns the axes.

>>> import matplotlib
>>> matplotlib.use("Agg")
>>> import pim, pim.plot
>>> u = pim.uncertainty("examples/cases/ricsac7_uncertainty.toml", cost="q2", draws=20)
>>> ax = pim.plot.intervals(u)
>>> [t.get_text() for t in ax.get_yticklabels()]
['speed 1', 'speed 2', 'delta-V 1', 'delta-V 2']
"""

from __future__ import annotations

from typing import Any, Dict, List, Optional, Sequence, Tuple

from . import _CONVERT
from ._base import _fmt
from ._results import Records, Uncertainty

_SPEEDS = ("speed1", "speed2", "delta_v1", "delta_v2")
_LABELS = {
    "speed1": "speed 1",
    "speed2": "speed 2",
    "delta_v1": "delta-V 1",
    "delta_v2": "delta-V 2",
    "e": "e",
    "mu": "mu",
    "em": "em",
    "energy_loss_percent": "energy loss",
}
# Speed units of `units=`: (factor from m/s, label), the factors those of records_frame.
_SPEED_UNITS = {
    "si": (1.0, "m/s"),
    "kmh": (_CONVERT["kmh"]["mps"][1], "km/h"),
    "us": (_CONVERT["us"]["mps"][1], "mph"),
}
_VALUE_LABELS = {
    "cost": "minimum cost (weighted sum of squares)",
    "energy_loss_percent": "energy loss [%]",
    "e": "restitution e [-]",
    "mu": "equivalent friction mu [-]",
    "em": "moment restitution em [-]",
}
_COLOURS = {"q1": "#1f77b4", "q2": "#ff7f0e", "q3": "#2ca02c"}


def _pyplot() -> Any:
    try:
        import matplotlib.pyplot as plt
    except ImportError as exc:  # pragma: no cover - exercised without matplotlib
        raise ImportError(
            "pim.plot needs matplotlib, which is not installed: pip install matplotlib"
        ) from exc
    return plt


def _axes(ax: Any, size: Tuple[float, float]) -> Any:
    if ax is not None:
        return ax
    _, new = _pyplot().subplots(figsize=size, layout="constrained")
    return new


def intervals(
    study: Uncertainty,
    quantities: Sequence[str] = _SPEEDS,
    units: str = "si",
    ax: Any = None,
) -> Any:
    """The 5-95 % range of each of ``quantities`` (default the speeds and delta-Vs) as a
    horizontal bar, its median as a tick and the nominal fit as a dot, the range written
    beside the bar. Quantities in m/s are converted to ``units`` (``"si"``, ``"kmh"``,
    ``"us"``); all ``quantities`` must share one unit."""
    if units not in _SPEED_UNITS:
        raise ValueError(f"units = {units!r}: not an accepted value; accepted: 'si', 'us', 'kmh'")
    missing = [q for q in quantities if q not in study.quantities]
    if missing:
        raise ValueError(f"no quantity {missing[0]!r} in the study; it has: "
                         + ", ".join(study.quantities))
    kinds = {study[q].unit for q in quantities}
    if len(kinds) > 1:
        raise ValueError(f"quantities {list(quantities)} mix units {sorted(kinds)}: plot each "
                         "unit on its own axes")
    unit = kinds.pop() if kinds else ""
    factor, label = _SPEED_UNITS[units] if unit == "m/s" else (1.0, unit)
    ax = _axes(ax, (7.0, 0.5 + 0.6 * len(quantities)))
    rows = list(reversed(range(len(quantities))))
    highs: List[float] = []
    for y, name in zip(rows, quantities):
        q = study[name]
        if q.p05 is None or q.p95 is None:
            ax.text(0.0, y, "no draws with a solution", va="center", fontsize=9)
            continue
        lo, hi = q.p05 * factor, q.p95 * factor
        highs.append(hi)
        ax.barh(y, hi - lo, left=lo, height=0.45, color="#9ecae1", edgecolor="#3182bd")
        if q.p50 is not None:
            ax.plot([q.p50 * factor] * 2, [y - 0.22, y + 0.22], color="#08519c", lw=2)
        if q.nominal is not None:
            ax.plot(q.nominal * factor, y, "o", color="black", ms=4)
        note = " (not determined)" if q.not_determined else (
            " (ended by a bound)" if q.reaches_bound else "")
        ax.annotate(f"{_fmt(lo, 3)} to {_fmt(hi, 3)} {label}{note}", (hi, y),
                    xytext=(6, 0), textcoords="offset points", va="center", fontsize=9)
    ax.set_yticks(rows, [_LABELS.get(q, q) for q in quantities])
    ax.set_xlabel(f"{label}: bar 5-95 %, tick median, dot nominal fit "
                  f"({study.feasible_draws} draws)")
    if highs:
        lo_all = min(study[q].p05 or 0.0 for q in quantities) * factor
        span = max(highs) - lo_all or 1.0
        # Room on the right for the written ranges.
        ax.set_xlim(lo_all - 0.05 * span, max(highs) + 0.6 * span)
    ax.set_ylim(-0.6, len(quantities) - 0.4)
    ax.spines[["top", "right"]].set_visible(False)
    return ax


def batch(
    records: Records,
    value: str = "cost",
    model: str = "pim",
    ax: Any = None,
) -> Any:
    """One bar per test and cost function of ``value`` (a numeric field of the records:
    ``"cost"``, ``"e"``, ``"mu"``, ``"em"``, ``"energy_loss_percent"``) for the best branch
    of ``model``, grouped by test; a fit without a solution is marked ``x`` on the axis."""
    mine = [r for r in records if r.get("model", "pim") == model and "test" in r]
    if not mine:
        raise ValueError(f"no records of model {model!r} with a test number")
    if value not in mine[0]:
        raise ValueError(f"records have no field {value!r}")
    tests = sorted({int(r["test"]) for r in mine})
    costs = sorted({str(r["cost_function"]) for r in mine})
    cells: Dict[Tuple[int, str], Optional[float]] = {}
    for r in mine:
        key = (int(r["test"]), str(r["cost_function"]))
        v = r.get(value)
        if r.get("best") and v is not None:
            cells[key] = float(v)
        else:
            cells.setdefault(key, None)
    ax = _axes(ax, (max(6.0, 1.5 + 0.25 * len(tests) * max(1, len(costs))), 3.5))
    width = 0.8 / max(1, len(costs))
    for j, cost in enumerate(costs):
        xs = [i + (j - (len(costs) - 1) / 2) * width for i in range(len(tests))]
        ys = [cells.get((t, cost)) for t in tests]
        colour = _COLOURS.get(cost, None)
        ax.bar([x for x, y in zip(xs, ys) if y is not None],
               [y for y in ys if y is not None], width * 0.9, color=colour,
               label=cost.upper())
        none = [x for x, y in zip(xs, ys) if y is None]
        if none:
            ax.plot(none, [0.0] * len(none), "x", color=colour, ms=7, mew=2, clip_on=False)
    ax.axhline(0.0, color="#666666", lw=0.8)
    ax.set_xticks(range(len(tests)), [str(t) for t in tests])
    ax.set_xlabel("test (x: no solution)")
    ax.set_ylabel(_VALUE_LABELS.get(value, value.replace("_", " ")))
    ax.legend(frameon=False, ncols=len(costs), loc="upper left", bbox_to_anchor=(0.0, 1.12))
    ax.spines[["top", "right"]].set_visible(False)
    return ax
