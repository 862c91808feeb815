"""Measurements on a computed sweep that the paper's claims can be held against."""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

import numpy as np

from core.closure import classifier_detail
from core.params import Params, sliding_branches
from core.stability import hopf_k
from slopetui.sweeps.diagram import RunPoint, SweepDiagram


def done(d: SweepDiagram) -> list[RunPoint]:
    return [r for r in d.runs if r.status == "done"]


def run_params(d: SweepDiagram, r: RunPoint) -> Params:
    values = {d.spec.x.param: r.x}
    if d.spec.y is not None and r.y is not None:
        values[d.spec.y.param] = r.y
    return d.spec.base.with_(**values)


def resting_faster(r: RunPoint, v: float) -> bool:
    """At rest, but sliding at more than twice the steady velocity (m_y > v). The fixed
    point itself drifts only by noise, |m_y| < 1e-3 at d <= 1e-2 in every preset sweep."""
    return r.regime == "sliding" and r.drift > v


def fast_sliding(d: SweepDiagram, r: RunPoint) -> bool:
    """At rest *not* at the fixed point m_y = 0 but on a faster steady sliding branch, one
    that core.params.sliding_branches predicts (low a, high b or low c open it). A run at
    rest with m_y > v where no branch exists is the noisy fixed point (large d)."""
    return resting_faster(r, d.spec.base.v) and bool(sliding_branches(run_params(d, r)))


def regime_counts(d: SweepDiagram) -> Counter[str]:
    return Counter(r.regime for r in done(d) if r.regime is not None)  # done: it has one


def branch_mismatch(d: SweepDiagram) -> tuple[int, float, int]:
    """Runs on a predicted faster branch, the largest relative distance of their m_y from
    its larger root, and the runs at rest with m_y > v where no branch exists (a drift
    the noise drives, at large d)."""
    worst, n, unpredicted = 0.0, 0, 0
    for r in done(d):
        if not resting_faster(r, d.spec.base.v):
            continue
        roots = sliding_branches(run_params(d, r))
        if not roots:
            unpredicted += 1
            continue
        n += 1
        worst = max(worst, abs(r.drift - roots[-1]) / abs(roots[-1]))
    return n, worst, unpredicted


def fast_count(d: SweepDiagram) -> int:
    return sum(fast_sliding(d, r) for r in done(d))


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


def certified_text(d: SweepDiagram) -> str:
    """What the panel's labels claim: how many of its computed runs certified their
    attractor (a fixed point by linear theory and the measured decay, an orbit by Newton
    from the run's final state), by attractor; the others' labels describe their window."""
    runs = [r for r in done(d) if not r.inferred]
    if not runs:
        return "no computed runs"
    tried = [r for r in runs if r.certified is not None]
    if not tried:
        return (f"certified attractors: none of {len(runs)} runs was tried (computed before "
                "certification): every label describes its run's window")
    by: Counter[str] = Counter(r.attractor or "?" for r in tried if r.certified)
    n = sum(by.values())
    kinds = ", ".join(f"{v} {k}" for k, v in by.most_common())
    return (f"certified attractors: {n} of {len(runs)} runs ({100 * n / len(runs):.0f}%)"
            + (f": {kinds}" if kinds else "")
            + (f"; the other {len(runs) - n} labels describe their window only"
               if n < len(runs) else ""))


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
    cells = agree = s_u = o_s = 0
    for r in done(d):
        if r.regime in ("unstable", None):
            continue
        stable = linearly_stable(run_params(d, r))
        # at rest on the fixed point; a run at rest on a faster branch left the fixed point
        sliding = r.regime == "sliding" and not fast_sliding(d, r)
        cells += 1
        agree += sliding == stable
        s_u += sliding and not stable
        o_s += (not sliding) and stable
    return LinearAgreement(cells, agree, s_u, o_s)


def details(d: SweepDiagram, regime: str) -> Counter[str]:
    """The classifier's detail labels (period-2, chaotic, ...) of one regime's runs
    (without the realisability clause, whose minima differ from run to run)."""
    return Counter(classifier_detail(r.detail or "") for r in done(d) if r.regime == regime)

