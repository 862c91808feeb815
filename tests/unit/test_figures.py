"""Publication figures (slopetui.figures): each kind rendered to PNG, PDF and SVG, the
data beside it, reproducible files, and output paths refused before anything is written.

No integration: diagrams are built from RunPoints and runs from synthetic traces (a
sine), so nothing compiles; the whole module takes a few seconds.
"""

from __future__ import annotations

import csv
import math
import os
import re
import subprocess
import sys
from dataclasses import fields, replace
from pathlib import Path
from typing import Any

import matplotlib
import numpy as np
import pytest
from matplotlib.figure import Figure
from matplotlib.image import imread

from core.classify import Summary, power_spectrum
from core.lyapunov import LyapunovEstimate
from core.params import PARAM_NAMES
from core.result_fields import RESULT_FIELDS
from slopetui.figures import (
    COMPARE_SIZE,
    DIAGRAM_SIZE,
    PNG_DPI,
    RUN_SIZE,
    Drawing,
    FigureError,
    Table,
    check_output,
    data_paths,
    run_drawing,
    sweep_drawing,
    write,
)
from slopetui.figures import output as figure_output
from slopetui.figures.labels import MEANINGS, axis_label
from slopetui.figures.lattice import cell_edges
from slopetui.figures.run_figure import MAX_TABLE_ROWS, RASTER_LINE_POINTS
from slopetui.figures.style import REGIME_COLORS
from slopetui.figures.sweep_figure import RASTER_POINTS
from slopetui.plots.regime_colors import LEGEND_ORDER, regime_key
from slopetui.plots.sweep_diagram import adaptive_notes
from slopetui.sweeps.diagram import RunPoint, SweepDiagram
from slopetui.sweeps.export import cell
from slopetui.sweeps.recompute import StoredRun, Traces
from slopetui.sweeps.spec import parse_spec

# -- builders -------------------------------------------------------------------------------


def _plane(nx: int, ny: int, *, log: bool = False, **extra: Any) -> dict[str, Any]:
    spacing = "log" if log else "linear"
    return {"name": "plane", "x": {"param": "k", "start": 3, "stop": 24, "num": nx, "spacing": spacing},
            "y": {"param": "tau", "start": 0.5, "stop": 10, "num": ny, "spacing": spacing}, **extra}


def plane_regime(k: float, tau: float) -> str:
    """Sliding below a Hopf-like curve, oscillatory above it, complex at large k."""
    if k < math.pi ** 2 / (2 * tau * tau) + 1.0:
        return "sliding"
    return "oscillatory" if k < 15 else "complex"


def phase_diagram(nx: int = 12, ny: int = 9, *, log: bool = False, skip: frozenset = frozenset(),
                  **extra: Any) -> SweepDiagram:
    """A 2-D sweep with every lattice point run except ``skip``; the top-left run pending,
    the bottom-right one unstable, sliding runs without lambda_max (NaN)."""
    spec = parse_spec(_plane(nx, ny, log=log, **extra))
    runs = []
    for iy, y in enumerate(spec.y.values()):
        for ix, x in enumerate(spec.x.values()):
            if (ix, iy) in skip:
                continue
            regime: str | None = plane_regime(x, y)
            if (ix, iy) == (nx - 1, 0):
                regime = "unstable"
            if (ix, iy) == (0, ny - 1):
                regime = None
            lam = math.nan if regime == "sliding" else 0.01 * ix
            runs.append(RunPoint(1 + ix + nx * iy, ix, iy, float(x), float(y),
                                 "done" if regime else "queued", regime, [], None, lambda_max=lam))
    return SweepDiagram(7, "plane", spec, runs)


def bifurcation(n: int = 60, peaks_per_complex: int = 5, *, log: bool = False) -> SweepDiagram:
    """A 1-D sweep in k: sliding (one mean each), oscillatory (one peak), complex (several),
    the last run pending."""
    spec = parse_spec({"name": "Fig. 4A", "x": {"param": "k", "start": 3, "stop": 24, "num": n,
                                                "spacing": "log" if log else "linear"}})
    rng = np.random.default_rng(1)
    runs = []
    for i, x in enumerate(spec.x.values()):
        x = float(x)
        if i == n - 1:
            runs.append(RunPoint(i + 1, i, 0, x, None, "queued", None, [], None))
        elif x < 6:
            runs.append(RunPoint(i + 1, i, 0, x, None, "done", "sliding", [1e-4], None))
        elif x < 15:
            runs.append(RunPoint(i + 1, i, 0, x, None, "done", "oscillatory", [0.1 * math.sqrt(x - 6)], None))
        else:
            runs.append(RunPoint(i + 1, i, 0, x, None, "done", "complex",
                                 list(0.3 + 0.2 * rng.random(peaks_per_complex)), None))
    return SweepDiagram(3, spec.name, spec, runs)


