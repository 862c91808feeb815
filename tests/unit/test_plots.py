"""Terminal plots: the Hopf curve in plot coordinates, phase and bifurcation diagrams."""

from __future__ import annotations

import re

import numpy as np
import plotext as plt
import pytest

from core.params import Params
from core.regimes import DEPENDS, REGIMES
from core.stability import hopf_curve_friction, hopf_k
from slopetui.plots import (
    REGIME_STYLES,
    regime_style,
    render_bifurcation,
    render_phase_diagram,
)
from slopetui.plots.regime_colors import (
    CANCELLED,
    FAILED,
    HOPF_COLOR,
    HOPF_MARKER,
    LEGEND_ORDER,
    PENDING,
    regime_counts,
    regime_key,
    run_key,
)
from slopetui.plots.sweep_diagram import render_sweep
from slopetui.sweeps.diagram import RunPoint, SweepDiagram
from slopetui.sweeps.hopf_plane import hopf_boundary
from slopetui.sweeps.spec import parse_spec

ANSI = re.compile(r"\x1b\[[0-9;]*m")
BRAILLE = re.compile("[\u2801-\u28ff]")
BASE = Params()
F1 = BASE.F1


def plain(text: str) -> str:
    return ANSI.sub("", text)


def plot_rows(text: str) -> list[str]:
    """The rows inside the plot frame (between the y axis and the right border)."""
    rows = []
    for line in plain(text).split("\n"):
        m = re.match(r"^[ 0-9.e+-]*[┤│](.*)│$", line)
        if m:
            rows.append(m.group(1))
    return rows


def grid_sweep() -> tuple[np.ndarray, np.ndarray, list[str | None]]:
    """A (k, tau) grid labelled by the exact boundary, with every regime and a pending run."""
    k, tau = (a.ravel() for a in np.meshgrid(np.linspace(1, 30, 30), np.linspace(0.5, 20, 20)))
    regimes: list[str | None] = []
    for ki, ti in zip(k, tau, strict=True):
        kh = hopf_k(ti, F1)
        regimes.append("sliding" if ki < kh else "oscillatory" if ki < 2 * kh else "unstable")
    regimes[3], regimes[40], regimes[41], regimes[7] = "complex", "mixed", "mixed", None
    regimes[42] = "undetermined"
    return k, tau, regimes


# -- hopf_boundary -----------------------------------------------------------------------

def test_k_tau_boundary_is_k_h_of_tau():
    ks, taus = hopf_boundary(BASE, "k", "tau", (0.0, 30.0), (0.0, 20.0))
    assert len(ks) > 100
    for i in np.linspace(0, len(ks) - 1, 7).astype(int):
        assert ks[i] == pytest.approx(hopf_k(taus[i], F1), rel=1e-9)
    assert ks.min() >= 0.0 and ks.max() <= 30.0 and taus.min() >= 0.0 and taus.max() <= 20.0
    # the curve spans the window: it enters at k = 30 and leaves at tau = 20
    assert ks.max() == pytest.approx(30.0, rel=1e-3)
    assert taus.max() == pytest.approx(20.0, rel=1e-3)
    assert np.all(np.diff(taus) > 0) and np.all(np.diff(ks) < 0)


def test_swapping_the_axes_swaps_the_arrays():
    ks, taus = hopf_boundary(BASE, "k", "tau", (2.0, 25.0), (0.5, 15.0))
    taus2, ks2 = hopf_boundary(BASE, "tau", "k", (0.5, 15.0), (2.0, 25.0))
    np.testing.assert_array_equal(ks, ks2)
    np.testing.assert_array_equal(taus, taus2)
    bs, tb = hopf_boundary(Params(k=12.0), "b", "tau", (6.0, 10.0), (0.0, 20.0))
    tb2, bs2 = hopf_boundary(Params(k=12.0), "tau", "b", (0.0, 20.0), (6.0, 10.0))
    np.testing.assert_array_equal(bs, bs2)
    np.testing.assert_array_equal(tb, tb2)


