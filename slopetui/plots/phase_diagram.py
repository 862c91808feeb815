"""The phase diagram of a sweep: each run a point in the (x, y) parameter plane, marked by
its regime, with the exact Hopf curve of the sliding state over it."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from slopetui.plots.canvas import (
    LegendEntry,
    Series,
    axis_label,
    message_block,
    note,
    regime_legend,
    render,
    visible,
)
from slopetui.plots.regime_colors import (
    FOLD_COLOR,
    FOLD_LABEL,
    FOLD_LEGEND_MARKER,
    FOLD_MARKER,
    HOPF_COLOR,
    HOPF_LABEL,
    HOPF_LEGEND_MARKER,
    HOPF_MARKER,
    REGIME_STYLES,
    regime_key,
)


def render_phase_diagram(x_param: str, y_param: str, xs: Sequence[float], ys: Sequence[float],
                         regimes: Sequence[str | None], *, x_log: bool = False,
                         y_log: bool = False, hopf: tuple[np.ndarray, np.ndarray] | None = None,
                         fold: tuple[np.ndarray, np.ndarray] | None = None, title: str = "",
                         width: int = 80, height: int = 24, color: bool = True,
                         notes: Sequence[str] = ()) -> str:
    """The runs at (xs[i], ys[i]) (parameter values, model units) marked by regimes[i].

    One series per regime; regime None or "pending" (not finished) is drawn in the faint
    pending style. A regime may also be a style key (regime_colors.run_key: "failed",
    "cancelled"), which is how a sweep's runs without a result are drawn as such. The
    legend under the plot names each regime with its run count, and counts the runs a
    log axis cannot show (values <= 0) or with non-finite values.
    ``hopf`` is a curve from hopf_boundary, drawn last so no run hides it; ``fold`` the
    fold-of-cycles curve (core.fold_curve), drawn as dots, likewise. ``notes`` are
    added to the legend as they are (e.g. an adaptive sweep's computed and inferred
    counts). Returns exactly
    ``height`` lines of at most ``width`` columns; with ``color`` False, no ANSI escapes.
    Raises ValueError for inputs of unequal length, an unknown regime, or a size too small.
    """
    x = np.asarray(xs, dtype=float)
    y = np.asarray(ys, dtype=float)
    keys = [regime_key(r) for r in regimes]
    if not len(x) == len(y) == len(keys):
        raise ValueError(f"xs, ys and regimes differ in length: {len(x)}, {len(y)}, {len(keys)}")
    shown = visible(x, x_log) & visible(y, y_log)
    series = _regime_series(x, y, keys, shown)
    legend = regime_legend(keys)
    curve = _visible_curve(hopf, x_log, y_log, HOPF_MARKER, HOPF_COLOR, line=True)
    if curve is not None:
        series.append(curve)
        legend.append(LegendEntry(HOPF_LEGEND_MARKER, HOPF_COLOR, HOPF_LABEL))
    folds = _visible_curve(fold, x_log, y_log, FOLD_MARKER, FOLD_COLOR, line=False)
    if folds is not None:
        series.append(folds)
        legend.append(LegendEntry(FOLD_LEGEND_MARKER, FOLD_COLOR, FOLD_LABEL))
    hidden = len(keys) - int(shown.sum())
    if hidden:
        why = "<= 0 on a log axis, or not finite" if x_log or y_log else "not finite"
        legend.append(note(f"{hidden} not shown ({why})"))
    legend.extend(note(text) for text in notes)
    if not series:
        what = f"{len(keys)} runs, none plottable" if keys else "no runs"
        prefix = f"{title}: " if title else ""
        return message_block(f"{prefix}{what} in the ({x_param}, {y_param}) plane.", width, height)
    return render(series, legend, x_label=axis_label(x_param), y_label=axis_label(y_param),
                  x_log=x_log, y_log=y_log, title=title, width=width, height=height, color=color)


def _regime_series(x: np.ndarray, y: np.ndarray, keys: list[str],
                   shown: np.ndarray) -> list[Series]:
    """One series per regime with shown points, the most numerous first: where runs share
    a terminal cell the later one wins, so rare regimes stay visible."""
    key_array = np.array(keys, dtype=object)
    masks = {k: shown & (key_array == k) for k in dict.fromkeys(keys)}
    order = sorted((k for k in masks if masks[k].any()), key=lambda k: -int(masks[k].sum()))
    return [Series(x[masks[k]], y[masks[k]], REGIME_STYLES[k].marker, REGIME_STYLES[k].color)
            for k in order]


def _visible_curve(curve: tuple[np.ndarray, np.ndarray] | None, x_log: bool, y_log: bool,
                   marker: str, color: str, *, line: bool) -> Series | None:
    """A curve (the Hopf curve, the fold of cycles), without points a log axis cannot show
    or that are not finite; None if empty."""
    if curve is None:
        return None
    hx, hy = (np.asarray(a, dtype=float) for a in curve)
    keep = visible(hx, x_log) & visible(hy, y_log)
    if not keep.any():
        return None
    return Series(hx[keep], hy[keep], marker, color, line=line)
