"""``slopetui reproduce --report``: compute every preset through the queue, then write
docs/reproduction.md with the paper's claim, slopetui's diagram and measurements, and a
verdict for each figure."""

from __future__ import annotations

import time
from datetime import date
from pathlib import Path

from slopetui.plots import render_sweep
from slopetui.queue.pool import default_jobs, run_pool
from slopetui.queue.worker_process import WorkerOptions
from slopetui.reproduce.findings import FINDINGS, Diagrams, Finding
from slopetui.store.database import Database
from slopetui.store.queries import runtime_total, unfinished_runs
from slopetui.sweeps.diagram import SweepDiagram, load_diagram
from slopetui.sweeps.presets import BY_KEY, PRESETS
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
        from slopetui.sweeps.adaptive import advance_all
        from slopetui.sweeps.progress import PoolProgress
        opts = WorkerOptions(db_url=db.url.render_as_string(hide_password=False),
                             log_path=str(log), exit_when_idle=True, idle_hook=advance_all,
                             progress=PoolProgress)
        run_pool(opts, jobs or default_jobs())
    return ids, time.perf_counter() - t0


def diagram_text(d: SweepDiagram) -> str:
    """The figure's diagram as plain text (the one render path of show and the TUI)."""
    return render_sweep(d, width=WIDTH, height=HEIGHT, color=False,
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
    out += ["**slopetui measured:**", ""] + [f"- {line}" for line in f.measured] + [""]
    single = all(len(diagrams[k].runs) == 1 for k in f.keys)
    if not single:
        for k in f.keys:
            out += ["```text", diagram_text(diagrams[k]).rstrip(), "```", ""]
    out += [f"**Verdict: {f.verdict}.** {f.reason}", ""]
    return "\n".join(out)


class Unfinished(KeyError):
    """A finding asked for a diagram whose runs are not all done."""


class FinishedDiagrams(dict[str, SweepDiagram]):
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


def _duration(seconds: float) -> str:
    return f"{seconds:.0f} s" if seconds < 120 else f"{seconds / 60:.0f} min"


def write_report(db: Database, resolution: int, t_end: float | None, out: Path,
                 jobs: int | None = None) -> tuple[Path, bool]:
    """Compute and write the report; returns its path and whether every figure was
    complete (an interrupted computation writes a report marked INCOMPLETE, with verdicts
    only for the figures whose runs are all done)."""
    out.parent.mkdir(parents=True, exist_ok=True)
    ids, wall = compute(db, resolution, t_end, jobs, out.with_suffix(".log"))
    diagrams = {k: load_diagram(db, i) for k, i in ids.items()}
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
        f"{jobs or default_jobs()} cores; this generation computed for {_duration(wall)} "
        "(the rest came from the store's cache). Verdicts: "
        + ", ".join(f"{v} {n}" for v, n in tally.items()) + ".",
        "",
        "Diagram legend: `.` sliding, `o` oscillatory, `*` complex, `+` mixed, `x` unstable; "
        "the braille line is the exact Hopf curve of the fixed point (linear stability, "
        "`core.stability`). Sliding runs of a bifurcation diagram are drawn at their mean m_y.",
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
    out.write_text("\n".join(head + body), encoding="utf-8")
    return out, complete
