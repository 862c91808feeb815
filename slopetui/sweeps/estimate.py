"""What a sweep will cost: runs, steps, and wall time on the workers.

The cost of a step is measured: the median over the newest runs this store's workers
computed with the same method and stop rule (``slopetui.store.runs.speeds``), which is
what they will take, batched or not, on this machine. Before any run of a method was
computed, the reference speeds below stand in, and the estimate says so.

A run under the stop rule "certified" takes the steps to where its attractor is
certified, which depends on the attractor: the estimate takes the expected stopping time
from this store's own finished certified runs (``expected_stop``); before there are any,
it assumes every run goes to t_end (an upper bound) and says so. They are the kernel speeds the
workers use, measured by ``benchmarks/bench_kernels.py --repeat 3`` on this project's
2-core reference machine (README, Speed): Euler batched 2.82 ns/point-step (6.59 with
lambda_max), RK4 single (workers compute RK4 run by run) 27.9 ns (32.4 with lambda_max).
A constant single-kernel Euler speed (6.5 ns) made the form's estimate ~2x too high once
workers ran the batched kernel.
"""

from __future__ import annotations

import statistics
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

from core.solve import STOPS
from slopetui.duration_text import duration_text
from slopetui.store.runs.speeds import certified_stops, seconds_per_step
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

#: Seconds per step by (method, lyap, stop rule).
Speeds = Mapping[tuple[str, bool, str], float]
#: (t_stop, t_end, dt) of finished certified runs (speeds.certified_stops).
Stops = Sequence[tuple[float, float, float]]


def measured_speeds(db: Database) -> dict[tuple[str, bool, str], float]:
    """The seconds per step measured on this store, for each (method, lyap, stop rule)
    with runs."""
    out = {}
    for method, lyap in REFERENCE_S_PER_STEP:
        for stop in STOPS:
            cost = seconds_per_step(db, method, lyap, stop)
            if cost is not None:
                out[(method, lyap, stop)] = cost
    return out


def measured_stops(db: Database) -> list[tuple[float, float, float]]:
    """Where this store's newest certified runs stopped (speeds.certified_stops)."""
    return certified_stops(db)


def expected_stop(t_end: float, stops: Stops) -> float | None:
    """The mean time a certified run of a sweep to ``t_end`` is expected to stop at, from
    ``stops`` (earlier certified runs): one certified at t_stop <= t_end stops there
    again; one certified later, or never within its own t_end (t_stop within a step of
    it), is taken to run to t_end. None without earlier certified runs."""
    if not stops:
        return None
    return statistics.fmean(
        t_stop if t_stop < run_end - dt and t_stop <= t_end else t_end
        for t_stop, run_end, dt in stops)


def _speed(spec: SweepSpec, speeds: Speeds | None) -> float | None:
    """The measured seconds per step of the spec's method, lyap and stop rule, else None.
    Not the other rule's: a certified run's steps also pay for its analysis and its
    certification's attempts, which a short run spreads over few steps (speeds.py)."""
    s = spec.solver
    return speeds.get((s.method, s.lyap, s.stop)) if speeds else None


def seconds_per_run(spec: SweepSpec, speeds: Speeds | None = None,
                    stops: Stops | None = None) -> float:
    """One run's cost: its steps (to t_end, or for stop = certified to the expected stop
    of ``stops``) at the measured speed (``speeds``, from measured_speeds) if known, else
    at the reference speed plus OVERHEAD_S (a measured runtime already holds the
    overhead)."""
    s = spec.solver
    assert s.dt is not None
    expected = expected_stop(s.t_end, stops or ()) if s.stop == "certified" else None
    t = s.t_end if expected is None else expected
    steps = t / s.dt
    speed = _speed(spec, speeds)
    if speed is not None:
        return steps * speed
    return steps * REFERENCE_S_PER_STEP[(s.method, s.lyap)] + OVERHEAD_S


def wall_seconds(spec: SweepSpec, workers: int, speeds: Speeds | None = None,
                 stops: Stops | None = None) -> float:
    """Wall time on ``workers`` processes, one core each (runs that blow up are faster)."""
    return spec.n_runs * seconds_per_run(spec, speeds, stops) / max(workers, 1)


def _stop_note(spec: SweepSpec, stops: Stops | None) -> str:
    """What the estimate assumes of where the runs stop."""
    s = spec.solver
    if s.stop != "certified":
        return "every run to t_end"
    t = expected_stop(s.t_end, stops or ())
    if t is None:
        return "assumes t_end: no certified run on this store yet"
    assert stops
    return (f"certified stop at {100 * t / s.t_end:.0f} % of t_end on average, from "
            f"{len(stops)} certified runs here")


def describe(spec: SweepSpec, workers: int, speeds: Speeds | None = None,
             stops: Stops | None = None) -> str:
    """One line for the new-sweep form. An adaptive sweep is estimated by its coarse
    lattice: how much refinement adds depends on the regime boundaries it finds."""
    on = f"on {workers} worker{'s' if workers != 1 else ''}"
    per_run = seconds_per_run(spec, speeds, stops)
    source = "measured speed" if _speed(spec, speeds) is not None else "reference speed"
    source += "; " + _stop_note(spec, stops)
    if spec.adaptive_levels is not None:
        first = spec.first_runs * per_run / max(workers, 1)
        return (f"{spec.first_runs} coarse runs x {per_run:.2f} s = about "
                f"{duration_text(first)} {on}, then refinement ({source})")
    return (f"{spec.n_runs} runs x {per_run:.2f} s = about "
            f"{duration_text(wall_seconds(spec, workers, speeds, stops))} {on} ({source})")
