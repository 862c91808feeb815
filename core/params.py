"""Model parameters of the mean-field spring-block model (paper Section 2-3).

All quantities are in the paper's dimensionless model units: time in units of the
integration clock (the paper's dt = 1e-3 is a model-time step), velocities relative to
the same clock. The paper never attaches physical units; neither do we.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields, replace
from typing import Any

#: Names of the model parameters, in the order the kernels receive them.
PARAM_NAMES: tuple[str, ...] = ("a", "b", "c", "d", "k", "v", "tau", "delta")


class ParameterError(ValueError):
    """A parameter or setting outside its allowed range.

    ``field`` names the offending input, ``allowed`` states the range in words, so that
    the CLI and the TUI can show the cause without a traceback.
    """

    def __init__(self, field: str, value: Any, allowed: str) -> None:
        self.field = field
        self.value = value
        self.allowed = allowed
        shown = repr(value)  # repr: a string's control characters come out escaped
        if len(shown) > 40:  # an integer of 400 digits is still one readable line
            shown = shown[:37] + "..."
        super().__init__(f"{field} = {shown} is out of range: allowed {allowed}")


def check_finite(field: str, value: float) -> float:
    """Coerce ``value`` to float and reject NaN, infinities and booleans.

    A bool is refused although float(True) is 1.0: ``k = true`` in a spec or a JSON
    settings file is a mistake, not a stiffness of 1. An integer too large for a float
    (10**400) raises OverflowError in float(), which is refused like any other non-number.
    """
    if isinstance(value, bool):
        raise ParameterError(field, value, "a finite real number, not a boolean")
    try:
        x = float(value)
    except (TypeError, ValueError, OverflowError):
        raise ParameterError(field, value, "a finite real number") from None
    if not math.isfinite(x):
        raise ParameterError(field, value, "a finite real number")
    return x


def check_at_least(field: str, value: float, low: float) -> float:
    x = check_finite(field, value)
    if x < low:
        raise ParameterError(field, value, f"{field} >= {low:g}")
    return x


def check_positive(field: str, value: float) -> float:
    x = check_finite(field, value)
    if x <= 0.0:
        raise ParameterError(field, value, f"{field} > 0")
    return x


@dataclass(frozen=True, slots=True)
class Params:
    """Parameters of eqs. 6a-6e with the paper's defaults (eq. 8, d = 1e-4, Fig. 4A).

    a, b, c : friction coefficients of F(v) = a v^3 - b v^2 + c v (eq. 1).
    d       : noise intensity (>= 0); enters eq. 6d as 2d.
    k       : spring stiffness (>= 0).
    v       : steady-state sliding velocity.
    tau     : delay of the spring effect (>= 0, model time units).
    delta   : offset of the initial conditions (eq. 19).
    """

    a: float = 3.2
    b: float = 7.2
    c: float = 4.8
    d: float = 1e-4
    k: float = 10.0
    v: float = 0.1
    tau: float = 10.0
    delta: float = 0.1

    def __post_init__(self) -> None:
        for f in fields(self):
            object.__setattr__(self, f.name, check_finite(f.name, getattr(self, f.name)))
        check_at_least("tau", self.tau, 0.0)
        check_at_least("d", self.d, 0.0)
        check_at_least("k", self.k, 0.0)

    def with_(self, **changes: float) -> Params:
        """A copy with some parameters changed (validated again)."""
        unknown = set(changes) - set(PARAM_NAMES)
        if unknown:
            raise ParameterError(
                sorted(unknown)[0], changes[sorted(unknown)[0]], f"one of {', '.join(PARAM_NAMES)}"
            )
        return replace(self, **changes)

    def as_dict(self) -> dict[str, float]:
        return asdict(self)

    # -- friction, eqs. 1 and 10 ------------------------------------------------------
    @property
    def F(self) -> float:
        """F(v) = a v^3 - b v^2 + c v (eq. 1)."""
        return friction(self.v, self.a, self.b, self.c)

    @property
    def F1(self) -> float:
        """F'(v) = 3 a v^2 - 2 b v + c, the linear damping of m_y (eqs. 6b, 10)."""
        return friction_slope(self.v, self.a, self.b, self.c)

    @property
    def q(self) -> float:
        """q = 3 a v - b, the quadratic coefficient of eq. 6b (F''(v) / 2)."""
        return 3.0 * self.a * self.v - self.b


def friction(v: float, a: float, b: float, c: float) -> float:
    """F(v) = a v^3 - b v^2 + c v (eq. 1)."""
    return ((a * v - b) * v + c) * v


def friction_slope(v: float, a: float, b: float, c: float) -> float:
    """F'(v) = 3 a v^2 - 2 b v + c (eq. 10)."""
    return (3.0 * a * v - 2.0 * b) * v + c


