"""The N-block ensemble beside the mean-field solution: two panels on one y range."""

from __future__ import annotations

import numpy as np
import plotext as plt

from slopetui.plots.canvas import LegendEntry, Series, render
from slopetui.plots.run_plots import stride

MEAN_FIELD_COLOR = "green"
ENSEMBLE_COLOR = "magenta"


def _panel(t: np.ndarray, y: np.ndarray, color: str, label: str, variable: str,
           y_range: tuple[float, float], *, width: int, height: int,
           show_color: bool) -> list[str]:
    keep = stride(len(t))
    series = [Series(t[keep], y[keep], "braille", color, line=True)]
    return render(series, [LegendEntry("⠤⠤", color, label)], x_label="t", y_label=variable,
                  x_log=False, y_log=False, title="", width=width, height=height,
                  color=show_color, y_range=y_range).split("\n")


def render_side_by_side(t: np.ndarray, mean_field: np.ndarray, ensemble: np.ndarray,
                        n_blocks: int, variable: str = "m_y", *, width: int = 100,
                        height: int = 20, color: bool = True) -> str:
    """Left: the mean-field variable against t; right: the ensemble's, on the same y
    range so that amplitudes compare by eye. Exactly height lines, at most width wide."""
    half = (width - 2) // 2
    both = np.concatenate([mean_field[np.isfinite(mean_field)], ensemble[np.isfinite(ensemble)]])
    y_range = (float(both.min()), float(both.max())) if both.size else (0.0, 1.0)
    left = _panel(t, mean_field, MEAN_FIELD_COLOR, "mean field (eqs. 6a-6e)", variable,
                  y_range, width=half, height=height, show_color=color)
    right = _panel(t, ensemble, ENSEMBLE_COLOR, f"ensemble, N = {n_blocks} (eq. 5)", variable,
                   y_range, width=half, height=height, show_color=color)
    return "\n".join(a + " " * (half - len(plt.uncolorize(a)) + 2) + b
                     for a, b in zip(left, right, strict=False))
