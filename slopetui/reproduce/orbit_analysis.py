"""The report's bifurcation analysis of the periodic orbits.

What the paper could only see by simulating, computed: the cycle branch at tau = 10 from
its Hopf point (criticality, fold of cycles, any period doubling or torus up to k = 25),
each result checked by simulation; the fold-of-cycles curve over tau, which with the Hopf
curve bounds the band where the outcome depends on the initial state; and that band held
against the cells where Figs. 5A (delta = 1e-6) and 5B (delta = 0.1) disagree.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from core.classify import find_peaks
from core.continuation import Bifurcation, Branch, bifurcations, criticality, walk
from core.fold_curve import FoldPoint, fold_curve
from core.orbit import Grid
from core.orbit_seed import simulate, simulate_from, state_at
from core.params import Params
from slopetui.sweeps.diagram import SweepDiagram
from slopetui.sweeps.fold_overlay import curve_of
from slopetui.sweeps.initial_dependence import (
    DEPENDS,
    BandAgreement,
    against_band,
    band_test,
    cells,
    dependence,
)

#: Where the analysis tells of its progress (a line each step), if anywhere.
Say = Callable[[str], None] | None

#: tau = 10 (Fig. 4A/4B): the branch is followed from the Hopf point to this k.
K_END = 25.0
#: The k at which the orbit a simulation from eq. 19 finds is compared with the branch.
PULSE_KS = (15.0, 18.0, 20.0, 22.0)
#: Offsets from the fold at which a simulation started on the stable orbit checks it.
FOLD_OFFSET = 0.003
#: Inside the band at tau = 10: the ks and offsets delta of eq. 19 simulated (RK4,
#: t = 2000) to see which start reaches the cycle and which the fixed point.
OFFSET_KS = (1.5, 3.0, 5.0)
OFFSET_DELTAS = (0.1, 0.5, 1.0, 2.0)
#: The taus of the fold-of-cycles curve beyond Fig. 5's axis (which ends at 20).
EXTRA_TAUS = (0.5, 0.6, 0.75, 30.0, 40.0, 60.0)


@dataclass(frozen=True)
class SimulationCheck:
    k: float
    late_amplitude: float  # peak-to-peak m_y over the last 20 time units of 2000
    stays: bool


@dataclass(frozen=True)
class PulseCheck:
    """At one k: maxima per period on the branch's orbit and in a simulation from eq. 19
    (delta = 0.1, RK4, t = 3000), and the simulated state's distance from the orbit."""

    k: float
    orbit_maxima: int
    simulated_maxima: int
    distance: float


@dataclass(frozen=True)
class Tau10:
    hopf: float
    hopf_period: float
    criticality: str
    found: list[Bifurcation]
    leading: tuple[float, float]   # |leading multiplier| range on the stable branch, k in [10, 25]
    checks: list[SimulationCheck]
    pulses: list[PulseCheck]
    n_points: int
    offsets: list[tuple[float, float, bool]]  # (k, delta, reaches the cycle)

    @property
    def fold(self) -> float | None:
        folds = [b.value for b in self.found if b.type == "fold"]
        return folds[0] if folds else None


def _maxima(y: np.ndarray, dt: float) -> int:
    t = np.arange(y.size) * dt
    return len(find_peaks(t, y)[0])


def tau10(p: Params | None = None) -> Tau10:
    """The branch at tau = 10 from its Hopf point, and the simulations that check it."""
    p = p or Params(tau=10.0, delta=0.1)
    branch, hopf = Branch.from_hopf(p, "k", 0.01, 1e-3, 0.02, 0.5)
    points = list(walk(branch, lambda pt: pt.value > K_END and pt.stable, 400, 1e-7))
    found = bifurcations(branch)
    mods = [abs(q.multipliers.leading) for q in points
            if q.stable and 10.0 <= q.value <= K_END]
    fold = next((b.value for b in found if b.type == "fold"), None)
    return Tau10(hopf.value, hopf.period, criticality(points), found,
                 (min(mods), max(mods)) if mods else (math.nan, math.nan),
                 _fold_checks(p, branch, fold), _pulse_checks(p, branch), len(points),
                 _offset_checks(p, branch.g0))