def test_reversed_range_bounds_give_the_same_curve():
    a = hopf_boundary(BASE, "k", "tau", (0.0, 30.0), (0.0, 20.0))
    b = hopf_boundary(BASE, "k", "tau", (30.0, 0.0), (20.0, 0.0))
    np.testing.assert_array_equal(a[0], b[0])
    np.testing.assert_array_equal(a[1], b[1])


@pytest.mark.parametrize("name, value_range", [("a", (0.0, 20.0)), ("b", (4.0, 10.0)),
                                               ("c", (2.0, 6.0))])
def test_friction_boundary_lies_on_the_k_tau_boundary(name, value_range):
    """At each (value, tau) of the friction curve, k_H(tau) for that value is the base k."""
    p = Params(k=12.0)
    vals, taus = hopf_boundary(p, name, "tau", value_range, (0.0, 20.0))
    assert len(vals) > 20
    assert np.all((vals >= value_range[0]) & (vals <= value_range[1]))
    assert np.all((taus >= 0.0) & (taus <= 20.0))
    for i in np.linspace(0, len(vals) - 1, 5).astype(int):
        q = p.with_(**{name: float(vals[i])})
        assert hopf_k(float(taus[i]), q.F1) == pytest.approx(12.0, rel=1e-6)


def test_friction_boundary_keeps_the_core_points_inside_the_window():
    p = Params(k=12.0)
    full_b, full_tau = hopf_curve_friction(p, "b", 1600)
    bs, taus = hopf_boundary(p, "b", "tau", (6.0, 10.0), (0.0, 2.0))
    inside = (full_b >= 6.0) & (full_b <= 10.0) & (full_tau <= 2.0)
    np.testing.assert_array_equal(bs, full_b[inside])
    np.testing.assert_array_equal(taus, full_tau[inside])


@pytest.mark.parametrize("x, y", [("d", "tau"), ("tau", "v"), ("delta", "tau"), ("k", "b"),
                                  ("a", "c"), ("tau", "tau")])
def test_planes_without_a_hopf_curve_give_none(x, y):
    assert hopf_boundary(BASE, x, y, (0.1, 10.0), (0.1, 10.0)) is None


def test_undefined_curves_give_none():
    unstable = Params(v=0.8)                     # F'(v) = -0.576: no damped sliding state
    assert unstable.F1 < 0
    assert hopf_boundary(unstable, "k", "tau", (0.0, 30.0), (0.0, 20.0)) is None
    assert hopf_boundary(unstable, "tau", "k", (0.0, 20.0), (0.0, 30.0)) is None
    assert hopf_boundary(Params(k=0.0), "a", "tau", (0.0, 30.0), (0.0, 20.0)) is None


def test_curve_outside_the_window_is_empty_not_none():
    # k_H >= F'^2 / 2 = 5.97 for every tau: a window below it holds no part of the curve
    ks, taus = hopf_boundary(BASE, "k", "tau", (0.0, 5.0), (0.0, 20.0))
    assert ks.size == 0 and taus.size == 0
    ks, taus = hopf_boundary(BASE, "k", "tau", (0.0, 30.0), (0.0, 0.0))
    assert ks.size == 0


# -- styles -------------------------------------------------------------------------------

