"""Measurements on a computed sweep that the paper's claims can be held against."""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass

import numpy as np

from core import Params
from core.params import sliding_branches
from core.stability import hopf_k
from slopetui.sweeps.diagram import RunPoint, SweepDiagram


def done(d: SweepDiagram) -> list[RunPoint]:
    return [r for r in d.runs if r.status == "done"]


def fast_sliding(r: RunPoint, v: float) -> bool:
    """A run at rest that is *not* at the fixed point m_y = 0 but at another steady state
    sliding faster than twice the steady velocity (m_y > v): the runaway branch that low
    a, high b or low c open (eq. 1 has further roots there). The fixed point itself drifts
    only by noise, |m_y| < 1e-3 at d <= 1e-2 in every preset sweep."""
    return r.regime == "sliding" and r.drift > v


def regime_counts(d: SweepDiagram) -> Counter[str]:
    return Counter(r.regime for r in done(d))


def branch_mismatch(d: SweepDiagram) -> tuple[int, float]:
    """Runs on a faster branch, and the largest relative distance of their m_y from the
    larger root of core.params.sliding_branches (nan if a run has no predicted branch)."""
    v, worst, n = d.spec.base.v, 0.0, 0
    x, y = d.spec.x.param, d.spec.y.param if d.spec.y else None
    for r in done(d):
        if not fast_sliding(r, v):
            continue
        n += 1
        values = {x: r.x} | ({y: r.y} if y else {})
        roots = sliding_branches(d.spec.base.with_(**values))
        worst = max(worst, abs(r.drift - roots[-1]) / roots[-1] if roots else math.nan)
    return n, worst


def fast_count(d: SweepDiagram) -> int:
    v = d.spec.base.v
    return sum(fast_sliding(r, v) for r in done(d))


def fraction(d: SweepDiagram, regime: str) -> float:
    runs = done(d)
    return sum(r.regime == regime for r in runs) / len(runs) if runs else float("nan")


def counts_text(d: SweepDiagram) -> str:
    c = regime_counts(d)
    n = sum(c.values())
    fast = fast_count(d)
    parts = [f"{k} {v} ({100 * v / n:.0f}%)" + (f" [{fast} of them on a faster sliding branch, "
                                                   "m_y > v]" if k == "sliding" and fast else "")
             for k, v in c.most_common()]
    return ", ".join(parts) or "no runs"


def first_x(d: SweepDiagram, regime: str) -> float | None:
    """The smallest x of a run with this regime (1-D sweeps)."""
    xs = [r.x for r in done(d) if r.regime == regime]
    return min(xs) if xs else None


def last_x(d: SweepDiagram, regime: str) -> float | None:
    xs = [r.x for r in done(d) if r.regime == regime]
    return max(xs) if xs else None


def rows(d: SweepDiagram) -> dict[float, list[RunPoint]]:
    """Runs of a 2-D sweep by y value (each row sorted by x)."""
    out: dict[float, list[RunPoint]] = {}
    for r in sorted(done(d), key=lambda r: (r.y, r.x)):
        out.setdefault(r.y, []).append(r)  # type: ignore[arg-type]
    return out


def xs_of(d: SweepDiagram, regime: str) -> np.ndarray:
    return np.array([r.x for r in done(d) if r.regime == regime])


def ys_of(d: SweepDiagram, regime: str) -> np.ndarray:
    return np.array([r.y for r in done(d) if r.regime == regime])


@dataclass(frozen=True)
class LinearAgreement:
    """How the sliding / not-sliding labels compare with linear stability of the fixed
    point (the sign of the leading exponent of the full characteristic function)."""

    cells: int             # runs compared (done, not unstable)
    agree: int
    sliding_but_unstable: int   # at rest on the fixed point where linear theory says unstable
    oscillating_but_stable: int  # oscillating where the fixed point is linearly stable

    @property
    def share(self) -> float:
        return self.agree / self.cells if self.cells else float("nan")


def linearly_stable(p: Params) -> bool:
    """Is the fixed point linearly stable? The variance block needs F'(v) > 0, the delay
    factor k < k_H(tau) (the first Hopf branch is the boundary; below F'^2/2 it is stable
    at every tau). Equivalent to core.stability.leading_exponent(p) < 0, which computes
    the roots and takes ~1 s a point; this takes ~0.1 ms."""
    if p.F1 <= 0.0:
        return False
    return p.tau == 0.0 or p.k < hopf_k(p.tau, p.F1)


def linear_agreement(d: SweepDiagram) -> LinearAgreement:
    base = d.spec.base
    x, y = d.spec.x.param, d.spec.y.param if d.spec.y else None
    cells = agree = s_u = o_s = 0
    for r in done(d):
        if r.regime in ("unstable", None):
            continue
        values = {x: r.x} | ({y: r.y} if y else {})
        stable = linearly_stable(base.with_(**values))
        # at rest on the fixed point; a run at rest on a faster branch left the fixed point
        sliding = r.regime == "sliding" and not fast_sliding(r, base.v)
        cells += 1
        agree += sliding == stable
        s_u += sliding and not stable
        o_s += (not sliding) and stable
    return LinearAgreement(cells, agree, s_u, o_s)


def details(d: SweepDiagram, regime: str) -> Counter[str]:
    """The classifier's detail labels (period-2, chaotic, ...) of one regime's runs."""
    return Counter(r.detail or "" for r in done(d) if r.regime == regime)

