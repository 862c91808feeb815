"""The blank figure every drawing starts from, its title, and a panel's "nothing to draw".

A ``matplotlib.figure.Figure`` made directly, never through pyplot: no backend is
selected and no display is needed (over SSH too), nothing registers the figure in a
global list, and figures can be drawn in the TUI's worker threads. ``savefig`` picks the
Agg, PDF or SVG canvas from the format. The layout engine is "constrained": it makes
room for the titles, tick labels and a legend outside the axes, so nothing is clipped at
the fixed figure size (the size stays exact: no bbox_inches="tight").
"""

from __future__ import annotations

import textwrap
from typing import TYPE_CHECKING

from slopetui.figures.labels import plain

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: Font size of a figure's title (points); the rest keeps matplotlib's default (10 pt).
TITLE_SIZE = 11
#: Minor ticks of a log axis are labelled when it spans fewer decades than the first
#: number (a subset of them below the second): matplotlib's LogFormatter thresholds,
#: raised from (1, 0.4) so that a sweep over 0.5 to 10 has more than two labels.
LOG_MINOR_THRESHOLDS = (2.0, 0.5)
#: A title line holds about this many characters per inch of figure width at TITLE_SIZE
#: (DejaVu Sans averages ~0.6 em a character: 72 / (0.6 * 11) = 10.9); longer titles
#: wrap instead of running off the page.
TITLE_CHARS_PER_INCH = 10
#: The share of a diagram's width its axes take beside the legend (about 0.7 at 6.4 in
#: with the longest legend, "oscillatory (1,234)"), for wrapping an axes title.
AXES_SHARE = 0.7


def new_figure(size: tuple[float, float]) -> Figure:
    """An empty figure of ``size`` inches with the constrained layout."""
    from matplotlib.figure import Figure

    return Figure(figsize=size, layout="constrained")


def set_title(figure: Figure, title: str, ax: Axes | None = None) -> None:
    """The figure's title, as plain text (labels.plain) line by line, each line wrapped to
    the figure's width (at spaces only: a break inside an escape would undo it). With
    ``ax``, the title of that axes instead, wrapped to its share of the width: a diagram's
    legend sits right of its one axes, up to the top, where a figure title centred on the
    whole width would run into it."""
    inches = figure.get_figwidth() * (AXES_SHARE if ax is not None else 1.0)
    width = max(20, int(inches * TITLE_CHARS_PER_INCH))
    lines = [textwrap.fill(plain(line), width, break_long_words=False, break_on_hyphens=False)
             for line in title.split("\n")]
    if ax is not None:
        ax.set_title("\n".join(lines), fontsize=TITLE_SIZE)
    else:
        figure.suptitle("\n".join(lines), fontsize=TITLE_SIZE)


def log_scale(ax: Axes, axis: str) -> None:
    """A log scale on ``axis`` ("x" or "y") whose ticks read as plain numbers (3, 0.5,
    20, 1e-06) rather than matplotlib's default 3×10⁰: a sweep's range often spans
    less than a decade, where the default labels only minor ticks, all in that form."""
    from matplotlib.ticker import LogFormatter

    class PlainLogFormatter(LogFormatter):
        def __call__(self, x: float, pos: int | None = None) -> str:
            return f"{x:g}" if super().__call__(x, pos) else ""

    target = ax.xaxis if axis == "x" else ax.yaxis
    if axis == "x":
        ax.set_xscale("log")
    else:
        ax.set_yscale("log")
    target.set_major_formatter(PlainLogFormatter())
    target.set_minor_formatter(PlainLogFormatter(minor_thresholds=LOG_MINOR_THRESHOLDS))


def time_origin(lo: float, hi: float) -> float:
    """The origin a linear time axis over [lo, hi] is drawn from: 0, or the offset
    matplotlib's ScalarFormatter would print beside the axis for those ticks ("+1e5":
    the last periods of a long run, 99 950 to 100 000). That offset text sits at the
    axis' right end, at the height of the x label, and in the constrained layout the two
    overprint; the caller draws t − origin instead and names the origin in the label
    (labels.time_label)."""
    from matplotlib.ticker import MaxNLocator, ScalarFormatter

    formatter = ScalarFormatter()
    formatter.create_dummy_axis()
    assert formatter.axis is not None  # create_dummy_axis set it
    formatter.axis.set_view_interval(lo, hi)
    formatter.set_locs(list(MaxNLocator().tick_values(lo, hi)))
    return float(formatter.offset)


def no_offset(ax: Axes) -> None:
    """Tick labels of the x axis as the numbers they are, never a shared offset text
    (time_origin: it would overprint the label)."""
    from matplotlib.ticker import ScalarFormatter

    formatter = ScalarFormatter(useOffset=False)
    ax.xaxis.set_major_formatter(formatter)


def empty_panel(ax: Axes, message: str) -> None:
    """A panel with nothing to plot says why, in its middle, without axes ticks."""
    ax.text(0.5, 0.5, message, ha="center", va="center", wrap=True, transform=ax.transAxes,
            color="#555555")
    ax.set_xticks([])
    ax.set_yticks([])
