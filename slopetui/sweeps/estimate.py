"""What a sweep will cost: runs, steps, and wall time on the workers.

The cost of a step is measured: the median over the newest runs this store's workers
computed with the same method (``slopetui.store.runs.speeds``), which is what they will
take, batched or not, on this machine. Before any run of a method was computed, the
reference speeds below stand in, and the estimate says so. They are the kernel speeds the
workers use, measured by ``benchmarks/bench_kernels.py --repeat 3`` on this project's
2-core reference machine (README, Speed): Euler batched 2.82 ns/point-step (6.59 with
lambda_max), RK4 single (workers compute RK4 run by run) 27.9 ns (32.4 with lambda_max).
A constant single-kernel Euler speed (6.5 ns) made the form's estimate ~2x too high once
workers ran the batched kernel.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

from slopetui.duration_text import duration_text
from slopetui.store.runs.speeds import seconds_per_step
from slopetui.sweeps.spec import SweepSpec

if TYPE_CHECKING:
    from slopetui.store.database import Database

#: Reference seconds per step, (method, lyap) -> s (see the module docstring).
#: The stiff-safe scheme (core.stiff, single-run kernel only): 13.6 and 15.3 ns per step,
#: measured against Euler's 6.0 and 8.0 in one process (its module docstring).
REFERENCE_S_PER_STEP = {("euler", False): 2.82e-9, ("euler", True): 6.59e-9,
                        ("rk4", False): 27.9e-9, ("rk4", True): 32.4e-9,
                        ("stiff", False): 13.6e-9, ("stiff", True): 15.3e-9}
#: Per-run costs outside the kernel (s): classification, the queue and the cache (~0.01),
#: certification (0.006-0.076 at the paper's settings, benchmarks/bench_certify.py) and the
#: accuracy estimate (0-0.1, benchmarks/bench_accuracy.py; docs/speed.md): their typical
#: sum. A sweep with measured runs in the store uses their speed instead.
OVERHEAD_S = 0.06

Speeds = Mapping[tuple[str, bool], float]


def measured_speeds(db: Database) -> dict[tuple[str, bool], float]:
    """The seconds per step measured on this store, for each (method, lyap) with runs."""
    out = {}
    for method, lyap in REFERENCE_S_PER_STEP:
        cost = seconds_per_step(db, method, lyap)
        if cost is not None:
            out[(method, lyap)] = cost
    return out


def seconds_per_run(spec: SweepSpec, speeds: Speeds | None = None) -> float:
    """One run's cost: measured (``speeds``, from measured_speeds) if known, else the
    reference speed plus OVERHEAD_S (a measured runtime already holds the overhead)."""
    s = spec.solver
    assert s.dt is not None
    steps = s.t_end / s.dt
    key = (s.method, s.lyap)
    if speeds and key in speeds:
        return steps * speeds[key]
    return steps * REFERENCE_S_PER_STEP[key] + OVERHEAD_S


def wall_seconds(spec: SweepSpec, workers: int, speeds: Speeds | None = None) -> float:
    """Wall time on ``workers`` processes, one core each (runs that blow up are faster)."""
    return spec.n_runs * seconds_per_run(spec, speeds) / max(workers, 1)


def describe(spec: SweepSpec, workers: int, speeds: Speeds | None = None) -> str:
    """One line for the new-sweep form. An adaptive sweep is estimated by its coarse
    lattice: how much refinement adds depends on the regime boundaries it finds."""
    on = f"on {workers} worker{'s' if workers != 1 else ''}"
    per_run = seconds_per_run(spec, speeds)
    source = ("measured speed" if speeds and (spec.solver.method, spec.solver.lyap) in speeds
              else "reference speed")
    if spec.adaptive_levels is not None:
        first = spec.first_runs * per_run / max(workers, 1)
        return (f"{spec.first_runs} coarse runs x {per_run:.2f} s = about "
                f"{duration_text(first)} {on}, then refinement ({source})")
    return (f"{spec.n_runs} runs x {per_run:.2f} s = about "
            f"{duration_text(wall_seconds(spec, workers, speeds))} {on} ({source})")