def test_every_regime_has_a_distinct_16_colour_style():
    regimes = (*REGIMES, DEPENDS, PENDING)
    keys = (*regimes, FAILED, CANCELLED)
    assert set(REGIME_STYLES) == set(keys) == set(LEGEND_ORDER)
    # markers alone tell every key apart (colour off), and none is a legend note's "-"
    assert len({REGIME_STYLES[k].marker for k in keys}) == len(keys)
    assert "-" not in {REGIME_STYLES[k].marker for k in keys}
    assert len({REGIME_STYLES[k].color for k in regimes}) == len(regimes)
    # the two without a result share a colour on purpose (regime_colors): failed the
    # terminal's foreground, cancelled pending's grey
    assert REGIME_STYLES[FAILED].color == "default"
    assert REGIME_STYLES[FAILED].color not in {REGIME_STYLES[k].color for k in regimes}
    assert REGIME_STYLES[CANCELLED].color == REGIME_STYLES[PENDING].color
    for k in keys:
        style = REGIME_STYLES[k]
        assert len(style.marker) == 1 and style.marker.isascii()
        if style.color == "default":  # no escape: the terminal's own colour
            assert plt.colorize("x", style.color) == "x"
            continue
        # plotext silently ignores colour names it does not know (e.g. "yellow")
        code = re.fullmatch(r"\x1b\[38;5;(\d+)mx\x1b\[0m", plt.colorize("x", style.color))
        assert code is not None and int(code.group(1)) < 16, style.color
    assert HOPF_COLOR not in {REGIME_STYLES[k].color for k in regimes}
    assert HOPF_MARKER == "braille"


def test_regime_style_of_unfinished_runs_and_unknown_labels():
    assert regime_style(None) == regime_style("pending") == REGIME_STYLES[PENDING]
    with pytest.raises(ValueError, match="unknown regime"):
        regime_style("chaotic")


def test_run_key_draws_failed_and_cancelled_runs_as_such():
    assert run_key(None, "failed") == FAILED and run_key(None, "cancelled") == CANCELLED
    assert run_key("sliding", "failed") == FAILED  # the status wins over a stale regime
    assert run_key(None, "queued") == run_key(None, "running") == run_key(None, None) == PENDING
    assert run_key("oscillatory", "done") == "oscillatory"
    assert regime_key(FAILED) == FAILED  # keys pass through: the renderers take either
    assert list(LEGEND_ORDER[-3:]) == [FAILED, CANCELLED, PENDING]
    assert LEGEND_ORDER.index(DEPENDS) < LEGEND_ORDER.index(FAILED)
    assert regime_counts([None, "failed", "sliding", "cancelled", "failed"]) == {
        "sliding": 1, FAILED: 2, CANCELLED: 1, PENDING: 1}
    with pytest.raises(ValueError, match="unknown regime"):
        run_key("chaotic", "done")


# -- render_phase_diagram -----------------------------------------------------------------

@pytest.mark.parametrize("width, height", [(80, 24), (60, 18), (120, 40)])
@pytest.mark.parametrize("color", [True, False])
def test_phase_diagram_fits_and_names_everything(width, height, color):
    k, tau, regimes = grid_sweep()
    hopf = hopf_boundary(BASE, "k", "tau", (1.0, 30.0), (0.5, 20.0))
    out = render_phase_diagram("k", "tau", k, tau, regimes, hopf=hopf, title="defaults",
                               width=width, height=height, color=color)
    lines = out.split("\n")
    assert len(lines) == height
    assert all(len(plain(line)) <= width for line in lines)
    assert ("\x1b" in out) == color
    text = plain(out)
    counts = {r: regimes.count(r) for r in REGIMES}
    for regime, n in counts.items():
        assert f"{regime} ({n})" in text
    assert "pending (1)" in text and "Hopf (exact)" in text and "defaults" in text
    assert re.search(r"^τ\s+k\s*$", text, re.MULTILINE)      # y label bottom left, x label centred


def test_phase_diagram_without_colour_keeps_regimes_apart_by_marker():
    k, tau, regimes = grid_sweep()
    hopf = hopf_boundary(BASE, "k", "tau", (1.0, 30.0), (0.5, 20.0))
    out = render_phase_diagram("k", "tau", k, tau, regimes, hopf=hopf, color=False)
    body = "".join(plot_rows(out))
    for regime in set(regimes):
        assert regime_style(regime).marker in body, regime
    assert BRAILLE.search(body)                          # the Hopf line
    for regime in REGIMES:                               # the legend shows each marker
        assert f"{REGIME_STYLES[regime].marker} {regime} (" in out


