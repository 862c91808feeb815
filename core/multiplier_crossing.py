"""Whether a Floquet multiplier really crossed the unit circle between two branch points,
and where.

A branch point's multipliers (core.floquet) carry an error: the scheme's (the orbit of
the RK4 map at dt, not of eqs. 6a-6e), the orbit's residual and ARPACK's tolerance. Most
multipliers are simple and that error is ~1e-9 (the flow multiplier's distance from 1).
But on the n-slip orbits (core.orbit_seed) 2 (n - 1) multipliers sit near the n-th roots
of unity in nearly defective clusters, and a cluster's eigenvalues move by the square
root of a perturbation: at tau = 10, N = 2 the pair near -1 is 1e-5 apart and its moduli
flip across 1 from one branch point to the next. So each candidate crossing is judged
against its multiplier's uncertainty, measured as the multiplier's change when the same
orbit is corrected again at dt / 2 (``uncertainty``): the crossing is real when |mu| - 1
lies beyond CLEAR times that on both sides, with opposite signs, and undetermined (with
the figures) otherwise. A real crossing is then located on corrected orbits: the orbit
is corrected at the parameter where the secant of |mu| - 1 vanishes, |mu| - 1 is
evaluated there, and the bracket shrinks (regula falsi, Illinois) until it is shorter
than LOCATE_TOL.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicSpline

from core.floquet import Multipliers, multipliers
from core.orbit import Grid, OrbitError, PeriodMap
from core.shooting import correct

#: A crossing is real when |mu| - 1 lies beyond CLEAR times its multiplier's uncertainty
#: on both sides. The uncertainty is itself an estimate (one halving of dt), good to a
#: factor of a few; 10 keeps a factor-3 misestimate from deciding. Measured (tau = 10,
#: dt = 0.01): on the upper N = 2 and N = 3 Hopf branches, past k = 10, |mu| - 1 of the
#: multipliers near the roots of unity is 1e-6 to 2e-5 and changes by 1e-7 to 2.5e-5 under
#: dt -> dt/2 (each side of a flip lies 0.3 to 30 uncertainties out, never both beyond
#: 10); the clear crossings measured lie 50 to 1600 uncertainties out on each side (N = 2
#: at k = 5.26, N = 3 at 9.86) and, for the period doubling at b = 22.3252 (tau = 2,
#: dt = 0.0025), 670 and 10.5 (the next point: 0.23 against ~1e-2).
CLEAR = 10.0
#: The located point's tolerance in the parameter, and the most orbits corrected to reach
#: it (regula falsi takes 6 to 12 on the crossings measured).
LOCATE_TOL, LOCATE_MAX = 1e-6, 40
#: Multipliers computed at each orbit of the check (as along the branch).
CHECK_MULTIPLIERS = 6
#: A crossing multiplier is complex (a torus, not a period doubling or a branch point)
#: when its imaginary part exceeds this many of its uncertainties too.
COMPLEX_CLEAR = CLEAR


@dataclass(frozen=True)
class Orbit:
    """A corrected orbit at one parameter value, on its grid, with its multipliers."""

    value: float
    z: np.ndarray
    period: float
    grid: Grid
    multipliers: Multipliers


@dataclass(frozen=True)
class Verdict:
    """A candidate crossing judged: ``kind`` is period-doubling, torus, branch-point or
    undetermined; ``value, period, multiplier`` where it was located (or the interval's
    interpolation when undetermined); ``reason`` says why undetermined, with the figures."""

    kind: str
    value: float
    period: float
    multiplier: complex
    reason: str = ""


def distance(m: Multipliers) -> np.ndarray:
    """|mu| - 1 of each nontrivial multiplier."""
    return np.abs(m.nontrivial) - 1.0


def nearest(m: Multipliers, mu: complex) -> complex:
    """The nontrivial multiplier of ``m`` nearest ``mu`` (the same one, followed)."""
    others = m.nontrivial
    return complex(others[int(np.argmin(np.abs(others - mu)))])


def crossing_multiplier(a: Multipliers, b: Multipliers) -> tuple[complex, complex] | None:
    """The multiplier that crossed the unit circle from a to b, as (mu at a, mu at b):
    each nontrivial multiplier of b (of a pair the one with Im >= 0) is followed back to
    its nearest at a; of those whose |mu| - 1 changed sign, the one farthest from the
    circle on its nearer side (the clearest crossing). None if none changed sign."""
    best: tuple[float, complex, complex] | None = None
    for mu_b in b.nontrivial:
        if mu_b.imag < 0:
            continue
        mu_a = nearest(a, complex(mu_b))
        ea, eb = abs(mu_a) - 1.0, abs(mu_b) - 1.0
        if ea * eb >= 0:
            continue
        clarity = min(abs(ea), abs(eb))
        if best is None or clarity > best[0]:
            best = (clarity, mu_a, complex(mu_b))
    return None if best is None else (best[1], best[2])


def halved(z: np.ndarray, g: Grid) -> tuple[np.ndarray, Grid]:
    """The reduced state on the grid of step dt / 2 (the history by cubic splines through
    its samples; the current state as it is)."""
    n = g.n_delay
    t = -np.arange(n + 1) * g.dt
    t2 = -np.arange(2 * n + 1) * g.dt / 2
    xi = np.concatenate(([0.0], z[4:4 + n]))
    eta = np.concatenate(([z[0]], z[4 + n:]))
    xi2 = CubicSpline(t[::-1], xi[::-1])(t2)
    eta2 = CubicSpline(t[::-1], eta[::-1])(t2)
    return np.concatenate((z[:4], xi2[1:], eta2[1:])), Grid(g.dt / 2, 2 * n)


def corrected(pm: PeriodMap, z: np.ndarray, period: float) -> Orbit:
    """The orbit of ``pm`` nearest (z, period), with its multipliers."""
    shot = pm.shoot(z, period)
    sol = correct(pm, z, period, z, shot.d_dT)
    return Orbit(float("nan"), sol.z, sol.period, pm.g, multipliers(pm, sol.shot, CHECK_MULTIPLIERS))


def uncertainty(pm: PeriodMap, z: np.ndarray, period: float, m: Multipliers, mu: complex) -> float:
    """The error of the multiplier ``mu`` of the orbit (z, period) of ``pm`` (with
    multipliers ``m``): its change when the orbit is corrected at dt / 2, or the flow
    multiplier's distance from 1 at either step if larger (an orbit or eigenvalue error
    the halving would not show)."""
    z2, g2 = halved(z, pm.g)
    fine = corrected(PeriodMap(pm.p, g2), z2, period)
    mu2 = nearest(fine.multipliers, mu)
    return max(abs(mu2 - mu), abs(abs(mu2) - abs(mu)), abs(m.flow - 1.0),
               abs(fine.multipliers.flow - 1.0))


#: Corrects the orbit at a parameter value: (value, z seed, period seed) -> Orbit.
Corrector = Callable[[float, np.ndarray, float], Orbit]


def locate(at: Corrector, a: Orbit, b: Orbit, mu_a: complex, mu_b: complex,
           seed: Seed | None = None) -> tuple[float, float, complex, float]:
    """The parameter where the multiplier followed from mu_a (at a) to mu_b (at b) has
    |mu| = 1: regula falsi (Illinois) on |mu| - 1, each evaluation an orbit corrected at
    the secant's root from ``seed``'s guess (default: interpolated between the bracket's
    ends). Returns the root of the last bracket's
    secant (value, period), the multiplier at the evaluated orbit nearest the circle, and
    the last bracket's length."""
    lo, hi = (a, abs(mu_a) - 1.0, mu_a), (b, abs(mu_b) - 1.0, mu_b)
    side = 0
    best = lo if abs(lo[1]) < abs(hi[1]) else hi
    for _ in range(LOCATE_MAX):
        if abs(hi[0].value - lo[0].value) < LOCATE_TOL:
            break
        (oa, fa, _), (ob, fb, _) = lo, hi
        s = fa / (fa - fb)
        s = min(max(s, 0.02), 0.98)  # keep the new orbit inside the bracket
        value = oa.value + s * (ob.value - oa.value)
        if seed is None:
            z, period = oa.z + s * (ob.z - oa.z), oa.period + s * (ob.period - oa.period)
        else:
            z, period = seed(value)
        orbit = at(value, z, period)
        mu = nearest(orbit.multipliers, (lo[2] if s < 0.5 else hi[2]))
        f = abs(mu) - 1.0
        point = (orbit, f, mu)
        if abs(f) < abs(best[1]):
            best = point
        if f * fa > 0:
            lo = point
            if side == -1:  # the same end twice: halve the other's weight (Illinois)
                hi = (hi[0], hi[1] / 2, hi[2])
            side = -1
        else:
            hi = point
            if side == 1:
                lo = (lo[0], lo[1] / 2, lo[2])
            side = 1
    (oa, fa, _), (ob, fb, _) = lo, hi
    s = fa / (fa - fb) if fa != fb else 0.5
    return (float(oa.value + s * (ob.value - oa.value)),
            float(oa.period + s * (ob.period - oa.period)), best[2], abs(ob.value - oa.value))