_RESULT_DEFAULTS = {"text": "", "measure": math.nan, "count": None, "list": None, "optional": None, "flag": None,
                    "pairs": None}


def stored_run(run_id: int, **changes: Any) -> StoredRun:
    """A done run (oscillatory, lambda_max 0.001) with every field StoredRun has."""
    values: dict[str, Any] = {f.name: _RESULT_DEFAULTS[f.kind] for f in RESULT_FIELDS}
    values.update(id=run_id, sweep_id=1, status="done", a=3.2, b=7.2, c=4.8, d=1e-4, k=12.0, v=0.1,
                  tau=2.0, delta=0.1, method="rk4", dt=0.01, t_end=200.0, window=100.0, lyap=True,
                  engine="test", worker_id=None, attempts=1, error=None, cached_from=None,
                  inferred=False, level=None, history="constant", stop="t_end", ic=0, carried=None,
                  regime="oscillatory", lambda_max=0.001, lambda_err=0.0005)
    values.update(changes)
    assert set(values) == {f.name for f in fields(StoredRun)}
    return StoredRun(**values)


def sine_traces(n: int = 10_001, f: float = 0.2, amp: float = 1.0) -> Traces:
    """A cycle of frequency f over the window t = 100..200 (m_x a ramp of slope 0.1 with
    the oscillation on it), and a running lambda converging on 0."""
    t = np.linspace(100.0, 200.0, n)
    m_y = 0.1 + amp * np.sin(2 * np.pi * f * t)
    m_x = 0.1 * t - amp / (2 * np.pi * f) * np.cos(2 * np.pi * f * t)
    freq, power = power_spectrum(t, m_y)
    lam_t = np.linspace(0.0, 200.0, 2001)
    lam = np.sin(lam_t) / (1.0 + lam_t)
    return Traces(t, m_x, m_y, freq, power, lam_t, lam, Summary("oscillatory", "", 2 * amp, 1 / f, 1, frequency=f),
                  LyapunovEstimate(0.0008, 0.0009, 100.0, 10), "rk4 map at dt = 0.01")


# -- reading what was written -----------------------------------------------------------------


def png_pixels(path: Path, size: tuple[float, float]) -> np.ndarray:
    """The PNG as RGB bytes, after checking it has exactly size x PNG_DPI pixels."""
    image = imread(path)
    assert image.shape[:2] == (round(size[1] * PNG_DPI), round(size[0] * PNG_DPI))
    return np.round(image[..., :3] * 255).astype(np.uint8)


def axes_colors(pixels: np.ndarray, figure: Figure, index: int = 0) -> set[str]:
    """The distinct colours (hex) inside an axes' frame (its position after layout),
    a few pixels in from the spines."""
    box = figure.axes[index].get_position()
    h, w = pixels.shape[:2]
    rows = slice(round((1 - box.y1) * h) + 3, round((1 - box.y0) * h) - 3)
    cols = slice(round(box.x0 * w) + 3, round(box.x1 * w) - 3)
    region = pixels[rows, cols].reshape(-1, 3).astype(np.uint32)
    packed = np.unique((region[:, 0] << 16) | (region[:, 1] << 8) | region[:, 2])
    return {f"#{int(p):06X}" for p in packed}


def legend_texts(figure: Figure) -> list[str]:
    return [t.get_text() for legend in figure.legends for t in legend.get_texts()]


def read_csv(path: Path) -> list[list[str]]:
    with path.open(newline="") as f:
        return list(csv.reader(f))


# -- phase diagrams ---------------------------------------------------------------------------


