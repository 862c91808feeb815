"""Terminal plots of sweeps: phase diagrams with the exact Hopf curve, and bifurcation
diagrams. Pure functions from numbers to text (plotext 5); no database, no CLI."""

from slopetui.plots.bifurcation import render_bifurcation
from slopetui.plots.phase_diagram import render_phase_diagram
from slopetui.plots.regime_colors import REGIME_STYLES, RegimeStyle, regime_style
from slopetui.plots.sweep_diagram import render_sweep

__all__ = ["REGIME_STYLES", "RegimeStyle", "regime_style", "render_bifurcation",
           "render_phase_diagram", "render_sweep"]
