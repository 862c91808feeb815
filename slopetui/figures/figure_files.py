"""The figure of a sweep or of runs, from what the store gave: what ``slopetui figure``
and the application's figure key (f) share.

The faces load the data (``slopetui.sweeps.diagram.load_diagram``,
``slopetui.sweeps.recompute.load_run``); this module adds what the figure needs on top
(the exact Hopf curve of the plane, the recomputed traces), names the file, and hands
``slopetui.figures.output.write`` the drawing.
"""

from __future__ import annotations

import glob
from collections.abc import Callable, Sequence
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

from slopetui.figures.figure_facts import runs_facts, sweep_facts
from slopetui.figures.output import Drawing
from slopetui.figures.run_figure import run_drawing
from slopetui.figures.sweep_figure import sweep_drawing
from slopetui.sweeps.diagram import plane_hopf
from slopetui.sweeps.recompute import recompute
from slopetui.whole_files import first_free

if TYPE_CHECKING:
    from slopetui.sweeps.diagram import SweepDiagram
    from slopetui.sweeps.hopf_plane import Curve
    from slopetui.sweeps.recompute import StoredRun, Traces

#: The format of a figure written without a name (a paper's: vector, fonts embedded).
DEFAULT_FORMAT = "pdf"


def sweep_stem(sweep_id: int) -> str:
    return f"sweep-{sweep_id}"


def runs_stem(run_ids: Sequence[int]) -> str:
    """run-12 for one run, runs-12-13 for a comparison."""
    if len(run_ids) == 1:
        return f"run-{run_ids[0]}"
    return "runs-" + "-".join(map(str, run_ids))


def unused_path(folder: Path, stem: str, fmt: str = DEFAULT_FORMAT) -> Path:
    """folder/stem.fmt, or stem-2.fmt, stem-3.fmt... the first whose figure and data files
    are all free (whole_files.first_free): a key press never overwrites an earlier figure."""
    return first_free(folder, stem, fmt, _figure_taken)


def _figure_taken(path: Path) -> bool:
    # the data beside it: <name>.csv and <name>.<table>.csv (output.data_paths)
    name = path.stem
    return (path.exists() or path.with_name(f"{name}.csv").exists()
            or any(path.parent.glob(f"{glob.escape(name)}.*.csv")))


def sweep_figure(diagram: SweepDiagram, *, hopf: bool = True, fold: Curve | None = None,
                 engines: Sequence[str] = ()) -> Drawing:
    """The sweep's phase diagram (with the exact Hopf curve of its plane, unless ``hopf``
    is False, and the fold of cycles if given) or its bifurcation diagram (1-D), naming
    what it was computed at (``engines``: its done runs' digests, store.queries
    .sweep_engines)."""
    curve = plane_hopf(diagram.spec) if hopf and diagram.spec.y is not None else None
    return replace(sweep_drawing(diagram, hopf=curve, fold=fold),
                   facts=sweep_facts(diagram, engines))


def runs_figure(runs: Sequence[StoredRun], progress: Callable[[StoredRun], None] | None = None
                ) -> Drawing:
    """Recompute the runs (as long as each took; ``progress(run)`` before each) and draw
    one run's four panels, or the comparison of several. Raises ParameterError for a
    run whose stored inputs are invalid."""
    pairs = []
    for run in runs:
        if progress is not None:
            progress(run)
        pairs.append((run, recompute(run)))
    return traced_runs_figure(pairs)


def traced_runs_figure(pairs: Sequence[tuple[StoredRun, Traces]]) -> Drawing:
    """The figure of runs already recomputed, naming what they were computed at."""
    return replace(run_drawing(pairs), facts=runs_facts([run for run, _ in pairs]))