def test_phase_diagram_png_has_a_cell_colour_per_regime_and_counts(tmp_path: Path) -> None:
    diagram = phase_diagram()
    drawing = sweep_drawing(diagram, hopf=None)
    written = write(drawing, tmp_path / "phase.png")
    assert written == [tmp_path / "phase.png", tmp_path / "phase.csv"]
    colors = axes_colors(png_pixels(written[0], DIAGRAM_SIZE), drawing.figure)
    present = {regime_key(r.regime) for r in diagram.runs}
    assert present == {"sliding", "oscillatory", "complex", "unstable", "pending"}
    assert {REGIME_COLORS[k] for k in present} <= colors
    counts = {k: sum(regime_key(r.regime) == k for r in diagram.runs) for k in present}
    assert legend_texts(drawing.figure) == [f"{k} ({counts[k]:,})" for k in LEGEND_ORDER if k in present]
    # the axes' title: the legend right of it runs up to the top (figures.canvas.set_title)
    assert drawing.figure.axes[0].get_title() == "sweep 7: plane" and not drawing.figure.get_suptitle()
    ax = drawing.figure.axes[0]
    assert ax.get_xlabel() == "k, spring stiffness"
    assert ax.get_ylabel() == "τ, delay (model time units)"


def test_log_spaced_phase_diagram_draws_log_axes_and_geometric_cells(tmp_path: Path) -> None:
    diagram = phase_diagram(log=True)
    drawing = sweep_drawing(diagram, hopf=None)
    colors = axes_colors(png_pixels(write(drawing, tmp_path / "log.png")[0], DIAGRAM_SIZE), drawing.figure)
    assert len({REGIME_COLORS[k] for k in ("sliding", "oscillatory", "complex")} & colors) == 3
    ax = drawing.figure.axes[0]
    assert (ax.get_xscale(), ax.get_yscale()) == ("log", "log")
    xs = diagram.spec.x.values()
    edges = cell_edges(xs, log=True)
    # the axis spans exactly the cells: half a (geometric) step beyond the end points
    assert ax.get_xlim() == pytest.approx((edges[0], edges[-1]))
    assert edges[1] == pytest.approx(math.sqrt(xs[0] * xs[1]))
    assert edges[0] == pytest.approx(xs[0] ** 2 / edges[1])


def test_cell_edges_are_midpoints_and_single_points_get_a_cell() -> None:
    assert cell_edges(np.array([1.0, 2.0, 4.0]), log=False) == pytest.approx([0.5, 1.5, 3.0, 5.0])
    assert cell_edges(np.array([1.0, 4.0]), log=True) == pytest.approx([0.5, 2.0, 8.0])
    assert cell_edges(np.array([10.0, 0.0]), log=False) == pytest.approx([15.0, 5.0, -5.0])
    lo, hi = cell_edges(np.array([2.0]), log=False)
    assert lo < 2.0 < hi
    lo, hi = cell_edges(np.array([0.0]), log=False)
    assert lo < 0.0 < hi
    with pytest.raises(ValueError, match="> 0"):
        cell_edges(np.array([0.0, 1.0]), log=True)


def test_phase_diagram_draws_hopf_solid_and_fold_dashed_with_their_samples(tmp_path: Path) -> None:
    diagram = phase_diagram()
    taus = np.linspace(0.6, 9.5, 50)
    hopf = (math.pi ** 2 / (2 * taus ** 2) + 1.0, taus)
    fold = (hopf[0] * 0.8, taus)
    drawing = sweep_drawing(diagram, hopf=hopf, fold=fold)
    written = write(drawing, tmp_path / "curves.png")
    assert written == [tmp_path / "curves.png", tmp_path / "curves.csv", tmp_path / "curves.curves.csv"]
    colors = axes_colors(png_pixels(written[0], DIAGRAM_SIZE), drawing.figure)
    assert "#000000" in colors  # the curves are black over the cells
    lines = {line.get_label(): line for line in drawing.figure.axes[0].get_lines()}
    assert lines["Hopf (exact)"].get_linestyle() == "-"
    assert lines["fold of cycles"].get_linestyle() == "--"
    assert legend_texts(drawing.figure)[-2:] == ["Hopf (exact)", "fold of cycles"]
    rows = read_csv(written[2])
    assert rows[0] == ["curve", "k", "tau"]
    assert [r[0] for r in rows[1:]] == ["hopf"] * 50 + ["fold"] * 50
    assert float(rows[1][1]) == pytest.approx(hopf[0][0]) and float(rows[51][2]) == pytest.approx(taus[0])


