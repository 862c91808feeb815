"""The rest state's characteristic roots at a point, for the faces (``slopetui roots``,
the run detail's Roots tab): computed by core.rest_stability.rest_roots, judged by the
leading one, and said in words. No UI here.

The leading nonzero root decides the rest (sliding) state's linear stability: its real
part is the growth rate of small perturbations (the m_x shift's root 0, a neutral
direction of every rest state, is left out). Where it lies within
core.rest_stability.NEUTRAL_TOL of the imaginary axis the computation resolves nothing,
and the verdict says "undecided".
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass

from core.params import Params
from core.rest_stability import NEUTRAL_TOL, RestRoot, rest_roots

#: The delay factor's roots a face asks for when the user names no count: the default of
#: ``slopetui roots --count``, so that the run detail lists what the command prints.
DEFAULT_COUNT = 6


def verdict(found: Sequence[RestRoot]) -> str:
    """The rest state's linear stability from its leading root: stable, unstable, or
    undecided within core.rest_stability.NEUTRAL_TOL of the imaginary axis."""
    lead = found[0].value.real
    if abs(lead) <= NEUTRAL_TOL:
        return "undecided"
    return "stable" if lead < 0 else "unstable"


def unstable_count(found: Sequence[RestRoot]) -> int:
    """How many of ``found`` lie right of the imaginary axis (beyond NEUTRAL_TOL)."""
    return sum(r.value.real > NEUTRAL_TOL for r in found)


@dataclass(frozen=True)
class RestRoots:
    """The rest state's rightmost roots at ``params``, best first (core.rest_stability
    .rest_roots: ``count`` of the delay factor and the variance block's), and the time
    they took (s of CPU)."""

    params: Params
    roots: list[RestRoot]
    count: int
    runtime_s: float

    @property
    def stability(self) -> str:
        return verdict(self.roots)

    @property
    def unstable(self) -> int:
        return unstable_count(self.roots)


def compute(params: Params, count: int = DEFAULT_COUNT) -> RestRoots:
    """The roots at ``params``; ArithmeticError when one cannot be carried to the noisy
    rest state (core.rest_stability.rest_roots)."""
    t0 = time.process_time()
    found = rest_roots(params, count)
    return RestRoots(params, found, count, time.process_time() - t0)
