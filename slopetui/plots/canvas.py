"""Drawing on plotext 5's one global figure: a fresh figure per plot, the legend below it.

plotext keeps a single module-global figure, so each plot starts from a cleared one
and holds a lock until its text is built (a TUI may render from worker threads).

The title and the legend are written around the plot, not by plotext: plotext 5 always
puts its legend in the top-left corner of the canvas, over the data (a dense sweep grid
loses those cells), and silently drops a legend or a title that does not fit.
"""

from __future__ import annotations

import textwrap
import threading
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import plotext as plt

from slopetui.plots import ticks
from slopetui.plots.regime_colors import (
    REGIME_STYLES,
    THEME_COLOR,
    THEME_PLAIN,
    regime_counts,
)
from slopetui.sweeps.run_labels import SHOWN_AS

#: Smallest plot accepted, in terminal cells: narrower plots squeeze the tick labels
#: out, and with fewer canvas rows plotext folds distinct y values onto one row.
MIN_WIDTH = 30
MIN_PLOT_HEIGHT = 10
#: Columns between two legend entries on one line.
LEGEND_GAP = 3

_LOCK = threading.Lock()


@dataclass(frozen=True, slots=True)
class Series:
    """One plotted set of points, in parameter units; ``line`` joins them in order."""

    xs: np.ndarray
    ys: np.ndarray
    marker: str
    color: str
    line: bool = False


@dataclass(frozen=True, slots=True)
class LegendEntry:
    """A legend item: a marker drawn in ``color`` followed by ``text``."""

    marker: str
    color: str
    text: str


def axis_label(param: str) -> str:
    """The axis label of a model parameter: tau and delta as their Greek letters
    (slopetui.sweeps.run_labels.SHOWN_AS)."""
    return SHOWN_AS.get(param, param)


def check_size(width: int, height: int, reserved: int) -> None:
    """Reject sizes (terminal cells) too small for a readable plot once ``reserved``
    lines (title, legend) are taken from ``height``."""
    need = MIN_PLOT_HEIGHT + reserved
    if width < MIN_WIDTH or height < need:
        raise ValueError(f"plot size {width}x{height} is too small: "
                         f"need at least {MIN_WIDTH} columns and {need} lines")


def visible(values: np.ndarray, log: bool) -> np.ndarray:
    """Mask of the values an axis can show: finite, and > 0 on a log axis."""
    ok = np.isfinite(values)
    return ok & (values > 0.0) if log else ok


def message_block(text: str, width: int, height: int) -> str:
    """``text`` wrapped to ``width`` and padded to exactly ``height`` lines, so a view
    that shows a plot keeps its layout when there is nothing to plot."""
    lines = textwrap.wrap(text, width)[:height]
    return "\n".join(lines + [""] * (height - len(lines)))


def regime_legend(keys: Sequence[str]) -> list[LegendEntry]:
    """One entry per regime key present, "<regime> (<runs>)", in LEGEND_ORDER."""
    return [LegendEntry(REGIME_STYLES[k].marker, REGIME_STYLES[k].color, f"{k} ({n})")
            for k, n in regime_counts(keys).items()]


def note(text: str) -> LegendEntry:
    """A legend entry without a marker of its own, e.g. how many runs are not shown."""
    return LegendEntry("-", "default", text)


def legend_lines(entries: Sequence[LegendEntry], width: int, color: bool) -> list[str]:
    """The entries packed into as few lines of at most ``width`` columns as fit."""
    lines: list[str] = []
    line, used = "", 0
    for entry in entries:
        plain = _fit(f"{entry.marker} {entry.text}", width)
        shown = _paint(entry.marker, entry.color, color) + plain[len(entry.marker):]
        if line and used + LEGEND_GAP + len(plain) > width:
            lines.append(line)
            line, used = "", 0
        if line:
            line += " " * LEGEND_GAP
            used += LEGEND_GAP
        line += shown
        used += len(plain)
    if line:
        lines.append(line)
    return lines