def _fold_checks(p: Params, branch: Branch, fold: float | None) -> list[SimulationCheck]:
    """Simulations started on the stable orbit nearest the fold, just above and below it."""
    if fold is None:
        return []
    g = branch.g0
    start = min((q for q in branch.points if q.stable), key=lambda q: q.value)
    checks = []
    for dk in (FOLD_OFFSET, -FOLD_OFFSET):
        traj = simulate_from(p.with_(k=fold + dk), g, start.z, 2000.0)
        late = float(np.ptp(traj[1, -int(20.0 / g.dt):]))
        checks.append(SimulationCheck(fold + dk, late, late > 0.1 * start.amplitude))
    return checks


def _pulse_checks(p: Params, branch: Branch) -> list[PulseCheck]:
    """At each of PULSE_KS: the stable orbit's maxima per period against those of a
    simulation from eq. 19, and how far the simulation is from the orbit."""
    g = branch.g0
    points = branch.points
    out = []
    for k in PULSE_KS:
        near = min(points, key=lambda q: abs(q.value - k) if q.stable else math.inf)
        orbit_y = branch.map_at(near.value).shoot(near.z, near.period).traj[1, g.n_delay:]
        traj = simulate(p.with_(k=near.value), g, 3000.0)
        m = int(near.period / g.dt)
        sim_y = traj[1, -m:]
        out.append(PulseCheck(near.value, _maxima(orbit_y[:m], g.dt),
                              _maxima(np.roll(sim_y, -int(np.argmin(sim_y))), g.dt),
                              _distance(branch, points.index(near), traj, g)))
    return out


def _offset_checks(p: Params, g: Grid) -> list[tuple[float, float, bool]]:
    """Inside the band: which offsets delta of eq. 19 reach the cycle (RK4, t = 2000)."""
    out = []
    for k in OFFSET_KS:
        for delta in OFFSET_DELTAS:
            traj = simulate(p.with_(k=k, delta=delta), g, 2000.0)
            out.append((k, delta, float(np.ptp(traj[1, -int(20.0 / g.dt):])) > 0.1))
    return out


def _distance(branch: Branch, i: int, traj: np.ndarray, g: Grid) -> float:
    """The weighted distance (core.orbit's norm) between the orbit of point i and the
    closest state of the last period of the simulation."""
    z = branch.points[i].z
    w = g.weights
    best = math.inf
    n_cols = traj.shape[1]
    m = int(branch.points[i].period / g.dt)
    for col in range(n_cols - m - 3, n_cols - 3, 5):
        s, _ = state_at(traj, g, (col - g.n_delay) * g.dt)
        diff = s - z
        best = min(best, math.sqrt(float(np.dot(diff * w, diff))))
    return best


def folds_over_tau(p: Params, taus: list[float], say: Say = None) -> list[FoldPoint]:
    """The fold of cycles in k at each tau (and the Hopf point with noise), each said as
    it is found (the curve takes minutes: tau = 60 alone ~5)."""
    out = []
    for point in fold_curve(p, sorted(set(taus))):
        if say is not None:
            say(f"fold of cycles at tau = {point.second:.4g}: "
                + (f"k = {point.fold:.5g}" if point.fold is not None else "none"))
        out.append(point)
    return out


@dataclass(frozen=True)
class Band:
    """Figs. 5A/5B against the bistable band: cells (same k, tau) where the two deltas
    disagree, how many lie in the band fold(tau) < k < Hopf(tau), and the band's cells."""

    disagree: int
    disagree_in_band: int
    cells: int
    band_cells: int
    band_disagree_share: float
    outside: list[tuple[float, float, str, str]]  # (k, tau, regime 5A, regime 5B)
    #: Band cells whose run moves (not at rest), in 5A (delta = 1e-6) and in 5B (0.1).
    moving_in_band: tuple[int, int] = (0, 0)
    #: 5B's band cells that move while 5A's rest: (k, tau), the largest k first.
    far_moves: list[tuple[float, float]] = field(default_factory=list)


#: The regimes of a run at rest. Inside the band the fixed point is linearly stable, so a
#: run there either rests on it (sliding) or moves.
AT_REST = ("sliding",)