def test_a_curve_outside_the_plane_is_not_in_the_legend() -> None:
    drawing = sweep_drawing(phase_diagram(), hopf=(np.array([100.0, 200.0]), np.array([1.0, 2.0])))
    assert "Hopf (exact)" not in legend_texts(drawing.figure)
    assert [t.name for t in drawing.tables] == ["points", "curves"]  # its samples are data still


def test_phase_table_has_a_row_per_cell_nan_and_empty_cells(tmp_path: Path) -> None:
    diagram = phase_diagram(5, 4)
    written = write(sweep_drawing(diagram, hopf=None), tmp_path / "p.pdf")
    rows = read_csv(written[1])
    assert rows[0] == ["run_id", "ix", "iy", "k", "tau", "regime", "status", "lambda_max",
                       "inferred"]
    assert len(rows) == 1 + 5 * 4
    by_cell = {(int(r[1]), int(r[2])): r for r in rows[1:]}
    sliding = next(r for r in rows[1:] if r[5] == "sliding")
    assert sliding[6:8] == ["done", "nan"]  # measured, undefined
    # not finished: no regime, nothing measured, and the status says why
    assert by_cell[(0, 3)][5:] == ["", "queued", "", "False"]
    assert by_cell[(3, 2)][7] == "0.03"
    assert float(by_cell[(3, 2)][3]) == pytest.approx(diagram.spec.x.values()[3])


def test_adaptive_diagram_draws_unqueued_points_as_pending_and_says_what_was_computed(tmp_path: Path) -> None:
    missing = frozenset({(1, 1), (2, 1), (1, 2)})
    diagram = phase_diagram(5, 5, skip=missing, adaptive={"levels": 1})
    runs = [RunPoint(**{**{f.name: getattr(r, f.name) for f in fields(r)}, "inferred": r.ix == 3})
            for r in diagram.runs]
    diagram = SweepDiagram(diagram.id, diagram.name, diagram.spec, runs)
    drawing = sweep_drawing(diagram, hopf=None)
    texts = legend_texts(drawing.figure)
    assert f"pending ({len(missing) + 1})" in texts
    note = texts[-1].replace("\n", " ")
    assert note == adaptive_notes(diagram)[0] == "16 computed, 5 inferred (adaptive, 1 levels)"
    rows = read_csv(write(drawing, tmp_path / "a.svg")[1])
    unqueued = [r for r in rows[1:] if r[0] == ""]
    assert {(int(r[1]), int(r[2])) for r in unqueued} == missing
    assert {r[8] for r in rows[1:] if r[1] == "3"} == {"True"}
    assert {(r[5], r[6]) for r in unqueued} == {("", "")}  # no run: no regime, no status


def test_several_initial_conditions_draw_the_cells_that_depend(tmp_path: Path) -> None:
    spec = parse_spec(_plane(4, 3, initial=[{"delta": 1e-6}, {"delta": 0.1}]))
    runs = []
    for ic in (0, 1):
        for iy, y in enumerate(spec.y.values()):
            for ix, x in enumerate(spec.x.values()):
                regime = "sliding" if ix < 2 else "oscillatory"
                if ic == 1 and ix == 1:
                    regime = "oscillatory"  # the larger offset reaches the cycle
                runs.append(RunPoint(100 * ic + 4 * iy + ix, ix, iy, float(x), float(y), "done",
                                     regime, [], None, ic=ic))
    drawing = sweep_drawing(SweepDiagram(1, "two", spec, runs), hopf=None)
    assert legend_texts(drawing.figure) == ["sliding (3)", "oscillatory (6)", "depends (3)"]
    colors = axes_colors(png_pixels(write(drawing, tmp_path / "d.png")[0], DIAGRAM_SIZE), drawing.figure)
    assert REGIME_COLORS["depends"] in colors
    assert len(drawing.tables[0].rows) == 12  # one row a cell, not a run


def with_status(diagram: SweepDiagram, status: dict[tuple[int, int], str]) -> SweepDiagram:
    """The diagram with the runs at these (ix, iy) given a status without a regime."""
    runs = [replace(r, status=status[(r.ix, r.iy)], regime=None) if (r.ix, r.iy) in status else r
            for r in diagram.runs]
    return SweepDiagram(diagram.id, diagram.name, diagram.spec, runs)