def friction_extrema(p: Params) -> tuple[float, float] | None:
    """v_-, v_+ of eq. 10: the local maximum and minimum of F, or None if b^2 <= 3ac."""
    disc = p.b * p.b - 3.0 * p.a * p.c
    if disc <= 0.0 or p.a == 0.0:
        return None
    r = math.sqrt(disc)
    lo, hi = sorted(((p.b - r) / (3.0 * p.a), (p.b + r) / (3.0 * p.a)))
    return lo, hi


def friction_warnings(p: Params) -> list[str]:
    """The paper's shape constraints on the friction law (eqs. 7, 9-13) that ``p`` breaks.

    They are warnings, not errors: the paper itself explores a = 0.03 (Fig. 7), far
    outside eq. 13a. An empty list means F keeps the shape the paper assumes.
    """
    out: list[str] = []
    if p.F <= 0.0:
        out.append(f"F(v) = {p.F:.4g} <= 0: friction must be positive at v (eqs. 7, 9)")
    if p.a <= 0.0:
        out.append(f"a = {p.a:g} <= 0: F must increase for large v (eq. 11, a > 0)")
    b2, ac = p.b * p.b, p.a * p.c
    if b2 <= 3.0 * ac:
        out.append(f"b^2 = {b2:.4g} <= 3ac = {3 * ac:.4g}: F has no local max/min (eqs. 10, 12)")
    elif b2 >= 4.0 * ac:
        out.append(f"b^2 = {b2:.4g} >= 4ac = {4 * ac:.4g}: F(v+) <= 0 at its local minimum (eq. 12)")
    return out


def fixed_points(p: Params) -> list[dict[str, float]]:
    """Fixed points of eqs. 6a-6e (eqs. 14-17), as dicts of m_y, s_x, s_y, u.

    m_x is free (any constant: the translation symmetry), m_y = u = 0. With k > 0,
    s_x = s_y / k (eq. 14c). For 3av - b != 0 only s_y = 0 solves eq. 14a, which needs
    d = 0 (eq. 15); for 3av - b = 0 the roots of eq. 16 that are real and >= 0 are
    fixed points. With k = 0 a fixed point needs s_y = 0 and d = 0 (eq. 14).

    With d > 0 and 3av - b != 0 there is no fixed point: the sliding state then drifts
    with a small constant m_y (see core.classify's drift), as the paper observes.
    """
    if p.k == 0.0:
        return [dict(m_y=0.0, s_x=0.0, s_y=0.0, u=0.0)] if p.d == 0.0 else []
    # 3av - b = 0 is tested up to round-off: v = b / (3a) rarely lands on it exactly
    if abs(p.q) > 1e-12 * max(abs(p.b), 1.0):
        return [dict(m_y=0.0, s_x=0.0, s_y=0.0, u=0.0)] if p.d == 0.0 else []
    if p.a == 0.0:
        # eq. 14b degenerates to F' s_y = d
        roots = [p.d / p.F1] if p.F1 != 0.0 else []
    else:
        disc = p.F1 * p.F1 + 12.0 * p.a * p.d  # eq. 16
        if disc < 0.0:
            return []
        r = math.sqrt(disc)
        roots = [(-p.F1 + r) / (6.0 * p.a), (-p.F1 - r) / (6.0 * p.a)]
    out = []
    for s_y in sorted(set(roots)):
        if s_y >= 0.0:
            out.append(dict(m_y=0.0, s_x=s_y / p.k, s_y=s_y, u=0.0))
    return out


def sliding_branches(p: Params) -> tuple[float, ...]:
    """Steady sliding at a constant m_y = y != 0: the slope at rest on a faster branch.

    With m_y constant, m_x grows linearly, so m_x(t - tau) - m_x(t) = -tau y, and eq. 6b
    with s_y = 0 (the noise-free limit) reads y (F'(v) + k tau + q y + a y^2) = 0. The
    nonzero branches are the real roots of a y^2 + q y + (F'(v) + k tau) = 0, q = 3av - b.
    At the defaults of eq. 8 there are none; low a, high b or low c open them. Runs that
    settle on a branch rest on its larger root (measured in the preset sweeps: m_y = root
    to 6 digits at b = 20.3, tau = 1.15, k = 12). Returns the roots, ascending.
    """
    c = p.F1 + p.k * p.tau
    if p.a == 0.0:
        return (-c / p.q,) if p.q != 0.0 else ()
    disc = p.q * p.q - 4.0 * p.a * c
    if disc < 0.0:
        return ()
    r = math.sqrt(disc)
    return tuple(sorted(((-p.q - r) / (2.0 * p.a), (-p.q + r) / (2.0 * p.a))))
