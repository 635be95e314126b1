"""Planar Impact Mechanics (Brach) for two-vehicle collision reconstruction, from Python.

The same solver, certified fit and documents as the ``pim`` command: every function returns
the document that ``pim <command> --format json`` prints for the same input, made by the same
Rust code (nothing is re-implemented here). Units are SI in every document: m/s, rad/s, kg,
m, J, degrees for angles.

A *case* is a case file of the ``pim`` command, given as TOML text, as a path (``str`` or
``os.PathLike``), or as a dict of the same shape::

    [vehicle1]                 # natural form: heading = where the nose points (deg)
    mass = 1036.0              # kg
    yaw_inertia = 1348.0       # kg m^2
    heading = 180.0
    impact_point = { x = 1.4, y = 0.15 }   # m from the CG, x forward, y to the left
    [vehicle2]                 # or: barrier = true (a fixed rigid barrier, nothing else)
    ...
    [impact]
    crush_angle = 0.0          # deg, the crush surface's normal
    [estimates.initial]        # fit: estimated velocities at contact (and [estimates.final])
    vehicle1 = { vx = -9.48, vy = 0.0, omega = 0.0 }

``pim solve --help`` and ``pim fit --help`` describe every section ([units], [sigma],
[known], [bounds], [[observations]], [uncertainty]).

Cost functions (``cost=``), after Vossou & Koulocheris (2018):

* ``"q1"``: the separation velocities are known exactly, the contact velocities estimated;
* ``"q2"``: the contact velocities are known exactly, the separation velocities estimated
  (Brach's fits);
* ``"q3"``: all twelve velocity components estimated;
* ``None``: the case's own ``[known]`` components held fixed, ``[estimates]`` estimated.

Each fit searches both moment branches: ``"free"`` (e_m in [-1, 0]) and ``"zero"`` (e_m = 1,
no moment impulse), and certifies the global optimum of each.

Errors: :class:`InputError` for bad input (the command line's message, naming the file and
field), :class:`NoSolution` when the model has no answer.
"""

from ._pim import (  # noqa: F401
    __version__,
    InputError,
    NoSolution,
    batch,
    fit,
    predict_dv,
    solve,
    uncertainty,
)
from ._pim import draw as _draw
from ._pim import report as _report

__all__ = [
    "__version__",
    "InputError",
    "NoSolution",
    "Report",
    "SVG",
    "batch",
    "draw",
    "fit",
    "predict_dv",
    "records_frame",
    "report",
    "solve",
    "uncertainty",
]


class SVG(str):
    """SVG text that a notebook shows as a picture (``_repr_svg_``); otherwise a ``str``."""

    def _repr_svg_(self):
        return str(self)


def draw(case, no_slip=False, moment_form="corrected", units=None):
    """The scale diagram of ``pim draw`` as :class:`SVG` text (a ``str`` a notebook shows as a
    picture), labelled in the case's units or ``units`` (``"si"``, ``"us"``, ``"kmh"``).

    >>> svg = draw("examples/cases/side_impact.toml")
    >>> svg.startswith("<svg"), svg._repr_svg_() == svg
    (True, True)
    """
    return SVG(_draw(case, no_slip=no_slip, moment_form=moment_form, units=units))


class Report:
    """The report of a crash, as ``pim report`` writes it: ``html`` (one self-contained page,
    figures inline) and ``markdown``; a notebook shows the page (``_repr_html_``)."""

    def __init__(self, html, markdown):
        self.html = html
        self.markdown = markdown

    def _repr_html_(self):
        return self.html

    def save(self, path):
        """Writes the HTML page to ``path``."""
        with open(path, "w", encoding="utf-8") as f:
            f.write(self.html)


def report(case, cost=None, draws=None, seed=None, units=None, solve=False):
    """The report of a crash (``pim report``): a fit case is fitted under ``cost``, a solve
    case solved (``solve=True`` picks the solve of a case that holds both); with [sigma] or
    [uncertainty] the answer's ranges come from ``draws`` refits (default 200, 0 for none).

    >>> r = report("examples/cases/side_impact.toml")
    >>> r.html.startswith("<!DOCTYPE html>"), "## Answer" in r.markdown
    (True, True)
    """
    html, markdown = _report(case, cost=cost, draws=draws, seed=seed, units=units, solve=solve)
    return Report(html, markdown)


# The twelve velocity components, in the order of the records' 12-element lists.
_COMPONENTS = ["vi1x", "vi1y", "wi1", "vi2x", "vi2y", "wi2",
               "vf1x", "vf1y", "wf1", "vf2x", "vf2y", "wf2"]


def _flatten(prefix, value, out):
    if prefix == "velocity_error" and isinstance(value, list) and len(value) == 12:
        for name, v in zip(_COMPONENTS, value):
            out[f"velocity_error_{name}"] = v
        return
    if isinstance(value, dict):
        for k, v in value.items():
            _flatten(f"{prefix}_{k}" if prefix else str(k), v, out)
    elif isinstance(value, list) and value and all(isinstance(v, (int, float)) for v in value):
        for i, v in enumerate(value, start=1):
            out[f"{prefix}_{i}"] = v
    elif isinstance(value, list):
        # Lists of records (constraints, ranges): kept whole in one cell.
        out[prefix] = value
    else:
        out[prefix] = value


