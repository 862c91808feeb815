"""Codimension-two points along a fold-of-cycles curve (core.fold_continuation), each
found between two consecutive curve points:

    - cusp: the fold's quadratic coefficient Dg.phi1 (k''(s)) changes sign (away from the
      curve's Bautin end: CUSP_AMPLITUDE);
    - bautin (generalised Hopf): the amplitude vanishes: the fold curve ends on the Hopf
      curve, where the first Lyapunov coefficient changes sign (core.lyapunov_coefficient
      locates it there, on the Hopf curve, independently);
    - fold-flip: a nontrivial multiplier crosses the unit circle near -1;
    - fold-ns: a complex pair crosses it (a torus curve ends there);
    - resonance-1:1: a third multiplier reaches +1.

Along a period-doubling curve (core.flip_continuation) the other multipliers are watched
likewise, the flow's and the one at -1 left out: resonance-1:2 (a second through -1),
flip-ns (a complex pair), fold-flip (one through +1).

Along a torus curve (core.torus_continuation) the pair's kappa = cos(arg mu) marks the
strong resonances: resonance-1:4 where it passes 0, resonance-1:3 at -1/2, and
resonance-1:2 / resonance-1:1 where it leaves (-1, 1) at -1 / +1 (the walk ends there);
the other multipliers, the pair on the circle left out: flip-ns (one through -1), double-ns
(another complex pair), fold-ns (one through +1). The Chenciner point (the torus's own
normal-form coefficient vanishing) is not looked for: that coefficient is not computed.

Multiplier crossings count only when the multiplier is off the circle by more than
UNIT_MARGIN on both sides and, along a walked curve, by more than CLEAR times its
uncertainty (its change under dt -> dt/2, core.multiplier_crossing) at the two points
either side; otherwise they are "undetermined" with the figures.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from core.floquet import Multipliers
from core.fold_continuation import CurvePoint, FoldCurve
from core.multiplier_crossing import CLEAR, uncertainty

#: The margin a multiplier crossing must clear on both sides: at a fold two multipliers
#: sit at +1 (the flow's and the fold's); round-off moves multipliers that sit on the
#: circle by ~1e-7 (core.floquet.FLOW_TOL's measurements).
UNIT_MARGIN = 1e-5
#: A cusp is claimed only where the amplitude is at least this fraction of the curve's
#: largest. Towards a Bautin point the fold degenerates (its quadratic coefficient goes to
#: zero with the amplitude squared) and the coefficient's sign stops being a property of
#: the curve: on the third fold curve in (k, tau) it changed sign at amplitude 0.02 (2 % of
#: the curve's largest) with GMRES at 1e-11, and already at 0.04 with GMRES at 1e-13 and
#: forward differences of 1e-5. There such a change is "undetermined", with that reason.
CUSP_AMPLITUDE = 0.1


@dataclass(frozen=True)
class Codim2:
    """A codimension-two point on the curve: its type and both parameters."""

    type: str
    first: float
    second: float
    period: float
    note: str = ""


#: The kind of a multiplier crossing the circle along a curve of folds, or of period
#: doublings: through -1, as a complex pair, through +1.
KINDS = {"fold": ("fold-flip", "fold-ns", "resonance-1:1"),
         "period-doubling": ("resonance-1:2", "flip-ns", "fold-flip"),
         "torus": ("flip-ns", "double-ns", "fold-ns")}
#: The strong resonances a torus curve's kappa = cos(arg mu) passes: 1:4 at 0, 1:3 at
#: -1/2; at -1 and +1 the pair meets on the real axis (1:2, 1:1), where the curve ends.
RESONANCES = {0.0: "resonance-1:4", -0.5: "resonance-1:3", -1.0: "resonance-1:2",
              1.0: "resonance-1:1"}


def crossings(a: CurvePoint, b: CurvePoint, largest: float = 0.0, what: str = "fold"
              ) -> list[Codim2]:
    """Codimension-two points between two consecutive points of a curve of ``what`` (fold,
    period-doubling or torus; see the module doc); ``largest``: the largest amplitude on
    the curve (CUSP_AMPLITUDE; a cusp is a fold curve's only)."""
    return _coefficients(a, b, largest, what) + through_circle([a, b], 1, what)


def _coefficients(a: CurvePoint, b: CurvePoint, largest: float, what: str) -> list[Codim2]:
    """A cusp (a fold's quadratic coefficient changing sign) or a strong resonance (a
    torus's kappa passing one) between a and b."""
    found: list[Codim2] = []
    if what == "fold" and a.curvature * b.curvature < 0:
        s = a.curvature / (a.curvature - b.curvature)
        if min(a.amplitude, b.amplitude) >= CUSP_AMPLITUDE * largest:
            found.append(_between("cusp", a, b, s, "the fold's quadratic coefficient vanishes"))
        else:
            found.append(_between("undetermined", a, b, s, (
                "the fold's quadratic coefficient changes sign where the fold degenerates "
                f"towards the Hopf curve (amplitude {min(a.amplitude, b.amplitude):.3g}): "
                "no cusp is claimed there")))
    if what == "torus":
        for at, kind in RESONANCES.items():
            if (a.kappa - at) * (b.kappa - at) < 0:
                s = (a.kappa - at) / (a.kappa - b.kappa)
                found.append(_between(kind, a, b, s, f"kappa = cos(arg mu) passes {at:g} "
                                      f"({a.kappa:.8g} -> {b.kappa:.8g})"))
    return found


#: A point's multiplier's uncertainty: (point, mu) -> its change under dt -> dt/2.
PointError = Callable[[CurvePoint, complex], float]


def through_circle(points: list[CurvePoint], j: int, what: str,
                   error: PointError | None = None) -> list[Codim2]:
    """The multipliers (but the bifurcation's own) that are clear of the circle at point j
    (UNIT_MARGIN) on the other side than at the last point before it where they were
    clear: followed back point by point (each to its nearest), so that a slow crossing,
    within the margin at the points next to it, is found once (one of a complex pair, Im
    >= 0). Located between the two points where |mu| - 1 changes sign if it does so once
    on the way; if it changes sign more often within the margin, where it crosses is not
    decided: "undetermined", with the figures. (The 3-slip orbit's second pair near the
    cube roots of unity, along its torus curve from tau = 10 to 20, wanders between
    0.999989 and 1.000014 before leaving the circle: the N-slip clusters move by ~1e-5
    under dt -> dt/2, tests/integration/test_real_crossings.py.) With ``error``, a
    crossing is claimed only where |mu| - 1 at those two clear points lies beyond CLEAR
    times its uncertainty (core.multiplier_crossing's rule for branches), and is
    undetermined with the figures otherwise."""
    b = points[j]
    at_minus_one, complex_pair, at_plus_one = KINDS[what]
    found: list[Codim2] = []
    for mu_b in others(b.multipliers, what):
        if mu_b.imag < 0 or abs(abs(mu_b) - 1.0) < UNIT_MARGIN:
            continue
        path = [(j, complex(mu_b))]          # the multiplier followed back, j downwards
        while path[-1][0] > 0:
            rest = others(points[path[-1][0] - 1].multipliers, what)
            if not rest.size:
                break
            mu = complex(rest[int(np.argmin(np.abs(rest - path[-1][1])))])
            path.append((path[-1][0] - 1, mu))
            if abs(abs(mu) - 1.0) >= UNIT_MARGIN:
                break
        (i, mu_a), off = path[-1], [abs(mu) - 1.0 for _, mu in reversed(path)]
        if len(path) == 1 or abs(off[0]) < UNIT_MARGIN or off[0] * off[-1] >= 0:
            continue
        if abs(mu_b.imag) > 1e-4:
            kind = complex_pair
        elif mu_b.real < 0:
            kind = at_minus_one
        else:
            kind = at_plus_one
        changes = [k for k in range(len(off) - 1) if off[k] * off[k + 1] < 0]
        s = off[0] / (off[0] - off[-1])
        if len(changes) != 1:
            found.append(_between("undetermined", points[i], b, s, (
                f"a {kind} crossing: multiplier {mu_a:.6g} -> {mu_b:.6g}, |mu| - 1 changing "
                f"sign {len(changes)} times within {UNIT_MARGIN:g} of the circle between "
                f"these two points ({len(off) - 2} between): where it crosses is not "
                "decided")))
        elif unclear := _unclear(points[i], b, mu_a, mu_b, error):  # two orbits at dt/2
            found.append(_between("undetermined", points[i], b, s, f"a {kind} crossing: "
                                  f"{unclear}: not beyond {CLEAR:g} uncertainties on both "
                                  "sides"))
        else:
            k = changes[0]
            lo, hi = points[i + k], points[i + k + 1]
            found.append(_between(kind, lo, hi, off[k] / (off[k] - off[k + 1]),
                                  f"multiplier {mu_a:.6g} -> {mu_b:.6g}"))
    return found


def _unclear(a: CurvePoint, b: CurvePoint, mu_a: complex, mu_b: complex,
             error: PointError | None) -> str:
    """"" when ``error`` is None or |mu| - 1 at a and at b lies beyond CLEAR times the
    multiplier's uncertainty there; else the figures."""
    if error is None:
        return ""
    ua, ub = error(a, mu_a), error(b, mu_b)
    ea, eb = abs(mu_a) - 1.0, abs(mu_b) - 1.0
    if abs(ea) > CLEAR * ua and abs(eb) > CLEAR * ub:
        return ""
    return (f"|mu| - 1 = {ea:+.1e} at ({a.first:.6g}, {a.second:.6g}) (uncertain by "
            f"{ua:.1e}) and {eb:+.1e} at ({b.first:.6g}, {b.second:.6g}) (uncertain by "
            f"{ub:.1e}; the change under dt -> dt/2)")


def point_error(curve: FoldCurve) -> PointError:
    """The uncertainty of a multiplier of a curve point: its change when the point's orbit
    is corrected again at dt / 2 (core.multiplier_crossing.uncertainty); infinite for a
    point without its unknowns."""
    def error(p: CurvePoint, mu: complex) -> float:
        if p.y is None:
            return math.inf
        n = curve.size
        return uncertainty(curve.map_at(p.y), p.y[:n], float(p.y[n]), p.multipliers, mu)
    return error


#: The multiplier a curve's own bifurcation puts on the circle, besides the flow's.
OWN_MULTIPLIER = {"fold": 1.0, "period-doubling": -1.0}


def others(m: Multipliers, what: str = "fold") -> np.ndarray:
    """The multipliers but the flow's and the one nearest the bifurcation's own
    (OWN_MULTIPLIER: a fold's second +1, a period doubling's -1; a torus's pair: the two
    nearest the unit circle)."""
    values = m.nontrivial
    if what == "torus":
        return values[np.sort(np.argsort(np.abs(np.abs(values) - 1.0))[2:])]
    if values.size:
        values = np.delete(values, int(np.argmin(np.abs(values - OWN_MULTIPLIER[what]))))
    return values


def _between(kind: str, a: CurvePoint, b: CurvePoint, s: float, note: str) -> Codim2:
    return Codim2(kind, a.first + s * (b.first - a.first), a.second + s * (b.second - a.second),
                  a.period + s * (b.period - a.period), note)


def codim2_points(curve: FoldCurve) -> list[Codim2]:
    """The codimension-two points along a walked curve, in order; a multiplier's crossing
    judged against its uncertainty at the points either side (``point_error``)."""
    found: list[Codim2] = []
    pts = curve.points
    largest = max((p.amplitude for p in pts), default=0.0)
    error = point_error(curve)
    for j in range(1, len(pts)):
        found.extend(_coefficients(pts[j - 1], pts[j], largest, curve.what))
        found.extend(through_circle(pts, j, curve.what, error))
    if curve.end.startswith("the amplitude vanished"):
        a, b = pts[-2], pts[-1]
        a2, b2 = a.amplitude ** 2, b.amplitude ** 2
        s = a2 / (a2 - b2) if a2 != b2 else 1.0  # p and q are linear in amplitude^2 there
        found.append(_between("bautin", a, b, s, "the fold curve's end on the Hopf curve, "
                                                 "extrapolated to zero amplitude"))
    return found


__all__ = ["OWN_MULTIPLIER", "Codim2", "codim2_points", "crossings", "others"]
