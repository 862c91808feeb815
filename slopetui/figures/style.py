"""Colours and line styles of the publication figures.

Regimes take the Okabe–Ito palette (Okabe & Ito 2008, "Color Universal Design"): its eight
colours stay distinct under the three common colour-vision deficiencies (protanopia,
deuteranopia, tritanopia) and in greyscale print differ enough in lightness for the
neighbouring regimes of a phase diagram. Each regime keeps the hue family of its
terminal colour (slopetui.plots.regime_colors), so the screen and the paper agree:

  sliding      #56B4E9  sky blue        the quiet state, usually the largest region: light
  oscillatory  #009E73  bluish green    a period-1 limit cycle
  complex      #CC79A7  reddish purple  period-n, quasi-periodic or chaotic
  mixed        #E69F00  orange          switches between quiet and oscillating stretches
  unstable     #D55E00  vermillion      blew up: the alarm colour
  undetermined #F0E442  yellow          where the run goes is not known: Okabe–Ito's last
                                        colour, light on paper, which suits a rare cell
                                        next to the Hopf curve that says "not decided"
  depends      #0072B2  blue            a cell whose initial conditions disagree: dark, so
                                        it stands out against sliding's light blue
  failed       #4D4D4D  dark grey       not a result: the worker gave up (run status
                                        failed). The darkest fill, so a failure is not
                                        missed, yet not Okabe–Ito's black, which the curves
                                        drawn over the cells take (a Hopf curve through
                                        black cells would vanish); greys carry no hue, so
                                        no colour-vision deficiency confuses it with a
                                        regime, and in greyscale it is darker than depends
  cancelled    #999999  mid grey        not a result: cancelled before it ran. Between
                                        failed and pending in lightness (contrast about
                                        2:1 with pending, 3:1 with failed): a run given
                                        up by choice, not by the model or the solver
  pending      #DDDDDD  light grey      not a result (not finished or not queued yet): not
                                        Okabe–Ito on purpose, so that it recedes

The three greys are the keys without a regime (slopetui.plots.regime_colors.run_key):
a reader tells "no answer" from every answer by the missing hue, then the three apart
by lightness. In greyscale print cancelled is as light as complex or oscillatory; the
legend's counts and the data table's status column say which.

Okabe–Ito's black is left for the curves drawn over the cells (the exact Hopf curve solid,
the fold of cycles dashed: told apart by the dash, not by colour), and its yellow
(#F0E442), too light on white paper for a large region, for the rare undetermined cells.

The regime keys, their legend order, ``regime_key`` and ``regime_counts`` are the
terminal plots' (slopetui.plots.regime_colors), imported: figures sits in the layer above
plots (pyproject.toml, the "layers" contract), so the two cannot drift apart.
"""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType
from typing import Literal

from core.regimes import DEPENDS
from slopetui.plots.regime_colors import CANCELLED, FAILED, PENDING

#: Fill colour of each regime key (see the module docstring).
REGIME_COLORS: Mapping[str, str] = MappingProxyType({
    "sliding": "#56B4E9",
    "oscillatory": "#009E73",
    "complex": "#CC79A7",
    "mixed": "#E69F00",
    "unstable": "#D55E00",
    "undetermined": "#F0E442",
    DEPENDS: "#0072B2",
    FAILED: "#4D4D4D",
    CANCELLED: "#999999",
    PENDING: "#DDDDDD",
})

#: Line colours of the runs of a comparison, in order: Okabe–Ito again (a qualitative
#: palette), the darkest first, yellow last. Beyond eight runs the colours repeat with
#: the next of RUN_DASHES, so up to 32 runs stay apart.
RUN_COLORS: tuple[str, ...] = ("#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00",
                               "#56B4E9", "#000000", "#F0E442")
Dash = Literal["-", "--", ":", "-."]
RUN_DASHES: tuple[Dash, ...] = ("-", "--", ":", "-.")

#: The curves over a phase diagram: black, told apart by the dash.
HOPF_LABEL = "Hopf (exact)"
HOPF_STYLE: Mapping[str, object] = MappingProxyType(
    {"color": "black", "linestyle": "-", "linewidth": 1.6})
FOLD_LABEL = "fold of cycles"
FOLD_STYLE: Mapping[str, object] = MappingProxyType(
    {"color": "black", "linestyle": "--", "linewidth": 1.4})

#: A reference line (zero of λ(t)) and a marked point (the spectrum's largest peak).
GUIDE_COLOR = "#777777"
#: The two series of a run's time series: m_x − trend (orange) under m_y (blue).
MX_COLOR = "#E69F00"
MY_COLOR = "#0072B2"
#: The phase portrait, the spectrum and λ(t) of a single run.
TRACE_COLOR = "#0072B2"
PEAK_COLOR = "#D55E00"


def run_style(i: int) -> tuple[str, Dash]:
    """Colour and dash of the i-th run of a comparison (see RUN_COLORS)."""
    n = len(RUN_COLORS)
    return RUN_COLORS[i % n], RUN_DASHES[(i // n) % len(RUN_DASHES)]
