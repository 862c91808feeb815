"""Colour and marker of each regime (core.regimes.REGIMES) in the terminal plots.

Colours are plotext's basic 16-colour names, so they survive 16-colour terminals, and
were picked to read on both dark and light backgrounds:

  sliding      cyan     '.'   the quiet state; usually the largest region, so the least ink
  oscillatory  green    'o'   a period-1 limit cycle: one closed orbit
  complex      magenta  '*'   period-n, quasi-periodic or chaotic
  mixed        orange   '+'   switches between quiet and oscillating stretches
  unstable     red      'x'   the run blew up: crossed out
  depends      blue+    '#'   not a regime: a cell whose initial conditions end in different
                              regimes (slopetui.sweeps.initial_dependence): bright blue (ANSI
                              12, legible on black where plain blue is not) and a heavy mark
  pending      gray     '?'   not finished yet (None or "pending"): faint, and plotted so a
                              live sweep shows which cells are still missing

Blue is left out: ANSI blue on a black background is barely visible in many palettes.
plotext's "orange" is ANSI colour 3, which terminals show as yellow or brown; plotext 5
has no "yellow" name (it silently draws uncoloured). The Hopf curve uses "default", the
terminal's own foreground, so it is legible on any background and differs from every
regime colour; it is drawn in braille dots, which no regime marker uses.

Every marker is a distinct ASCII character, so the plots and their legends still
separate the regimes with colour off.

Themes: plotext's "default" theme paints a white canvas, a bright box on dark terminals.
"pro" keeps the terminal's own background and foreground and only colours the data;
"clear" colours nothing (used with colour off).
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from types import MappingProxyType

from core.regimes import DEPENDS, REGIMES

#: The label of runs without a regime yet (stored as None or "pending").
PENDING = "pending"
#: Legend order: the classifier's order, cells that depend on the initial state, then
#: runs not finished yet.
LEGEND_ORDER: tuple[str, ...] = (*REGIMES, DEPENDS, PENDING)

#: plotext themes with colour on and off (see the module docstring).
THEME_COLOR = "pro"
THEME_PLAIN = "clear"

#: The exact Hopf curve: the terminal's foreground, in braille dots.
HOPF_COLOR = "default"
HOPF_MARKER = "braille"
#: Two braille cells that look like a short line, for the legend.
HOPF_LEGEND_MARKER = "⠤⠤"
HOPF_LABEL = "Hopf (exact)"
#: The fold-of-cycles curve (core.fold_curve): the lower edge of the bistable band, in
#: plotext's small dots so it reads apart from the Hopf curve with colour off too.
FOLD_COLOR = "default"
FOLD_MARKER = "•"
FOLD_LEGEND_MARKER = "••"
FOLD_LABEL = "fold of cycles"


@dataclass(frozen=True, slots=True)
class RegimeStyle:
    """How one regime is drawn: a plotext colour name and a one-character marker."""

    color: str
    marker: str


REGIME_STYLES: Mapping[str, RegimeStyle] = MappingProxyType({
    "sliding": RegimeStyle("cyan", "."),
    "oscillatory": RegimeStyle("green", "o"),
    "complex": RegimeStyle("magenta", "*"),
    "mixed": RegimeStyle("orange", "+"),
    "unstable": RegimeStyle("red", "x"),
    DEPENDS: RegimeStyle("blue+", "#"),
    PENDING: RegimeStyle("gray", "?"),
})


def regime_key(regime: str | None) -> str:
    """The style key of a run's regime: the regime itself, or PENDING for None/"pending".

    Raises ValueError for a label the classifier never produces, rather than drawing it
    in a made-up style that the legend could not explain.
    """
    if regime is None or regime == PENDING:
        return PENDING
    if regime not in REGIMES and regime != DEPENDS:
        expected = ", ".join(LEGEND_ORDER)
        raise ValueError(f"unknown regime {regime!r}: expected one of {expected} or None")
    return regime


def regime_style(regime: str | None) -> RegimeStyle:
    """Colour and marker of a regime (None and "pending" share the pending style)."""
    return REGIME_STYLES[regime_key(regime)]


def regime_counts(regimes: Iterable[str | None]) -> dict[str, int]:
    """Runs per regime key, in LEGEND_ORDER, leaving out regimes with no runs."""
    counts = Counter(regime_key(r) for r in regimes)
    return {key: counts[key] for key in LEGEND_ORDER if counts[key]}
