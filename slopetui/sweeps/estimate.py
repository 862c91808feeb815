"""What a sweep will cost: runs, steps, and wall time on the workers.

The per-step costs are the single-trajectory kernel speeds measured by
``benchmarks/bench_kernels.py`` on this project's reference machine (2.6 GHz Xeon, one
core): Euler 6.5 ns/step (10.1 with lambda_max), RK4 28.7 ns/step (34.8 with lambda_max).
"""

from __future__ import annotations

from slopetui.sweeps.spec import SweepSpec

NS_PER_STEP = {("euler", False): 6.5, ("euler", True): 10.1,
               ("rk4", False): 28.7, ("rk4", True): 34.8}
#: Per-run costs outside the kernel: classification, the queue, the cache (s).
OVERHEAD_S = 0.01


def seconds_per_run(spec: SweepSpec) -> float:
    s = spec.solver
    assert s.dt is not None
    steps = s.t_end / s.dt
    return steps * NS_PER_STEP[(s.method, s.lyap)] * 1e-9 + OVERHEAD_S


def wall_seconds(spec: SweepSpec, workers: int) -> float:
    """Wall time on ``workers`` processes, one core each (runs that blow up are faster)."""
    return spec.n_runs * seconds_per_run(spec) / max(workers, 1)


def describe(spec: SweepSpec, workers: int) -> str:
    """One line for the new-sweep form. An adaptive sweep is estimated by its coarse
    lattice: how much refinement adds depends on the regime boundaries it finds."""
    on = f"on {workers} worker{'s' if workers != 1 else ''}"
    if spec.adaptive_levels is not None:
        first = spec.first_runs * seconds_per_run(spec) / max(workers, 1)
        return (f"{spec.first_runs} coarse runs x {seconds_per_run(spec):.2f} s = about "
                f"{_duration(first)} {on}, then refinement")
    return (f"{spec.n_runs} runs x {seconds_per_run(spec):.2f} s = about "
            f"{_duration(wall_seconds(spec, workers))} {on}")


def _duration(seconds: float) -> str:
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"