def test_phase_diagram_colours_each_regime():
    out = render_phase_diagram("k", "tau", [1.0, 2.0], [1.0, 2.0], ["oscillatory", "unstable"])
    assert "\x1b[38;5;2mo" in out                        # green o
    assert "\x1b[38;5;1mx" in out                        # red x


def test_marker_lands_where_the_run_is():
    out = render_phase_diagram("k", "tau", [0.0, 10.0, 10.0], [0.0, 0.0, 5.0],
                               ["sliding", "unstable", "oscillatory"], color=False)
    rows = plot_rows(out)
    assert rows[0].rstrip().endswith("o")                # top right: (10, 5)
    assert rows[-1].startswith(".") and rows[-1].rstrip().endswith("x")


def test_rare_regimes_are_drawn_over_common_ones():
    # two runs in the same spot: the rarer regime must be the one shown
    xs, ys = [1.0, 1.0, 1.0, 2.0], [1.0, 1.0, 1.0, 2.0]
    out = render_phase_diagram("k", "tau", xs, ys, ["mixed", "sliding", "sliding", "sliding"],
                               color=False)
    rows = plot_rows(out)
    assert rows[-1].startswith("+")


def test_log_axis_spaces_decades_evenly():
    xs = [1.0, 10.0, 100.0, 1000.0]
    ys = [1.0, 1.0, 1.0, 1.0]
    regimes = ["sliding", "oscillatory", "complex", "unstable"]
    out = render_phase_diagram("k", "tau", xs, ys, regimes, x_log=True, color=False)
    row = next(r for r in plot_rows(out) if "x" in r)
    cols = [row.index(REGIME_STYLES[r].marker) for r in regimes]
    gaps = np.diff(cols)
    assert gaps.max() - gaps.min() <= 1
    linear = next(r for r in plot_rows(render_phase_diagram("k", "tau", xs, ys, regimes,
                                                            color=False)) if "x" in r)
    assert linear.index("o") - linear.index(".") < 3    # 1 and 10 nearly coincide


def test_log_axis_counts_the_runs_it_cannot_show():
    out = render_phase_diagram("k", "tau", [0.0, 1.0, 10.0], [1.0, 2.0, 3.0],
                               ["sliding"] * 3, x_log=True, color=False)
    assert "sliding (3)" in out
    assert "1 not shown (<= 0 on a log axis" in out
    assert "".join(plot_rows(out)).count(".") == 2


def test_log_axes_with_the_hopf_curve():
    k, tau, regimes = grid_sweep()
    hopf = hopf_boundary(BASE, "k", "tau", (1.0, 30.0), (0.5, 20.0))
    out = render_phase_diagram("k", "tau", k, tau, regimes, hopf=hopf, x_log=True, y_log=True,
                               color=False)
    assert len(out.split("\n")) == 24
    assert BRAILLE.search("".join(plot_rows(out)))


@pytest.mark.parametrize("color", [True, False])
def test_empty_phase_diagram_is_a_message(color):
    out = render_phase_diagram("k", "tau", [], [], [], title="sweep 3", color=color)
    assert "no runs" in out and "sweep 3" in out and "(k, tau)" in out
    assert len(out.split("\n")) == 24


def test_only_unplottable_runs_is_a_message():
    out = render_phase_diagram("k", "tau", [0.0, -1.0], [1.0, 2.0], ["sliding", None],
                               x_log=True)
    assert "2 runs, none plottable" in out


def test_pending_runs_show_as_faint_question_marks():
    out = render_phase_diagram("k", "tau", [1.0, 2.0, 3.0], [1.0, 2.0, 3.0],
                               [None, "pending", "sliding"])
    assert "pending (2)" in plain(out)
    assert "\x1b[38;5;8m?" in out                        # gray