def render(series: Sequence[Series], legend: Sequence[LegendEntry], *, x_label: str,
           y_label: str, x_log: bool, y_log: bool, title: str, width: int, height: int,
           color: bool, x_range: tuple[float, float] | None = None,
           y_range: tuple[float, float] | None = None) -> str:
    """The series plotted under the title and over the legend: exactly ``height`` lines,
    each at most ``width`` columns wide, and no ANSI escapes when ``color`` is False.
    ``x_range`` pins the x axis (e.g. to the whole sweep, when only part of it has points)."""
    above = [_fit(title, width).center(width).rstrip()] if title else []
    below = legend_lines(legend, width, color)
    check_size(width, height, len(above) + len(below))
    plot_height = height - len(above) - len(below)
    with _LOCK:
        _fresh_figure(width, plot_height, color)
        for s in series:
            draw = plt.plot if s.line else plt.scatter
            draw(s.xs.tolist(), s.ys.tolist(), marker=s.marker,
                 color=s.color if color else "default")
        plt.xlabel(x_label)
        plt.ylabel(y_label)
        if x_log:
            plt.xscale("log")
        if x_range is not None and x_range[0] < x_range[1]:
            plt.xlim(*x_range)
        if y_range is not None and y_range[0] < y_range[1]:
            plt.ylim(*y_range)
        if y_log:
            plt.yscale("log")
        _round_ticks(series, width, plot_height, x_log=x_log, y_log=y_log, x_range=x_range,
                     y_range=y_range, x_label=bool(x_label))
        text = plt.build()
        plt.clear_figure()           # leave no data behind in plotext's global figure
    if not color:
        # even theme "clear" ends every line with a reset code
        text = plt.uncolorize(text)
    return "\n".join(above + text.rstrip("\n").split("\n") + below)


def _round_ticks(series: Sequence[Series], width: int, height: int, *, x_log: bool, y_log: bool,
                 x_range: tuple[float, float] | None, y_range: tuple[float, float] | None,
                 x_label: bool) -> None:
    """Ticks at round numbers (slopetui.plots.ticks) in place of plotext's, for the
    ranges plotext will draw: the pinned one, else the data's."""
    def span(values: np.ndarray, log: bool, pinned: tuple[float, float] | None) -> tuple[float, float]:
        if pinned is not None and pinned[0] < pinned[1]:
            return pinned
        return ticks.data_range(values, log)

    if not series:
        return
    xs = np.concatenate([s.xs for s in series])
    ys = np.concatenate([s.ys for s in series])
    y_lo, y_hi = span(ys, y_log, y_range)
    # the canvas: the plot less its frame (2), the x ticks' row and the x label's
    rows = height - 3 - (1 if x_label else 0)
    y_ticks, y_labels = ticks.axis_ticks(y_lo, y_hi, log=y_log, length=rows, label_room=False)
    x_lo, x_hi = span(xs, x_log, x_range)
    columns = width - max(map(len, y_labels), default=0) - 2  # the y labels and the frame
    x_ticks, x_labels = ticks.axis_ticks(x_lo, x_hi, log=x_log, length=columns, label_room=True)
    plt.yticks(y_ticks, y_labels)
    plt.xticks(x_ticks, x_labels)


def _fresh_figure(width: int, height: int, color: bool) -> None:
    # main() makes the top figure active again in case someone selected a subplot
    plt.main()
    plt.clear_figure()
    # by default plotext shrinks the plot to the terminal, which is not ours to measure
    plt.limitsize(False, False)
    plt.plotsize(width, height)
    plt.theme(THEME_COLOR if color else THEME_PLAIN)


def _paint(text: str, color_name: str, color: bool) -> str:
    return plt.colorize(text, color_name) if color else text


def _fit(text: str, width: int) -> str:
    """``text`` cut to ``width`` columns, with an ellipsis when cut."""
    return text if len(text) <= width else text[: max(width - 1, 0)] + "…"
