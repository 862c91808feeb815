"""``slopetui reproduce --report``: compute every preset through the queue, then write
docs/reproduction.md with the paper's claim, slopetui's diagram and measurements, and a
verdict for each figure."""

from __future__ import annotations

import time
from datetime import date
from pathlib import Path

from slopetui.duration_text import duration_text
from slopetui.plots import render_sweep
from slopetui.queue.pool import default_jobs, run_pool
from slopetui.queue.worker_process import WorkerOptions
from slopetui.reproduce import measures as m
from slopetui.reproduce.delta_maps import MAP_FIGURES, DeltaMap, delta_map, friction_folds, maps_section
from slopetui.reproduce.findings import FINDINGS, Diagrams, Finding, band_lines
from slopetui.reproduce.orbit_analysis import OrbitAnalysis, Say, analyse
from slopetui.store.database import Database
from slopetui.store.queries import runtime_total, unfinished_runs
from slopetui.sweeps.adaptive import advance_all
from slopetui.sweeps.diagram import SweepDiagram, load_diagram
from slopetui.sweeps.fold_overlay import has_fold_plane, inside
from slopetui.sweeps.presets import BY_KEY, PRESETS
from slopetui.sweeps.progress import PoolProgress
from slopetui.sweeps.spec import parse_spec
from slopetui.sweeps.submit import submit

WIDTH, HEIGHT = 78, 24


def compute(db: Database, resolution: int, t_end: float | None, jobs: int | None,
            log: Path) -> tuple[dict[str, int], float]:
    """Queue every preset (finished runs come from the cache) and run a local pool until
    the queue is empty. Returns the sweep id per preset and the wall time (s)."""
    ids = {}
    for p in PRESETS:
        ids[p.key] = submit(db, parse_spec(p.at_resolution(resolution, t_end))).sweep_id
    t0 = time.perf_counter()
    if unfinished_runs(db, ids.values()):
        # idle_grace_s = 0: the report waits for its own sweeps, which it never pauses,
        # not for the grace period that a paused sweep elsewhere in the store would hold
        opts = WorkerOptions(db_url=db.url.render_as_string(hide_password=False),
                             log_path=str(log), exit_when_idle=True, idle_grace_s=0.0,
                             idle_hook=advance_all, progress=PoolProgress)
        run_pool(opts, jobs or default_jobs())
    return ids, time.perf_counter() - t0


def diagram_text(d: SweepDiagram, orbits: OrbitAnalysis | None = None) -> str:
    """The figure's diagram as plain text (the one render path of show and the TUI), with
    the fold-of-cycles curve over a (k, tau) plane when the orbits were analysed."""
    fold = (inside(d.spec, *orbits.curve()) if orbits is not None and has_fold_plane(d.spec)
            else None)
    return render_sweep(d, width=WIDTH, height=HEIGHT, color=False, fold=fold,
                        title=f"{d.name} ({d.n_done}/{len(d.runs)} runs)")


def section(f: Finding, diagrams: Diagrams) -> str:
    presets = [BY_KEY[k] for k in f.keys]
    figures = ", ".join(p.figure for p in presets)
    out = [f"## {figures}: {f.verdict.upper()}", ""]
    claim = presets[0].claim
    out += ["**The paper says:**", "", *[f"> {line}" for line in claim.split("\n")], ""]
    notes: list[str] = []
    for p in presets:
        if p.note not in notes:
            notes.append(p.note)
    out += ["**Ranges and points:** " + " ".join(notes), ""]
    out += ["**slopetui measured:**", ""] + [f"- {line}" for line in f.measured]
    # what the window shows is the measured lines; what is certified about the attractor
    out += [f"- {BY_KEY[k].figure}: {m.certified_text(diagrams[k])}" for k in f.keys] + [""]
    single = all(len(diagrams[k].runs) == 1 for k in f.keys)
    if not single:
        for k in f.keys:
            out += ["```text", diagram_text(diagrams[k], diagrams.orbits).rstrip(), "```", ""]
    out += [f"**Verdict: {f.verdict}.** {f.reason}", ""]
    return "\n".join(out)