def band_comparison(near: SweepDiagram, far: SweepDiagram, folds: list[FoldPoint]) -> Band:
    """Cell by cell: do delta = 1e-6 and delta = 0.1 agree, and is the cell in the band?
    (slopetui.sweeps.initial_dependence: the fold and Hopf values interpolated linearly
    between computed taus; below the smallest tau with a fold, a supercritical Hopf
    point, the band is empty.)"""
    both = cells([near, far])
    dep = dependence(both)
    test = band_test(folds)
    agree = (against_band(both, test) if test is not None else
             BandAgreement(dep.depends, 0, 0, [c for c in both if c.verdict == DEPENDS]))
    inside = [c for c in both if c.finished and c.y is not None and test is not None
              and test(c.x, c.y)]
    moving = tuple(sum(c.regimes[i] not in AT_REST for c in inside) for i in (0, 1))
    far_moves = sorted(((c.x, float(c.y or 0.0)) for c in inside
                        if c.regimes[0] in AT_REST and c.regimes[1] not in AT_REST),
                       key=lambda kt: -kt[0])
    return Band(dep.depends, agree.depends_in_band, dep.cells, agree.band_cells,
                agree.band_share, [(c.x, float(c.y or 0.0), str(c.regimes[0]), str(c.regimes[1]))
                                   for c in agree.outside], (moving[0], moving[1]), far_moves)


@dataclass
class OrbitAnalysis:
    """Everything the report says from continuation: tau = 10, the fold curve, the band."""

    tau10: Tau10
    folds: list[FoldPoint]
    band: Band | None
    runtime_s: float

    def tau10_lines(self) -> list[str]:
        t = self.tau10
        lines = [f"continuation at tau = 10 (core.continuation, RK4 dt = 0.01, {t.n_points} "
                 f"orbits): Hopf point k = {t.hopf:.6f} (period {t.hopf_period:.5f}), "
                 f"{t.criticality}; "
                 + "; ".join(f"{b.type} at k = {b.value:.6f}" for b in t.found)
                 + f"; nothing else up to k = {K_END:g}"]
        if t.checks:
            lines.append("checked by simulation from the stable orbit (t = 2000): "
                         + "; ".join(f"k = {c.k:.4f}: {'stays, peak-to-peak' if c.stays else 'falls to rest,'} "
                                     f"{c.late_amplitude:.3g}" for c in t.checks))
        lines.append(f"the stable single-slip orbit's leading multiplier for k = 10-25: "
                     f"|mu| = {t.leading[0]:.3f}-{t.leading[1]:.3f}")
        by_k: dict[float, list[str]] = {}
        for k, delta, cycle in t.offsets:
            by_k.setdefault(k, []).append(f"{delta:g} {'cycle' if cycle else 'rest'}")
        lines.append("inside the band, from eq. 19 with offset delta (RK4, t = 2000): "
                     + "; ".join(f"k = {k:g}: " + ", ".join(v) for k, v in by_k.items()))
        return lines

    def pulse_lines(self) -> list[str]:
        return [f"k = {p.k:.2f}: the stable orbit has {p.orbit_maxima} maximum per period; a "
                f"simulation from eq. 19 (delta = 0.1, t = 3000) has {p.simulated_maxima}, at "
                f"distance {p.distance:.2g} from it" for p in self.tau10.pulses]

    def fold_table(self) -> list[str]:
        rows = ["| tau | Hopf k (d = 1e-4) | fold of cycles k | Hopf point |", "|---|---|---|---|"]
        for f in self.folds:
            fold = f"{f.fold:.5f}" if f.fold is not None else f"none ({f.note})" if f.note else "none"
            rows.append(f"| {f.second:.4g} | {f.hopf:.5f} | {fold} | {f.criticality or '-'} |")
        return rows

    def curve(self) -> tuple[np.ndarray, np.ndarray]:
        """The fold curve as (k, tau) arrays, for a (k, tau) phase diagram."""
        return curve_of(self.folds)


def analyse(p: Params, taus: list[float], near: SweepDiagram | None,
            far: SweepDiagram | None, say: Say = None) -> OrbitAnalysis:
    """tau = 10, the fold curve at ``taus`` (and EXTRA_TAUS), and the band against Figs.
    5A/5B when both are given; ``say`` hears of each step (a few minutes in all)."""
    import time
    t0 = time.process_time()
    if say is not None:
        say("continuation at tau = 10 and its checks by simulation")
    t10 = tau10(p.with_(tau=10.0, delta=0.1))
    folds = folds_over_tau(p.with_(delta=0.1), [*taus, *EXTRA_TAUS], say)
    band = band_comparison(near, far, folds) if near is not None and far is not None else None
    return OrbitAnalysis(t10, folds, band, time.process_time() - t0)