def kind_of(mu: complex, u: float) -> str:
    """The crossing's type from where the multiplier crosses: a complex pair (its
    imaginary part clear of the uncertainty) a torus, near -1 a period doubling, near +1
    a branch point."""
    if abs(mu.imag) > COMPLEX_CLEAR * u:
        return "torus"
    return "period-doubling" if mu.real < 0 else "branch-point"


#: A crossing multiplier within this angle (radians) of a q-th root of unity, q <= 4, is
#: said to be near the strong resonance 1:q (there the normal form of a generic torus
#: or period doubling does not apply: the tori born are phase-locked or absent).
RESONANCE_ANGLE = 1e-2


def resonance(mu: complex) -> str:
    """"; near the 1:q resonance (arg mu = ...)" for a torus multiplier near a root of
    unity of order 3 or 4, or a complex pair near -1 (order 2); "" otherwise."""
    if abs(mu.imag) == 0.0:
        return ""
    angle = abs(math.atan2(mu.imag, mu.real))
    for q in (2, 3, 4):
        for j in range(1, q // 2 + 1):
            if math.gcd(j, q) == 1 and abs(angle - 2 * math.pi * j / q) < RESONANCE_ANGLE:
                return f"; near the 1:{q} resonance (arg mu = {angle:.6f})"
    return ""


#: A side of a crossing that is not clear at its nearest branch point is looked at up to
#: this many points farther along (on the same stretch: no fold between): a point may land
#: next to a real crossing (b at tau = 2, dt = 0.0025: |mu| - 1 = +0.02 at b = 22.3255,
#: 6 e-5 past the period doubling, uncertain by 1.9e-3; +0.23 a point later).
WIDEN = 2

#: The uncertainty of a multiplier of a branch orbit: (orbit, mu) -> error.
Uncertainty = Callable[[Orbit, complex], float]
#: A seed for the orbit at a parameter value: value -> (z, period).
Seed = Callable[[float], tuple[np.ndarray, float]]


@dataclass(frozen=True)
class Side:
    """One side of a crossing as judged: the orbit looked at last, the multiplier followed
    there, its uncertainty, and whether it is clear of the circle."""

    orbit: Orbit
    mu: complex
    error: float
    clear: bool

    def __str__(self) -> str:
        return (f"{abs(self.mu) - 1:+.1e} at {self.orbit.value:.6g} (uncertain by "
                f"{self.error:.1e})")


def clear_side(side: list[Orbit], mu: complex, error: Uncertainty) -> Side:
    """The nearest orbit of ``side`` (nearest the crossing first) where the multiplier
    followed from ``mu`` is beyond CLEAR uncertainties from the circle, on the side it was
    at the first; the last one looked at (not clear) if there is none."""
    outside = abs(mu) > 1.0
    judged = Side(side[0], mu, math.inf, False)
    for k, orbit in enumerate(side):
        if k:
            mu = nearest(orbit.multipliers, mu)
            if (abs(mu) > 1.0) != outside:
                break
        u = error(orbit, mu)
        judged = Side(orbit, mu, u, abs(abs(mu) - 1.0) > CLEAR * u)
        if judged.clear:
            break
    return judged


def judge(at: Corrector, a_side: list[Orbit], b_side: list[Orbit], error: Uncertainty,
          seed: Seed | None = None) -> Verdict | None:
    """The crossing between branch orbits a = a_side[0] and b = b_side[0] (each side
    nearest first, up to WIDEN more), if a multiplier changed sides from a to b: real
    (located, typed) when |mu| - 1 is beyond CLEAR uncertainties (``error``) on both
    sides, else undetermined. ``seed`` gives the orbit's first guess at a parameter value
    (default: interpolated between the bracket's ends)."""
    a, b = a_side[0], b_side[0]
    found = crossing_multiplier(a.multipliers, b.multipliers)
    if found is None:
        return None
    mu_a, mu_b = found
    ea, eb = abs(mu_a) - 1.0, abs(mu_b) - 1.0
    s = ea / (ea - eb)
    rough = (a.value + s * (b.value - a.value), a.period + s * (b.period - a.period))
    try:
        sa = clear_side(a_side[:WIDEN + 1], mu_a, error)
        sb = clear_side(b_side[:WIDEN + 1], mu_b, error)
    except OrbitError as exc:
        return Verdict("undetermined", *rough, mu_b, reason=(
            f"|mu| - 1 = {ea:+.1e} at {a.value:.6g} and {eb:+.1e} at {b.value:.6g}; its "
            f"uncertainty could not be measured (the orbit at dt/2: {exc})"))
    figures = f"|mu| - 1 = {sa} and {sb} (uncertainty: the change under dt -> dt/2)"
    if not (sa.clear and sb.clear):
        return Verdict("undetermined", *rough, mu_b, reason=(
            f"{figures}: not beyond {CLEAR:g} uncertainties on both sides"))
    try:
        value, period, mu, bracket = locate(at, sa.orbit, sb.orbit, sa.mu, sb.mu, seed)
    except OrbitError as exc:
        return Verdict("undetermined", *rough, mu_b, reason=f"{figures}; located by no orbit: {exc}")
    located = f"; located within {bracket:.1e}, where |mu| - 1 = {abs(mu) - 1:+.1e}"
    return Verdict(kind_of(mu, max(sa.error, sb.error)), value, period, mu,
                   reason=figures + located + resonance(mu))


__all__ = ["CLEAR", "LOCATE_TOL", "WIDEN", "Corrector", "Orbit", "Seed", "Side", "Uncertainty",
           "Verdict", "clear_side", "corrected", "crossing_multiplier", "halved", "judge",
           "kind_of", "locate", "resonance", "uncertainty"]