class Unfinished(KeyError):
    """A finding asked for a diagram whose runs are not all done."""


class FinishedDiagrams(Diagrams):
    """The diagrams a finding may read: an unfinished one raises Unfinished, so that no
    verdict is ever drawn from a figure with runs missing (an interrupted report once
    said "nan% of 0 runs agree" and DISAGREE for figures that had no runs at all)."""

    def __getitem__(self, key: str) -> SweepDiagram:
        diagram = super().__getitem__(key)
        if not finished(diagram):
            raise Unfinished(key)
        return diagram


def finished(d: SweepDiagram) -> bool:
    """Every point of the sweep has a run, and every run is done (a failed run has no
    result to judge)."""
    return len(d.runs) >= d.n_points and d.n_done == len(d.runs)


def evaluate(diagrams: Diagrams) -> list[Finding | Unfinished]:
    """Each finding, or Unfinished naming the first diagram it lacked."""
    complete = FinishedDiagrams(diagrams)
    complete.orbits = diagrams.orbits
    out: list[Finding | Unfinished] = []
    for f in FINDINGS:
        try:
            out.append(f(complete))
        except Unfinished as missing:
            out.append(missing)
    return out


def unfinished_section(missing: Unfinished, diagrams: Diagrams) -> str:
    key = missing.args[0]
    d = diagrams[key]
    return "\n".join([f"## {BY_KEY[key].figure} and what depends on it: INCOMPLETE", "",
                      f"{d.n_done} of {d.n_points} runs of {BY_KEY[key].figure} are done; "
                      "no verdict is drawn from a figure with runs missing. Run the same "
                      "command again to finish it (done runs come from the store).", ""])


def orbit_analysis(diagrams: Diagrams, say: Say = None) -> OrbitAnalysis:
    """Continuation at tau = 10 and the fold of cycles at the taus of Fig. 5's axis (and
    beyond it), held against Figs. 5A/5B when they are complete."""
    near, far = diagrams["fig5a"], diagrams["fig5b"]
    assert near.spec.y is not None
    both = finished(near) and finished(far)
    return analyse(near.spec.base, [float(t) for t in near.spec.y.values()],
                   near if both else None, far if both else None, say)


def delta_maps(diagrams: Diagrams, orbits: OrbitAnalysis, say: Say = None) -> list[DeltaMap]:
    """Figs. 5, 6, 8, 9, 10 as delta-dependence maps, with the fold curve of each plane
    that has one (Fig. 5's from the orbit analysis, the friction planes' computed now)."""
    maps = []
    for stem in MAP_FIGURES:
        near, far = diagrams[f"{stem}a"], diagrams[f"{stem}b"]
        param = near.spec.x.param
        folds = (orbits.folds if param == "k" else
                 friction_folds(near, say) if param in ("a", "b", "c") else [])
        maps.append(delta_map(BY_KEY[f"{stem}a"].figure.removesuffix("A"), near, far, folds))
    return maps


def orbit_section(o: OrbitAnalysis) -> str:
    out = ["## Periodic orbits, their bifurcations and the bistable band (continuation)", "",
           "What the paper could only see by simulating, computed: periodic orbits by "
           "Newton-Krylov shooting on the discretised delay equation (RK4, dt = 0.01), their "
           "Floquet multipliers by Arnoldi, branches by pseudo-arclength continuation "
           "(`slopetui orbit`, `slopetui continue`). The fold of cycles bounds, with the Hopf "
           "curve, the band where a stable cycle and the stable steady state coexist: there "
           "the initial state decides, the paper's conditionally stable slopes.", "",
           "**At tau = 10 (Figs. 4A, 4B):**", "", *[f"- {line}" for line in o.tau10_lines()],
           *[f"- {line}" for line in o.pulse_lines()], "",
           "**The fold of cycles over tau** (each value an independent continuation from the "
           "Hopf point, at the defaults of eq. 8):", "", *o.fold_table(), ""]
    if o.band is not None:
        out += ["**Against Figs. 5A/5B:**", "", *[f"- {line}" for line in band_lines(o.band)], ""]
    out += [f"The analysis took {o.runtime_s:.0f} s of CPU.", ""]
    return "\n".join(out)


