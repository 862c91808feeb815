"""Do Euler (the paper's, dt = 1e-3) and RK4 (dt = 0.01) give a point the same label?

Twenty points across the paper's planes (k-tau, a, b, c, delta), each run to the
paper's t_end = 1e5 with both schemes; where the regimes differ, the point is run
again with Euler at dt = 2.5e-4 to see which one a finer step agrees with.

    .venv/bin/python benchmarks/euler_vs_rk4_labels.py
"""

from __future__ import annotations

from core.params import Params
from core.point import run_point
from core.solve import SolverSettings

POINTS = [
    dict(k=3.0, tau=10.0), dict(k=5.0, tau=10.0), dict(k=7.0, tau=10.0), dict(k=10.0, tau=10.0),
    dict(k=15.0, tau=10.0), dict(k=17.2, tau=10.0), dict(k=20.0, tau=10.0), dict(k=24.0, tau=10.0),
    dict(k=6.0, tau=60.0, delta=1e-6), dict(k=12.0, tau=2.0), dict(k=30.0, tau=1.0),
    dict(k=100.0, tau=0.5), dict(k=6.0, b=15.5, tau=21.3), dict(k=12.0, b=20.3, tau=1.15),
    dict(k=12.0, b=12.0, tau=5.0), dict(k=12.0, a=0.035, tau=1.0), dict(k=12.0, a=8.0, tau=5.0),
    dict(k=12.0, c=2.0, tau=5.0), dict(k=12.0, c=8.0, tau=5.0), dict(k=5.5, tau=10.0, delta=1.0),
]


def label(p: Params, method: str, dt: float | None = None) -> tuple[str, str, int, str]:
    s = run_point(p, SolverSettings(method=method, dt=dt, lyap=False)).summary
    return s.regime, s.attractor, s.maxima_per_period, ",".join(s.flags)


def main() -> None:
    same = 0
    for kw in POINTS:
        p = Params(**kw)
        e, r = label(p, "euler"), label(p, "rk4")
        same += e[0] == r[0]
        line = f"{kw}: euler {e} | rk4 {r}"
        if e[0] != r[0]:
            line += f" | euler dt 2.5e-4 {label(p, 'euler', 2.5e-4)}"
        print(line, flush=True)
    print(f"same regime at {same} of {len(POINTS)} points")


if __name__ == "__main__":
    main()
