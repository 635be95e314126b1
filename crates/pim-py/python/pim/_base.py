"""What every typed result shares: the document type, the number and table helpers, and the
velocities of both vehicles at one instant."""

from __future__ import annotations

import html
from dataclasses import dataclass
from typing import Any, Dict, Mapping, Optional, Sequence

Document = Dict[str, Any]


def _float(d: Mapping[str, Any], key: str) -> Optional[float]:
    v = d.get(key)
    return None if v is None else float(v)


def _fmt(v: Any, digits: int = 4) -> str:
    """A table cell: floats to ``digits`` significant figures (never ``-0``), None as a dash."""
    if v is None:
        return "\u2013"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, float):
        text = f"{v:.{digits}g}"
        return "0" if text in ("-0", "-0.0") else text
    return str(v)


def _table(header: Sequence[str], rows: Sequence[Sequence[Any]], caption: str = "") -> str:
    cells = "".join(f"<th>{html.escape(h)}</th>" for h in header)
    body = "".join(
        "<tr>" + "".join(f"<td>{html.escape(_fmt(c))}</td>" for c in row) + "</tr>" for row in rows
    )
    cap = f"<caption>{html.escape(caption)}</caption>" if caption else ""
    return f"<table>{cap}<thead><tr>{cells}</tr></thead><tbody>{body}</tbody></table>"


@dataclass(frozen=True)
class Motion:
    """One vehicle's velocity: ``vx``, ``vy`` (m/s) and yaw rate ``omega`` (rad/s), in the
    document's frame (natural: y to the left of x, yaw counter-clockwise)."""

    vx: float
    vy: float
    omega: float

    @property
    def speed(self) -> float:
        """The speed of the centre of gravity, m/s."""
        return float((self.vx**2 + self.vy**2) ** 0.5)

    @classmethod
    def _read(cls, d: Mapping[str, Any]) -> Motion:
        return cls(float(d["vx"]), float(d["vy"]), float(d["omega"]))


@dataclass(frozen=True)
class Velocities:
    """Both vehicles' velocities at one instant (contact or separation)."""

    vehicle1: Motion
    vehicle2: Motion

    @classmethod
    def _read(cls, d: Optional[Mapping[str, Any]]) -> Optional[Velocities]:
        if d is None:
            return None
        return cls(Motion._read(d["vehicle1"]), Motion._read(d["vehicle2"]))