def test_bad_inputs_raise():
    with pytest.raises(ValueError, match="differ in length"):
        render_phase_diagram("k", "tau", [1.0], [1.0, 2.0], ["sliding"])
    with pytest.raises(ValueError, match="unknown regime"):
        render_phase_diagram("k", "tau", [1.0], [1.0], ["wobbly"])
    with pytest.raises(ValueError, match="too small"):
        render_phase_diagram("k", "tau", [1.0], [1.0], ["sliding"], width=20, height=24)
    with pytest.raises(ValueError, match="too small"):
        render_phase_diagram("k", "tau", [1.0], [1.0], ["sliding"], width=80, height=8)


def test_long_title_is_cut_not_dropped():
    out = render_phase_diagram("k", "tau", [1.0], [1.0], ["sliding"], title="T" * 200,
                               width=60, height=20, color=False)
    first = out.split("\n")[0]
    assert first.startswith("T" * 10) and first.endswith("…") and len(first) == 60


def test_legend_wraps_within_a_narrow_width():
    k, tau, regimes = grid_sweep()
    out = render_phase_diagram("k", "tau", k, tau, regimes, width=40, height=24, color=False)
    lines = out.split("\n")
    assert len(lines) == 24 and all(len(line) <= 40 for line in lines)
    for regime in REGIMES:
        assert f"{regime} (" in out


def test_greek_labels_for_tau_and_delta():
    out = render_phase_diagram("delta", "tau", [0.1, 0.2], [1.0, 2.0], ["sliding"] * 2,
                               color=False)
    assert re.search(r"^τ\s+δ\s*$", out, re.MULTILINE)


def test_plotext_state_left_by_others_does_not_leak_in():
    args = ("k", "tau", [1.0, 2.0], [1.0, 2.0], ["sliding", "oscillatory"])
    clean = render_phase_diagram(*args)
    plt.clear_figure()
    plt.subplots(1, 2)
    plt.subplot(1, 2)
    plt.scatter([5, 6], [7, 8], label="junk")
    plt.title("junk title")
    plt.theme("matrix")
    plt.plotsize(30, 10)
    try:
        assert render_phase_diagram(*args) == clean
    finally:
        plt.main()
        plt.clear_figure()


# -- render_bifurcation -------------------------------------------------------------------

def bifurcation_sweep() -> tuple[np.ndarray, list[list[float]], list[str | None]]:
    """Fig. 4A in miniature: at rest, period 1, period 2, a continuum, blow-up; one pending."""
    values = np.linspace(5.0, 30.0, 26)
    runs: list[tuple[list[float], str | None]] = []
    for v in values:
        if v < 8:
            runs.append(([], "sliding"))
        elif v < 18:
            runs.append(([0.3 * (v - 8) ** 0.5], "oscillatory"))
        elif v < 22:
            runs.append(([1.0 + 0.1 * (v - 18), 2.0], "complex"))
        elif v < 29:
            runs.append((list(np.linspace(0.5, 3.0, 12)), "complex"))
        else:
            runs.append(([], "unstable"))
    runs[-3] = ([], None)
    return values, [p for p, _ in runs], [r for _, r in runs]


@pytest.mark.parametrize("color", [True, False])
def test_bifurcation_fits_and_counts_runs_without_peaks(color):
    values, peaks, regimes = bifurcation_sweep()
    out = render_bifurcation("k", values, peaks, regimes, title="tau = 10", color=color)
    lines = out.split("\n")
    assert len(lines) == 24 and all(len(plain(line)) <= 80 for line in lines)
    assert ("\x1b" in out) == color
    text = plain(out)
    for regime in set(regimes):
        key = regime or "pending"
        assert f"{key} ({regimes.count(regime)})" in text
    assert "m_y peaks" in text and "tau = 10" in text
    body = "".join(plot_rows(out))
    assert "." not in body and "x" not in body            # sliding, unstable: no peaks
    assert body.count("o") == 10


