"""Colour and marker of each regime (core.regimes.REGIMES) in the terminal plots, and of
the runs that have none (failed, cancelled, pending).

Colours are plotext's basic 16-colour names, so they survive 16-colour terminals, and
were picked to read on both dark and light backgrounds:

  sliding      cyan     '.'   the quiet state; usually the largest region, so the least ink
  oscillatory  green    'o'   a period-1 limit cycle: one closed orbit
  complex      magenta  '*'   period-n, quasi-periodic or chaotic
  mixed        orange   '+'   switches between quiet and oscillating stretches
  unstable     red      'x'   the run blew up: crossed out
  undetermined magenta+ '~'   the window still sits at an unstable rest state and where it
                              goes is not known (core.heading): rare, next to the Hopf
                              curve. Bright magenta, legible on both backgrounds; the
                              marker tells it from complex's magenta
  depends      blue+    '#'   not a regime: a cell whose initial conditions end in different
                              regimes (slopetui.sweeps.initial_dependence): bright blue (ANSI
                              12, legible on black where plain blue is not) and a heavy mark
  failed       default  '!'   not a regime: the worker gave up after its attempts (run status
                              "failed"). The terminal's own foreground: legible on any
                              background, as no free 16-colour name is (white or black vanish
                              on one, the bright ones sit next to a regime's colour, and red
                              would say "unstable"); an alarm mark
  cancelled    gray     '/'   not a regime: the run was cancelled before it ran (run status
                              "cancelled"). Pending's faint grey on purpose: neither is a
                              result nor the model's doing, so both recede; the marker (a
                              stroke through the cell) tells them apart
  pending      gray     '?'   not finished yet (None or "pending"; run status queued or
                              running): faint, and plotted so a live sweep shows which
                              cells are still missing

``run_key(regime, status)`` is the style key of a run: failed and cancelled by its status
(they have no regime), otherwise its regime's key (``regime_key``), a queued or running
run's None giving pending. Every drawing of a sweep's runs takes its keys from it, so a
run that failed is never drawn as one still to come.

Blue is left out: ANSI blue on a black background is barely visible in many palettes.
plotext's "orange" is ANSI colour 3, which terminals show as yellow or brown; plotext 5
has no "yellow" name (it silently draws uncoloured). The Hopf curve uses "default", the
terminal's own foreground, so it is legible on any background and differs from every
regime colour (failed runs share it: their '!' is not a curve's braille dot or '•').

Every marker is a distinct ASCII character (and none is '-', the legend's mark of a note),
so the plots and their legends still separate the keys with colour off.

Half blocks: where the application draws two lattice rows per character (``▀``, its
foreground the upper run's colour, its background the lower's: slopetui.plots.lattice_cells)
a cell has no marker, only colours, so every key needs a colour of its own there:
``BLOCK_COLORS``, in ANSI's 16 names as Rich spells them. The regimes and depends keep
their colours (undetermined takes bright magenta, a free name); failed takes bright red
(an alarm, brighter than unstable's red: the foreground's colour cannot be a background),
cancelled blue (it recedes, and differs from pending's dark grey). The overlays take what
no key has: the Hopf curve bright white, the fold of cycles bright yellow, the cursor
black (a hole in the colours). With colour off there are no half blocks: one marker per
cell, as above.

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
#: The keys of runs that will have no regime: their run status (slopetui.store.statuses).
FAILED = "failed"
CANCELLED = "cancelled"
#: Legend order: the classifier's order, cells that depend on the initial state, runs
#: that gave no result, then runs not finished yet.
LEGEND_ORDER: tuple[str, ...] = (*REGIMES, DEPENDS, FAILED, CANCELLED, PENDING)

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
    "undetermined": RegimeStyle("magenta+", "~"),
    DEPENDS: RegimeStyle("blue+", "#"),
    FAILED: RegimeStyle("default", "!"),
    CANCELLED: RegimeStyle("gray", "/"),
    PENDING: RegimeStyle("gray", "?"),
})


#: The colour of each key in a half-block cell (module docstring), Rich's ANSI names.
BLOCK_COLORS: Mapping[str, str] = MappingProxyType({
    "sliding": "cyan", "oscillatory": "green", "complex": "magenta", "mixed": "yellow",
    "unstable": "red", "undetermined": "bright_magenta", DEPENDS: "bright_blue",
    FAILED: "bright_red", CANCELLED: "blue", PENDING: "bright_black",
})
#: The overlays of a half-block drawing: the Hopf curve, the fold of cycles, the cursor.
BLOCK_HOPF = "bright_white"
BLOCK_FOLD = "bright_yellow"
BLOCK_CURSOR = "black"


def regime_key(regime: str | None) -> str:
    """The style key of a run's regime: the regime itself, or PENDING for None/"pending".

    A style key passes through as it is (DEPENDS, and run_key's FAILED and CANCELLED), so
    that the renderers take either regimes or keys. Raises ValueError for a label the
    classifier never produces, rather than drawing it in a made-up style that the legend
    could not explain.
    """
    if regime is None or regime == PENDING:
        return PENDING
    if regime not in REGIME_STYLES:
        expected = ", ".join(LEGEND_ORDER)
        raise ValueError(f"unknown regime {regime!r}: expected one of {expected} or None")
    return regime


def run_key(regime: str | None, status: str | None) -> str:
    """The style key of a run from its regime and its status (slopetui.store.statuses):
    FAILED or CANCELLED by the status, whatever the regime; otherwise ``regime_key`` of
    the regime (a done run's regime; queued and running runs have None: PENDING)."""
    if status == FAILED:
        return FAILED
    if status == CANCELLED:
        return CANCELLED
    return regime_key(regime)


def regime_style(regime: str | None) -> RegimeStyle:
    """Colour and marker of a regime (None and "pending" share the pending style)."""
    return REGIME_STYLES[regime_key(regime)]


def regime_counts(regimes: Iterable[str | None]) -> dict[str, int]:
    """Runs per regime key, in LEGEND_ORDER, leaving out regimes with no runs."""
    counts = Counter(regime_key(r) for r in regimes)
    return {key: counts[key] for key in LEGEND_ORDER if counts[key]}
