"""The figures the application writes (the f key, the palette): drawn and written in a
background action, under a name not yet taken in the folder, and the notice that says
where.

The functions that write run in the action's thread, and import ``slopetui.figures``
there, on first use: the package loads its run figure, which recomputes runs
(``slopetui.sweeps.recompute``: numba and scipy), 0.6 s of CPU (``python -X importtime``,
measured after the application's own imports) before matplotlib itself (~1 s to load, a
second or two to draw). Imported with the application it would slow every start; on the
UI thread it would freeze the screen on the key.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from slopetui.sweeps.diagram import SweepDiagram
    from slopetui.sweeps.fold_overlay import Curve
    from slopetui.sweeps.recompute import StoredRun, Traces


def write_sweep_figure(diagram: SweepDiagram, fold: Curve | None, folder: Path) -> list[Path]:
    """The sweep's figure (its diagram, with the fold curve if given) written in
    ``folder``: the files written, the figure first."""
    from slopetui.figures.figure_files import sweep_figure, sweep_stem, unused_path
    from slopetui.figures.output import write

    return write(sweep_figure(diagram, fold=fold), unused_path(folder, sweep_stem(diagram.id)))


def write_runs_figure(runs: Sequence[tuple[StoredRun, Traces]], folder: Path) -> list[Path]:
    """The figure of runs already recomputed (one run's four panels, or the comparison of
    several) written in ``folder``: the files written, the figure first."""
    from slopetui.figures.figure_files import runs_stem, unused_path
    from slopetui.figures.output import write
    from slopetui.figures.run_figure import run_drawing

    return write(run_drawing(runs), unused_path(folder, runs_stem([run.id for run, _ in runs])))


def written_text(paths: Sequence[Path]) -> str:
    """The notice of a figure written: its path, and the names of its data files."""
    figure, *data = paths
    beside = f" (its data: {', '.join(p.name for p in data)})" if data else ""
    return f"figure written: {figure}{beside}"
