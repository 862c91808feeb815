"""A continuation's lines as `continue` prints them while it walks and `branch ID` prints
them from the store: one branch point, the bifurcations found. Light (no numpy, no
numba), so that `branch` reads stored branches without loading the continuation's
kernels (`continue` loads them)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from slopetui.display_text import terminal_safe


def print_point(param: str, point: Mapping[str, Any]) -> None:
    print(f"{param} = {point['value']:<12.8g} period {point['period']:<12.8g} amplitude "
          f"{point['amplitude']:<10.6g} {'stable' if point['stable'] else 'unstable'}",
          flush=True)


def print_bifurcations(param: str, found: Sequence[Mapping[str, Any]]) -> None:
    for b in found:
        mu = b["multiplier"]
        print(f"{terminal_safe(b['type']):<16} {param} = {b['value']:.8g}, period {b['period']:.8g}"
              + (f", multiplier {mu[0]:+.6f}{mu[1]:+.6f}i"
                 if b["type"] not in ("fold", "hopf") else "")
              + (f"\n{'':<16} {terminal_safe(b['reason'])}" if b.get("reason") else ""))
    if not found:
        print("no bifurcation on this branch")
