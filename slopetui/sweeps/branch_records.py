"""A branch point and a bifurcation as the faces show them and ``continue --json`` and
``branch --json`` print them: one shape for a branch computed here and one read back from
the store. Light (no numpy, no SQLAlchemy): the command line imports it at start."""

from __future__ import annotations

from typing import Any

#: value, period, amplitude (peak to peak of m_y), stable, leading_multiplier [re, im].
PointRecord = dict[str, Any]
#: type, value, period, multiplier [re, im], reason (what decided a multiplier's crossing,
#: "" where nothing had to: a fold, a Hopf end).
BifurcationRecord = dict[str, Any]


def point_record(value: float, period: float, amplitude: float, stable: bool,
                 leading: complex) -> PointRecord:
    return {"value": value, "period": period, "amplitude": amplitude, "stable": bool(stable),
            "leading_multiplier": [leading.real, leading.imag]}


def bifurcation_record(kind: str, value: float, period: float,
                       multiplier: complex, reason: str | None = "") -> BifurcationRecord:
    return {"type": kind, "value": value, "period": period,
            "multiplier": [multiplier.real, multiplier.imag], "reason": reason or ""}