def test_failed_and_cancelled_runs_are_cells_of_their_own_not_pending(tmp_path: Path) -> None:
    diagram = with_status(phase_diagram(5, 4), {(2, 1): "failed", (3, 1): "failed",
                                                 (1, 2): "cancelled"})
    drawing = sweep_drawing(diagram, hopf=None)
    texts = legend_texts(drawing.figure)
    assert texts[-3:] == ["failed (2)", "cancelled (1)", "pending (1)"]  # LEGEND_ORDER
    written = write(drawing, tmp_path / "f.png")
    colors = axes_colors(png_pixels(written[0], DIAGRAM_SIZE), drawing.figure)
    assert {REGIME_COLORS["failed"], REGIME_COLORS["cancelled"], REGIME_COLORS["pending"]} <= colors
    # the failed run's cell has the failed colour: its centre, as a fraction of the figure
    figure = drawing.figure
    pixels = png_pixels(written[0], DIAGRAM_SIZE)
    centre = figure.axes[0].transData.transform((diagram.spec.x.values()[2],
                                                 diagram.spec.y.values()[1]))
    fx, fy = figure.transFigure.inverted().transform(centre)
    h, w = pixels.shape[:2]
    r, g, b = pixels[round((1 - fy) * h), round(fx * w)]
    assert f"#{r:02X}{g:02X}{b:02X}" == REGIME_COLORS["failed"]
    rows = read_csv(written[1])
    by_cell = {(int(r[1]), int(r[2])): r for r in rows[1:]}
    assert by_cell[(2, 1)][5:7] == ["", "failed"] and by_cell[(1, 2)][5:7] == ["", "cancelled"]
    assert by_cell[(2, 1)][7] == ""  # nothing measured


def test_the_bifurcation_legend_counts_failed_and_cancelled_runs() -> None:
    diagram = bifurcation(10)
    runs = [replace(r, status="failed", regime=None, peaks=[]) if r.ix in (2, 5) else
            replace(r, status="cancelled", regime=None, peaks=[]) if r.ix == 7 else r
            for r in diagram.runs]
    drawing = sweep_drawing(SweepDiagram(3, "line", diagram.spec, runs), hopf=None)
    assert legend_texts(drawing.figure)[-3:] == ["failed (2)", "cancelled (1)", "pending (1)"]


@pytest.mark.slow  # over 0.5 s: out of the fast loop, still in CI
def test_a_large_phase_diagram_is_rasterised_into_a_small_pdf(tmp_path: Path) -> None:
    drawing = sweep_drawing(phase_diagram(100, 100), hopf=None)
    written = write(drawing, tmp_path / "big.pdf")
    assert all(c.get_rasterized() for c in drawing.figure.axes[0].collections)
    # measured: 20 kB rasterised, 129 kB with every cell a vector path
    assert written[0].stat().st_size < 60_000
    rows = read_csv(written[1])
    assert len(rows) == 1 + 100 * 100


# -- bifurcation diagrams ---------------------------------------------------------------------


def test_bifurcation_png_colours_peaks_by_regime_with_a_row_per_peak(tmp_path: Path) -> None:
    diagram = bifurcation()
    drawing = sweep_drawing(diagram, hopf=None)
    written = write(drawing, tmp_path / "bif.png")
    colors = axes_colors(png_pixels(written[0], DIAGRAM_SIZE), drawing.figure)
    assert {REGIME_COLORS[k] for k in ("sliding", "oscillatory", "complex")} <= colors
    counts = {k: sum(regime_key(r.regime) == k for r in diagram.runs) for k in LEGEND_ORDER}
    assert legend_texts(drawing.figure) == [f"{k} ({n})" for k, n in counts.items() if n]
    assert "pending (1)" in legend_texts(drawing.figure)
    ax = drawing.figure.axes[0]
    assert ax.get_ylabel() == "peaks of $m_y$" and ax.get_xscale() == "linear"
    rows = read_csv(written[1])
    assert rows[0] == ["run_id", "k", "peak_m_y", "regime"]
    assert len(rows) - 1 == sum(len(r.peaks) for r in diagram.runs)
    assert rows[1][2:] == ["0.0001", "sliding"]
    assert not any(c.get_rasterized() for c in ax.collections)  # few points: vectors