# Unit suffixes of the flat columns: (test on the name, suffix), first match wins. Angles are
# degrees, velocities m/s, yaw rates rad/s, energies J, impulses N s (moment: N m s).
_UNIT_RULES = [
    (lambda n: n.endswith("_percent"), "pct"),
    (lambda n: n.startswith("velocity_error_w"), "radps"),
    (lambda n: n.startswith("velocity_error_v"), "mps"),
    (lambda n: n.endswith(("heading", "pdof", "_phi", "crush_angle")), "deg"),
    (lambda n: n.endswith(("omega", "yaw_rate_change")), "radps"),
    (lambda n: n.endswith(("_vx", "_vy", "speed_initial", "speed_final")), "mps"),
    (lambda n: "delta_v" in n and "relative" not in n and "detail" not in n, "mps"),
    (lambda n: n.endswith("energy_loss"), "j"),
    (lambda n: n == "impulse_moment", "nms"),
    (lambda n: n.startswith("impulse_"), "ns"),
    (lambda n: n.endswith("_d"), "m"),
]


def _with_unit(name):
    for test, unit in _UNIT_RULES:
        if test(name):
            if unit == "pct":
                return name[: -len("_percent")] + "_pct"
            return f"{name}_{unit}"
    return name


# Conversions of the SI suffixes for ``records_frame(..., units=)``: suffix -> (new suffix,
# factor). Exact definitions: 1 mph = 0.44704 m/s, 1 ft = 0.3048 m, 1 lbf = 4.4482216152605 N.
_LBF = 4.4482216152605
_CONVERT = {
    "si": {},
    "us": {
        "mps": ("mph", 1.0 / 0.44704),
        "radps": ("degps", 180.0 / 3.141592653589793),
        "j": ("ftlbf", 1.0 / (_LBF * 0.3048)),
        "ns": ("lbfs", 1.0 / _LBF),
        "nms": ("lbfsft", 1.0 / (_LBF * 0.3048)),
        "m": ("ft", 1.0 / 0.3048),
    },
    "kmh": {
        "mps": ("kmh", 3.6),
        "radps": ("degps", 180.0 / 3.141592653589793),
    },
}


def records_frame(records, units="si"):
    """A pandas DataFrame with one row per record and flat, unit-suffixed columns.

    ``records`` is the list that :func:`batch` returns, a fit document (its branches become
    the rows), or any list of flat or nested dicts. Nested fields are joined with ``_``
    (``initial_vehicle1_vx_mps``, ``vehicles_1_delta_v_mps``); lists of numbers become one
    column per element. Units: ``_mps`` m/s, ``_radps`` rad/s, ``_deg`` degrees, ``_j``
    joules, ``_ns`` newton seconds, ``_m`` metres, ``_pct`` percent.

    Columns that repeat another (``moment_branch``) or only stand for a nested field absent
    from every row are left out; the velocity errors are named by component
    (``velocity_error_vf1x_mps``).

    ``units="us"`` converts those columns to mph (``_mph``), deg/s (``_degps``), ft lbf
    (``_ftlbf``), lbf s (``_lbfs``) and feet (``_ft``); ``units="kmh"`` speeds to km/h and yaw
    rates to deg/s. The documents themselves are always SI (their ``units`` says so).

    pandas is optional for the package and needed here: ``pip install pandas``.
    """
    try:
        import pandas as pd
    except ImportError as exc:  # pragma: no cover - exercised without pandas
        raise ImportError(
            "pim.records_frame needs pandas, which is not installed: pip install pandas "
            "(or pip install 'pim[pandas]')"
        ) from exc
    if units not in _CONVERT:
        raise InputError(f"units = {units!r}: not an accepted value; accepted: 'si', 'us', 'kmh'")
    convert = _CONVERT[units]
    if isinstance(records, dict) and "branches" in records:
        records = [dict(b, cost_function=records.get("cost_function")) for b in records["branches"]]
    rows = []
    for r in records:
        flat = {}
        for k, v in r.items():
            if k == "vehicles" and isinstance(v, list):
                for i, veh in enumerate(v, start=1):
                    _flatten(f"vehicle{i}", veh, flat)
            else:
                _flatten(k, v, flat)
        row = {}
        for k, v in flat.items():
            name = _with_unit(k)
            suffix = name.rsplit("_", 1)[-1]
            if suffix in convert and name != k:
                new, factor = convert[suffix]
                name = name[: -len(suffix)] + new
                if isinstance(v, (int, float)) and not isinstance(v, bool):
                    v = v * factor
            row[name] = v
        rows.append(row)
    frame = pd.DataFrame(rows)
    return _without_placeholders_and_twins(frame)


def _without_placeholders_and_twins(frame):
    """Drops the columns that say nothing the others do not: a nested field absent from every
    row (``initial`` of records whose others have ``initial_vehicle1_vx_mps``), and the
    records' duplicates (``moment_branch`` beside ``moment``, ``vehicle1_delta_v_*`` beside
    ``delta_v_vehicle1_*``) when equal in every row."""
    drop = []
    columns = list(frame.columns)
    for c in columns:
        if frame[c].isna().all():
            base = c.rsplit("_", 1)[0] if c.rsplit("_", 1)[-1] in _SUFFIXES else c
            # `vehicles` is flattened as vehicle1_*, vehicle2_*.
            stem = "vehicle1" if base == "vehicles" else base
            if any(o != c and o.startswith(stem + "_") for o in columns):
                drop.append(c)
    twins = [("moment_branch", "moment")]
    for c in columns:
        for k in ("1", "2"):
            prefix = f"vehicle{k}_delta_v_"
            if c.startswith(prefix) and c.count("_") == 3:
                twins.append((c, f"delta_v_vehicle{k}_" + c[len(prefix):]))
    for twin, kept in twins:
        if twin in frame and kept in frame and frame[twin].equals(frame[kept]):
            drop.append(twin)
    return frame.drop(columns=sorted(set(drop)))


_SUFFIXES = {"mps", "radps", "deg", "j", "ns", "nms", "m", "pct",
             "mph", "kmh", "degps", "ftlbf", "lbfs", "lbfsft", "ft"}
