"""A two-parameter curve's point and codimension-two point as the faces show them and
``continue --param2 --json`` and ``curve --json`` print them: one shape for a curve computed
here and one read back from the store. Light (no numpy): the command line imports it at
start."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from slopetui.display_text import terminal_safe


def curve_solver(dt: float, kind: str, max_points: int, max_step: float,
                 to2: float) -> dict[str, Any]:
    """The solver facts of a curve, as asked (a core.curve_start.CurveSpec's, or a stored
    row's)."""
    return {"method": "rk4", "dt": dt, "curve": kind, "points": max_points,
            "max_step": max_step, "to2": to2}


def curve_record(name: str, second: str, point: Any, kind: str = "fold") -> dict[str, Any]:
    """One point of the curve: both parameters by name and the period; a fold's amplitude
    (peak to peak of m_y) and its largest multiplier but the two a fold has at +1 (inside
    the circle: the fold's orbit is otherwise stable; its own stability changes there); a
    Hopf point's l1 and criticality; a period doubling's like a fold's, its own multiplier
    being the one at -1; a torus's too, with its own pair's multiplier on the circle
    (``torus_multiplier``, Im >= 0: its angle is the torus's rotation number times 2 pi)."""
    out: dict[str, Any] = {name: point.first, second: point.second, "period": point.period}
    if point.l1 is not None:
        out["l1"] = point.l1
        out["criticality"] = "supercritical" if point.l1 < 0 else "subcritical"
        return out
    return {**out, **multiplier_fields(point.amplitude, point.multipliers, kind)}


#: What a curve's kind is a curve of, as core.codim2 names it.
WHAT = {"fold": "fold", "pd": "period-doubling", "ns": "torus"}


def multiplier_fields(amplitude: float | None, m: Any, kind: str) -> dict[str, Any]:
    """A point's amplitude and its largest multiplier but the bifurcation's own (a fold's
    two at +1, the flow's and the fold's; a period doubling's flow multiplier and -1; a
    torus's flow multiplier and its pair: core.codim2.others), and a torus's own
    multiplier (the one of the pair nearest the circle with Im >= 0)."""
    import numpy as np  # numpy: module docstring

    from core.codim2 import others

    out: dict[str, Any] = {"amplitude": amplitude}
    rest = others(m, WHAT[kind]) if m is not None else np.array([])
    lead = complex(rest[0]) if rest.size else 0j
    out["leading_multiplier"] = [lead.real, lead.imag]
    if kind == "ns" and m is not None and m.nontrivial.size:
        values = m.nontrivial
        own = complex(values[int(np.argmin(np.abs(np.abs(values) - 1.0)))])
        out["torus_multiplier"] = [own.real, abs(own.imag)]
    return out


def codim2_record(name: str, second: str, c: Any) -> dict[str, Any]:
    return {"type": c.type, name: c.first, second: c.second, "period": c.period,
            "note": c.note}


def print_curve_point(name: str, second: str, point: Mapping[str, Any]) -> None:
    extra = (f"l1 {point['l1']:+.6g} ({point['criticality']})" if "l1" in point else
             f"amplitude {point['amplitude']:.6g}, next multiplier "
             f"|mu| {abs(complex(*point['leading_multiplier'])):.4g}")
    if "torus_multiplier" in point:
        own = complex(*point["torus_multiplier"])
        extra += f", torus multiplier {own.real:.8f}{own.imag:+.3e}i"
    print(f"{name} = {point[name]:<14.10g} {second} = {point[second]:<12.8g} period "
          f"{point['period']:<12.8g} {extra}", flush=True)


def print_codim2(name: str, second: str, found: Sequence[Mapping[str, Any]]) -> None:
    for b in found:
        print(f"{terminal_safe(b['type']):<14} {name} = {b[name]:.8g}, {second} = "
              f"{b[second]:.8g}, period {b['period']:.8g}  ({terminal_safe(b['note'])})")
    if not found:
        print("no codimension-two point on this curve")