@pytest.mark.slow  # over 0.5 s: out of the fast loop, still in CI
def test_a_dense_log_spaced_bifurcation_is_rasterised_on_a_log_axis(tmp_path: Path) -> None:
    diagram = bifurcation(200, RASTER_POINTS // 30, log=True)  # ~45 complex runs
    assert sum(len(r.peaks) for r in diagram.runs) > RASTER_POINTS
    drawing = sweep_drawing(diagram, hopf=None)
    ax = drawing.figure.axes[0]
    assert ax.get_xscale() == "log"
    assert ax.collections and all(c.get_rasterized() for c in ax.collections)
    assert write(drawing, tmp_path / "b.pdf")[0].read_bytes().startswith(b"%PDF")


# -- run figures ------------------------------------------------------------------------------


@pytest.mark.slow  # over 0.5 s: out of the fast loop, still in CI
def test_single_run_png_has_four_panels_and_long_format_data(tmp_path: Path) -> None:
    drawing = run_drawing([(stored_run(5), sine_traces())])
    written = write(drawing, tmp_path / "run.png")
    pixels = png_pixels(written[0], RUN_SIZE)
    figure = drawing.figure
    assert len(figure.axes) == 4
    for i in range(4):
        assert len(axes_colors(pixels, figure, i)) > 1  # something drawn in every panel
    time_ax, _, spec_ax, lam_ax = figure.axes
    assert [t.get_text() for t in time_ax.get_legend().get_texts()] == [
        "$m_x$ − trend (slope 0.1 removed)", "$m_y$"]
    peak = spec_ax.get_legend().get_texts()[0].get_text()
    assert peak.startswith("largest peak at f = ") and float(peak.rsplit(" ", 1)[1]) == pytest.approx(0.2, abs=0.01)
    assert spec_ax.get_xscale() == "log" and lam_ax.get_xscale() == "log"
    # the time series shows the last 10 periods (5 time units each) of the 100 of the window
    assert time_ax.get_xlabel().startswith("t (model time units): the last 10 periods")
    shown = np.concatenate([line.get_xdata() for line in time_ax.get_lines()])
    assert (shown.min(), shown.max()) == pytest.approx((150, 200), abs=1)
    lam_texts = [t.get_text() for t in lam_ax.get_legend().get_texts()]
    assert lam_texts == ["running λ(t)", "0", "λmax = 0.0008(9)", "rk4 map at dt = 0.01"]
    title = figure.get_suptitle().replace("\u00a0", " ")  # no-break spaces keep "k = 12" whole
    assert "run 5" in title and "τ = 2" in title and "δ = 0.1" in title
    assert "rk4, dt 0.01" in title and "oscillatory, λmax 0.001 ± 0.0005" in title
    rows = read_csv(written[1])
    assert rows[0] == ["run_id", "panel", "x", "y"]
    per_panel: dict[str, int] = {}
    for r in rows[1:]:
        per_panel[r[1]] = per_panel.get(r[1], 0) + 1
    assert set(per_panel) == {"time_m_x_detrended", "time_m_y", "phase", "spectrum", "lambda"}
    assert per_panel["time_m_y"] == 10_001 and per_panel["lambda"] == 2000  # t = 0 has no log
    # the oscillation is left once the ramp is removed
    detrended = [float(r[3]) for r in rows[1:] if r[1] == "time_m_x_detrended"]
    assert abs(np.mean(detrended)) < 1e-3 and np.ptp(detrended) == pytest.approx(2 / (2 * np.pi * 0.2), rel=1e-3)


def test_long_traces_are_rasterised_and_their_table_strided() -> None:
    n = 2 * MAX_TABLE_ROWS + 1
    drawing = run_drawing([(stored_run(1), sine_traces(n=n))])
    time_ax = drawing.figure.axes[0]
    assert n > RASTER_LINE_POINTS and all(line.get_rasterized() for line in time_ax.get_lines())
    rows = [r for r in drawing.tables[0].rows if r[1] == "time_m_y"]
    assert MAX_TABLE_ROWS // 2 < len(rows) <= MAX_TABLE_ROWS
    assert not any(line.get_rasterized() for line in drawing.figure.axes[3].get_lines())


def test_a_fixed_point_run_says_so_instead_of_magnifying_round_off() -> None:
    drawing = run_drawing([(stored_run(2, regime="sliding"), sine_traces(amp=0.0))])
    _, phase_ax, spec_ax, _ = drawing.figure.axes
    assert phase_ax.get_legend().get_texts()[0].get_text().startswith("a fixed point")
    assert any("no spectrum" in t.get_text() for t in spec_ax.texts)
    assert {r[1] for r in drawing.tables[0].rows} == {"time_m_x_detrended", "time_m_y", "phase", "lambda"}


@pytest.mark.slow  # over 0.5 s: out of the fast loop, still in CI
def test_comparison_overlays_runs_named_by_what_differs(tmp_path: Path) -> None:
    runs = [(stored_run(5), sine_traces()),
            (stored_run(6, k=14.0, regime="complex"), sine_traces(f=0.3, amp=0.5))]
    drawing = run_drawing(runs)
    written = write(drawing, tmp_path / "cmp.png")
    pixels = png_pixels(written[0], COMPARE_SIZE)
    figure = drawing.figure
    assert len(figure.axes) == 2
    for i in range(2):
        assert {"#0072B2", "#D55E00"} <= axes_colors(pixels, figure, i)  # the first two run colours
    assert legend_texts(figure) == ["run 5: k 12 (oscillatory)", "run 6: k 14 (complex)"]
    title = figure.get_suptitle().replace("\u00a0", " ")
    assert "τ = 2" in title and "k = " not in title
    shown = np.concatenate([line.get_xdata() for line in figure.axes[0].get_lines()])
    assert shown.min() == pytest.approx(150, abs=1)  # 10 periods of the slower run
    assert {r[1] for r in read_csv(written[1])[1:]} == {"time_m_y", "phase"}


def test_run_drawing_needs_a_run() -> None:
    with pytest.raises(ValueError, match="no runs"):
        run_drawing([])


# -- files: formats, fonts, reproducibility, data -----------------------------------------


@pytest.mark.slow  # over 0.5 s: out of the fast loop, still in CI
def test_pdf_embeds_truetype_fonts_and_carries_no_date(tmp_path: Path) -> None:
    before = matplotlib.rcParams["pdf.fonttype"]
    data = write(sweep_drawing(phase_diagram(), hopf=None), tmp_path / "f.PDF")[0].read_bytes()
    assert data.startswith(b"%PDF")
    assert b"/FontFile2" in data and b"/Type3" not in data
    assert b"slopetui 0.1.0" in data and b"/CreationDate" not in data
    assert matplotlib.rcParams["pdf.fonttype"] == before  # the global settings are untouched


@pytest.mark.slow  # over 0.5 s: out of the fast loop, still in CI
def test_svg_is_svg_with_its_creator(tmp_path: Path) -> None:
    data = write(run_drawing([(stored_run(5), sine_traces(n=2001))]), tmp_path / "r.svg")[0].read_bytes()
    assert data.startswith(b"<?xml") and b"<svg" in data[:1000]
    assert b"slopetui 0.1.0" in data and b"<dc:date>" not in data


@pytest.mark.slow  # over 0.5 s: out of the fast loop, still in CI
@pytest.mark.parametrize("ext", ["pdf", "svg"])
def test_the_same_data_gives_byte_identical_files(tmp_path: Path, ext: str) -> None:
    first = write(sweep_drawing(phase_diagram(), hopf=None), tmp_path / f"one.{ext}")[0]
    second = write(sweep_drawing(phase_diagram(), hopf=None), tmp_path / f"two.{ext}")[0]
    assert first.read_bytes() == second.read_bytes()


def test_data_paths_put_the_first_table_at_the_stem() -> None:
    drawing = Drawing(Figure(), (Table("points", ("a",), []), Table("curves", ("a",), [])))
    assert data_paths(Path("/d/fig.pdf"), drawing) == [Path("/d/fig.csv"), Path("/d/fig.curves.csv")]


def test_csv_cells_spell_out_nan_and_leave_none_empty() -> None:
    # the figures' tables write their cells with the exporter's (csv.writer takes str())
    assert [str(cell(v)) for v in (math.nan, math.inf, -math.inf, None, [1.5, 2.0], np.float64(0.1),
                                  np.int64(3), True, "x")] == [
        "nan", "inf", "-inf", "", "[1.5, 2.0]", "0.1", "3", "True", "x"]


def test_stored_text_is_drawn_plain() -> None:
    diagram = phase_diagram(3, 3)
    evil = SweepDiagram(diagram.id, "cost $5 to $10 \x1b[31m", diagram.spec, diagram.runs)
    title = sweep_drawing(evil, hopf=None).figure.axes[0].get_title()
    assert title == r"sweep 7: cost \$5 to \$10 \x1b[31m"


# -- bad output paths and failed writes ---------------------------------------------------------


def test_check_output_returns_the_absolute_path(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    assert check_output("fig.Svg") == tmp_path / "fig.Svg"
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize(("name", "message"), [
    ("x.jpg", "--output: unknown extension '.jpg' in {p} (allowed: .pdf, .svg, .png)"),
    ("x", "--output: no extension in {p}"),
    ("missing/x.pdf", "--output: the folder {d} does not exist"),
])
def test_check_output_refuses_bad_names(tmp_path: Path, name: str, message: str) -> None:
    path = tmp_path / name
    with pytest.raises(FigureError) as err:
        check_output(path)
    assert str(err.value).startswith(message.format(p=path, d=path.parent))
    assert err.value.field == "--output"
    assert os.listdir(tmp_path) == []


def test_check_output_refuses_a_folder_as_target_or_parent(tmp_path: Path) -> None:
    (tmp_path / "sub.pdf").mkdir()
    (tmp_path / "file").write_text("")
    with pytest.raises(FigureError, match=r"^--output: .*sub\.pdf is a folder"):
        check_output(tmp_path / "sub.pdf")
    with pytest.raises(FigureError, match=r"^--figure: .*file is not a folder"):
        check_output(tmp_path / "file" / "x.png", field="--figure")
    assert sorted(os.listdir(tmp_path)) == ["file", "sub.pdf"]


def test_check_output_refuses_an_unwritable_folder(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    folder = tmp_path / "ro"
    folder.mkdir()
    folder.chmod(0o500)
    try:
        # the real permission check: root passes it (permissions do not bind root), so
        # follow what os.access says rather than skipping
        if os.access(folder, os.W_OK | os.X_OK):
            assert check_output(folder / "x.pdf") == folder / "x.pdf"
        else:
            with pytest.raises(FigureError, match=r"^--output: the folder .* is not writable"):
                check_output(folder / "x.pdf")
        # and the refusal itself, as any user sees it
        monkeypatch.setattr(figure_output.os, "access", lambda path, mode: Path(path) != folder)
        with pytest.raises(FigureError, match=f"^--output: the folder {re.escape(str(folder))} is not writable"):
            check_output(folder / "x.pdf")
        assert os.listdir(folder) == []
    finally:
        folder.chmod(0o700)


def test_a_failing_save_leaves_no_file_and_keeps_the_old_one(tmp_path: Path,
                                                             monkeypatch: pytest.MonkeyPatch) -> None:
    target = tmp_path / "fig.pdf"
    target.write_bytes(b"old")

    def broken(self: Figure, out: Any, **kwargs: Any) -> None:
        out.write(b"%PDF-partial")
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(Figure, "savefig", broken)
    with pytest.raises(FigureError, match=f"^cannot write {re.escape(str(target))}: No space left on device$"):
        write(sweep_drawing(phase_diagram(3, 3), hopf=None), target)
    assert os.listdir(tmp_path) == ["fig.pdf"] and target.read_bytes() == b"old"


def test_a_failing_table_leaves_no_figure_either(tmp_path: Path) -> None:
    drawing = sweep_drawing(phase_diagram(3, 3), hopf=None)
    bad = Drawing(drawing.figure, (Table("points", ("a", "b"), [(1, 2), (3,)]),))
    with pytest.raises(ValueError, match="row 1 has 1 cells"):
        write(bad, tmp_path / "fig.png")
    assert os.listdir(tmp_path) == []


def test_written_files_get_the_usual_permissions(tmp_path: Path) -> None:
    umask = os.umask(0o022)
    os.umask(umask)
    for path in write(sweep_drawing(phase_diagram(3, 3), hopf=None), tmp_path / "fig.png"):
        assert path.stat().st_mode & 0o777 == 0o666 & ~umask


# -- colours, labels, imports ----------------------------------------------------------------


def test_every_regime_key_has_a_colour_of_its_own() -> None:
    assert set(REGIME_COLORS) == set(LEGEND_ORDER)
    assert len(set(REGIME_COLORS.values())) == len(REGIME_COLORS)


def test_every_parameter_has_a_label() -> None:
    assert set(MEANINGS) == set(PARAM_NAMES)
    assert axis_label("delta") == "δ, initial offset (eq. 19)"


@pytest.mark.slow  # over 0.5 s: out of the fast loop, still in CI
def test_importing_the_package_loads_no_matplotlib() -> None:
    code = "import sys, slopetui.figures; print('matplotlib' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"
