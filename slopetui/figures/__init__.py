"""Publication figures: a sweep's phase or bifurcation diagram and a run's traces, drawn
with matplotlib into PDF, SVG or PNG files, each with its data as CSV beside it.

The file counterpart of slopetui.plots (the terminal plots): the same things drawn, for
a paper. Pure drawing: the callers (``slopetui figure``, the application's figure key)
load the sweep or recompute the run and hand the data over; nothing here opens the store
or the queue (pyproject.toml, the figures-draw-only contract).

Usage: ``check_output(path)`` first (before any computation: it writes nothing), then
``write(sweep_drawing(diagram, hopf=...), path)`` or ``write(run_drawing(runs), path)``.

matplotlib (~1 s to import) is imported only when a figure is drawn or saved, so that
importing this package (e.g. for ``check_output``) stays cheap.
"""

from slopetui.figures.output import (
    FORMATS,
    PNG_DPI,
    Drawing,
    FigureError,
    Table,
    check_output,
    data_paths,
    write,
)
from slopetui.figures.run_figure import COMPARE_SIZE, RUN_SIZE, run_drawing
from slopetui.figures.sweep_figure import DIAGRAM_SIZE, sweep_drawing

__all__ = ["COMPARE_SIZE", "DIAGRAM_SIZE", "FORMATS", "PNG_DPI", "RUN_SIZE", "Drawing",
           "FigureError", "Table", "check_output", "data_paths", "run_drawing",
           "sweep_drawing", "write"]