def write_report(db: Database, resolution: int, t_end: float | None, out: Path,
                 jobs: int | None = None, orbits: bool = True, say: Say = None
                 ) -> tuple[Path, bool]:
    """Compute and write the report; returns its path and whether every figure was
    complete (an interrupted computation writes a report marked INCOMPLETE, with verdicts
    only for the figures whose runs are all done). ``orbits`` adds the continuation
    analysis to a complete report (a few minutes of CPU: the fold curve at large
    delays), whose steps ``say`` hears of."""
    out.parent.mkdir(parents=True, exist_ok=True)
    ids, wall = compute(db, resolution, t_end, jobs, out.with_suffix(".log"))
    diagrams = Diagrams({k: load_diagram(db, i) for k, i in ids.items()})
    # Only for a complete report: an interrupted one is run again, and the analysis (a few
    # minutes) does not depend on the runs except for its comparison with Figs. 5A/5B.
    if orbits and all(finished(d) for d in diagrams.values()):
        diagrams.orbits = orbit_analysis(diagrams, say)
    results = evaluate(diagrams)
    findings = [f for f in results if isinstance(f, Finding)]
    complete = len(findings) == len(results)
    n_runs = sum(len(d.runs) for d in diagrams.values())
    n_done = sum(d.n_done for d in diagrams.values())
    # cached runs carry the runtime of the run that computed them
    core_s = runtime_total(db, ids.values())
    tally = {v: sum(f.verdict == v for f in findings) for v in ("agree", "partly", "disagree")}
    head = [
        "# The paper reproduced" + ("" if complete else " (INCOMPLETE)"),
        "",
        *([] if complete else [
            f"**Incomplete:** the computation was interrupted with {n_done} of {n_runs} "
            f"runs done. {len(results) - len(findings)} of {len(results)} findings have no "
            "verdict (marked INCOMPLETE below); run the same command again to finish.", ""]),
        "*Complex global dynamics of conditionally stable slopes: effect of initial "
        "conditions* (the seed paper), figure by figure: what it says, what slopetui "
        "measures, and whether they agree.",
        "",
        f"Generated by `slopetui reproduce --report --resolution {resolution}"
        + (f" --t-end {t_end:g}" if t_end else "") + f"` on {date.today().isoformat()}: "
        f"{n_done} of {n_runs} runs done, phase diagrams at {resolution} x {resolution}, "
        "the paper's solver "
        "(Euler, dt = 1e-3"
        + (f", t_end = {t_end:g}" if t_end else ", t_end = 1e5, window [99000, 100000]")
        + f"). The runs took {core_s / 60:.0f} core-minutes (the sum of their runtimes), "
        f"about {core_s / 60 / max(jobs or default_jobs(), 1):.0f} min on this machine's "
        f"{jobs or default_jobs()} cores; this generation computed for {duration_text(wall)} "
        "(the rest came from the store's cache). Verdicts: "
        + ", ".join(f"{v} {n}" for v, n in tally.items()) + ".",
        "",
        "Diagram legend: `.` sliding, `o` oscillatory, `*` complex, `+` mixed, `x` unstable, "
        "`~` undetermined; "
        "the braille line is the exact Hopf curve of the fixed point (linear stability, "
        "`core.stability`, without noise), and `•` over a (k, tau) plane the fold of cycles "
        "(continuation, last section). Sliding runs of a bifurcation diagram are drawn at "
        "their mean m_y.",
        "",
        "| figure | verdict |",
        "|---|---|",
        *[f"| {', '.join(BY_KEY[k].figure for k in f.keys)} | {f.verdict} |"
          if isinstance(f, Finding) else f"| {BY_KEY[f.args[0]].figure} ... | INCOMPLETE |"
          for f in results],
        "",
    ]
    body = [section(f, diagrams) if isinstance(f, Finding) else unfinished_section(f, diagrams)
            for f in results]
    if diagrams.orbits is not None:
        body.append(orbit_section(diagrams.orbits))
        body.append(maps_section(delta_maps(diagrams, diagrams.orbits, say)))
    out.write_text("\n".join(head + body), encoding="utf-8")
    return out, complete
