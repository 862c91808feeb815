"""The figures the application writes (the f key, the palette): drawn and written in a
background action, under a name not yet taken in the folder, and the notice that says
where.

The folder is $SLOPETUI_FIGURES, else ``figures`` in the user data folder, beside the
default store (slopetui.store.location: ~/.local/share/slopetui/figures on Linux), and
is created on the first figure. Not the folder the application was started in: in a
git checkout that left untracked figures and multi-megabyte CSVs among the sources.
The palette's exports go there too. ``slopetui figure -o`` writes where it is told.

The functions that write run in the action's thread, and import ``slopetui.figures``
there, on first use: the package loads its run figure, which recomputes runs
(``slopetui.sweeps.recompute``: numba and scipy), 0.6 s of CPU (``python -X importtime``,
measured after the application's own imports) before matplotlib itself (~1 s to load, a
second or two to draw). Imported with the application it would slow every start; on the
UI thread it would freeze the screen on the key.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from platformdirs import user_data_path

if TYPE_CHECKING:
    from slopetui.sweeps.diagram import SweepDiagram
    from slopetui.sweeps.fold_overlay import Curve
    from slopetui.sweeps.recompute import StoredRun, Traces


#: Environment variable naming the folder the application writes figures and exports into.
FIGURES_ENV = "SLOPETUI_FIGURES"


def default_folder() -> Path:
    """$SLOPETUI_FIGURES (``~`` expanded, made absolute), else ``figures`` in the user
    data folder, the base of the default store (slopetui.store.location.default_url)."""
    env = os.environ.get(FIGURES_ENV, "").strip()
    if env:
        return Path(os.path.abspath(Path(env).expanduser()))
    return user_data_path("slopetui") / "figures"


def ready_folder(folder: Path) -> Path:
    """``folder``, created with its parents if missing. Raises NotADirectoryError naming
    it and $SLOPETUI_FIGURES when a file is in the way; other OSErrors (no permission)
    as they are, with the path."""
    if folder.exists() and not folder.is_dir():
        raise NotADirectoryError(f"{folder} is a file, not a folder: set ${FIGURES_ENV} to "
                                 f"a folder for the application's figures")
    folder.mkdir(parents=True, exist_ok=True)
    return folder


def write_sweep_figure(diagram: SweepDiagram, fold: Curve | None, folder: Path,
                       engines: Sequence[str] = ()) -> list[Path]:
    """The sweep's figure (its diagram, with the fold curve if given) written in
    ``folder``: the files written, the figure first. ``engines``: the digests its done
    runs were computed with (store.queries.sweep_engines), which the figure names."""
    from slopetui.figures.figure_files import sweep_figure, sweep_stem, unused_path
    from slopetui.figures.output import write

    return write(sweep_figure(diagram, fold=fold, engines=engines),
                 unused_path(ready_folder(folder), sweep_stem(diagram.id)))


def write_runs_figure(runs: Sequence[tuple[StoredRun, Traces]], folder: Path) -> list[Path]:
    """The figure of runs already recomputed (one run's four panels, or the comparison of
    several) written in ``folder``: the files written, the figure first."""
    from slopetui.figures.figure_files import runs_stem, traced_runs_figure, unused_path
    from slopetui.figures.output import write

    return write(traced_runs_figure(runs),
                 unused_path(ready_folder(folder), runs_stem([run.id for run, _ in runs])))


def written_text(paths: Sequence[Path]) -> str:
    """The notice of a figure written: its path, and the names of its data files."""
    figure, *data = paths
    beside = f" (its data: {', '.join(p.name for p in data)})" if data else ""
    return f"figure written: {figure}{beside}"