def test_each_peak_is_a_point_in_the_run_column():
    out = render_bifurcation("k", [1.0, 2.0], [[1.0, 2.0, 3.0], [1.0]],
                             ["complex", "oscillatory"], color=False)
    rows = plot_rows(out)
    cols = {r.index("*") for r in rows if "*" in r}
    assert len(cols) == 1 and sum(r.count("*") for r in rows) == 3
    assert rows[-1].rstrip().endswith("o")


def test_bifurcation_log_axis_and_bad_values():
    out = render_bifurcation("tau", [0.0, 0.1, 1.0, 10.0], [[1.0], [1.0, np.nan], [2.0], [3.0]],
                             ["oscillatory"] * 4, log=True, color=False)
    assert "oscillatory (4)" in out
    assert "".join(plot_rows(out)).count("o") == 3
    assert re.search(r"^m_y peaks\s+τ\s*$", out, re.MULTILINE)


def test_empty_bifurcation_is_a_message():
    assert "no runs" in render_bifurcation("k", [], [], [])
    out = render_bifurcation("k", [1.0, 2.0], [[], []], ["sliding", "unstable"], height=12)
    assert "2 runs, no peaks to plot" in out and len(out.split("\n")) == 12
    with pytest.raises(ValueError, match="differ in length"):
        render_bifurcation("k", [1.0], [], ["sliding"])


# -- render_sweep: runs without a result ----------------------------------------------------

def _plane_with_failures() -> SweepDiagram:
    """A 4 x 3 (k, tau) sweep: done runs, one failed, one cancelled, one still queued."""
    spec = parse_spec({"x": {"param": "k", "start": 2, "stop": 20, "num": 4},
                       "y": {"param": "tau", "start": 1, "stop": 10, "num": 3}})
    assert spec.y is not None
    status = {(1, 1): "failed", (2, 0): "cancelled", (3, 2): "queued"}
    runs = []
    for iy, y in enumerate(spec.y.values()):
        for ix, x in enumerate(spec.x.values()):
            s = status.get((ix, iy), "done")
            runs.append(RunPoint(1 + ix + 4 * iy, ix, iy, float(x), float(y), s,
                                 ("sliding" if ix < 2 else "oscillatory") if s == "done" else None,
                                 [], "gave up" if s == "failed" else None))
    return SweepDiagram(7, "with failures", spec, runs)


def test_a_sweep_draws_failed_and_cancelled_runs_as_such_not_pending():
    out = render_sweep(_plane_with_failures(), width=80, height=24, color=False, hopf=False)
    assert "\x1b" not in out
    text = plain(out)
    # the legend: each in LEGEND_ORDER, after the regimes, before pending
    legend = [". sliding (5)", "o oscillatory (4)", "! failed (1)", "/ cancelled (1)",
              "? pending (1)"]
    at = [text.index(entry) for entry in legend]
    assert at == sorted(at)
    body = "".join(plot_rows(out))
    for marker in "!/?":  # with colour off the markers alone tell them apart
        assert body.count(marker) == 1, marker
    assert "(9/12 done)" in text  # the title: a failed or cancelled run is not done
    coloured = render_sweep(_plane_with_failures(), width=80, height=24, color=True, hopf=False)
    assert "\x1b[38;5;8m/" in coloured and "\x1b[38;5;8m?" in coloured  # both grey


def test_a_1d_sweep_counts_failed_and_cancelled_runs_in_its_legend():
    spec = parse_spec({"x": {"param": "k", "start": 2, "stop": 20, "num": 4}})
    runs = [RunPoint(1, 0, 0, 2.0, None, "done", "oscillatory", [0.5], None),
            RunPoint(2, 1, 0, 8.0, None, "failed", None, [], "gave up"),
            RunPoint(3, 2, 0, 14.0, None, "cancelled", None, [], None),
            RunPoint(4, 3, 0, 20.0, None, "running", None, [], None)]
    out = plain(render_sweep(SweepDiagram(8, "line", spec, runs), width=80, height=24,
                             color=False))
    for entry in ("o oscillatory (1)", "! failed (1)", "/ cancelled (1)", "? pending (1)"):
        assert entry in out, entry
