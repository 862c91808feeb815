"""A figure names what it was computed at, as every output does (slopetui.provenance): in
its PDF, SVG or PNG metadata, in the comment line that opens each CSV beside it, and with
`--caption` in a line under it; the same facts in all three."""

from __future__ import annotations

import json
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

import slopetui
from core.jit_cache import source_digest
from slopetui.cli import main
from slopetui.figures import DIAGRAM_SIZE, PNG_DPI
from slopetui.figures.figure_facts import figure_caption
from slopetui.figures.output import FACTS_PREFIX, caption_lines, caption_strip_in
from tests.support import finish_all, submit_quick

DC = "{http://purl.org/dc/elements/1.1/}"
RDF = "{http://www.w3.org/1999/02/22-rdf-syntax-ns#}"


def _svg_metadata(path: Path) -> tuple[str, dict]:
    """The SVG's Dublin Core description (the caption's line) and keywords (the JSON)."""
    root = ET.parse(path).getroot()
    description = root.find(f".//{DC}description")
    keywords = root.find(f".//{DC}subject/{RDF}Bag/{RDF}li")
    assert description is not None and keywords is not None
    return description.text or "", json.loads(keywords.text or "")


def _csv_facts(path: Path) -> dict:
    first = path.read_text(encoding="utf-8").splitlines()[0]
    assert first.startswith(FACTS_PREFIX)
    return json.loads(first.removeprefix(FACTS_PREFIX))


@pytest.fixture
def sweep(db) -> int:
    sweep = submit_quick(db, 2, tau=2.0, lyap=False).sweep_id
    finish_all(db)
    return sweep


def test_a_sweeps_figure_names_its_params_solver_and_engine_in_the_svg_and_csv(
        sweep, db_url, tmp_path, capsys):
    out = tmp_path / "fig.svg"
    assert main(["figure", str(sweep), "-o", str(out), "--db", db_url]) == 0
    line, facts = _svg_metadata(out)
    assert facts["sweep"] == sweep and facts["varied"] == ["k"]
    assert facts["params"]["tau"] == 2.0 and facts["params"]["delta"] == 0.1
    assert facts["params"]["k"] is None  # varied: no one value
    assert facts["solver"] == {"method": "rk4", "dt": 0.01, "t_end": 200.0, "window": 100.0,
                               "lyap": False, "history": "constant", "stop": "t_end"}
    assert facts["engine"] == {"version": slopetui.__version__, "digest": source_digest()}
    assert _csv_facts(tmp_path / "fig.csv") == facts
    assert line == figure_caption(facts)
    assert line.startswith(f"sweep {sweep}: a=3.2 b=7.2 c=4.8 d=0.0001 k varied v=0.1 tau=2 ")
    assert "rk4, dt=0.01, t_end=200, window=100, lyap=False, history=constant, stop=t_end;" in line


def test_a_pdf_names_them_in_its_subject_and_keywords(sweep, db_url, tmp_path, capsys):
    out = tmp_path / "fig.pdf"
    assert main(["figure", str(sweep), "-o", str(out), "--db", db_url]) == 0
    data = out.read_bytes()  # matplotlib writes the info dictionary uncompressed
    subject = re.search(rb"/Subject \((.*?)\)\s*(?:/|>>)", data, re.DOTALL)
    assert subject is not None and subject.group(1).startswith(f"sweep {sweep}: a=3.2".encode())
    keywords = re.search(rb"/Keywords \((.*?)\)\s*(?:/|>>)", data, re.DOTALL)
    assert keywords is not None
    assert json.loads(keywords.group(1).decode()) == _csv_facts(tmp_path / "fig.csv")


def test_caption_adds_the_line_under_the_figure(sweep, db_url, tmp_path, capsys):
    import matplotlib.image

    plain, captioned = tmp_path / "plain.png", tmp_path / "captioned.png"
    assert main(["figure", str(sweep), "-o", str(plain), "--db", db_url]) == 0
    assert main(["figure", str(sweep), "-o", str(captioned), "--caption", "--db", db_url]) == 0
    width, height = DIAGRAM_SIZE
    assert matplotlib.image.imread(plain).shape[:2] == (round(height * PNG_DPI),
                                                        round(width * PNG_DPI))
    assert matplotlib.image.imread(captioned).shape[:2] == (
        round((height + caption_strip_in(2)) * PNG_DPI), round(width * PNG_DPI))
    from PIL import Image

    with Image.open(captioned) as image:
        facts = json.loads(image.text["slopetui"])
        assert image.text["Description"] == figure_caption(facts)
    assert facts == _csv_facts(tmp_path / "captioned.csv")


def test_the_caption_is_drawn_from_the_same_facts(sweep, db):
    from slopetui.figures.figure_files import sweep_figure
    from slopetui.figures.output import write
    from slopetui.store.queries import sweep_engines
    from slopetui.sweeps.diagram import load_diagram

    drawing = sweep_figure(load_diagram(db, sweep), hopf=False, engines=sweep_engines(db, sweep))
    assert drawing.facts is not None
    texts_before = len(drawing.figure.texts)
    import tempfile

    with tempfile.TemporaryDirectory() as folder:
        write(drawing, Path(folder) / "a.svg", caption=True)
    added = drawing.figure.texts[texts_before:]
    line = figure_caption(dict(drawing.facts))
    assert [t.get_text() for t in added] == ["\n".join(caption_lines(line))]
    assert added[0].get_text().replace("\n", "; ") == line  # the same line, in two
    assert added[0].get_fontsize() <= 6.5


@pytest.mark.slow  # recomputes two runs (~1 s): out of the fast loop
def test_runs_figure_names_each_run_and_what_they_share(db, db_url, sweep, tmp_path, capsys):
    from slopetui.store.queries import runs_of

    a, b = (r.id for r in runs_of(db, sweep))
    out = tmp_path / "cmp.svg"
    assert main(["figure", "--run", str(a), "--run", str(b), "-o", str(out), "--db", db_url]) == 0
    line, facts = _svg_metadata(out)
    assert [f["run"] for f in facts["runs"]] == [a, b] and facts["varied"] == ["k"]
    assert facts["params"]["k"] is None and [f["params"]["k"] for f in facts["runs"]] == [4.0, 12.0]
    # redrawn now by this engine; the stored result by the engine stored with the run
    assert all(f["engine"]["digest"] == f["stored_engine"] == source_digest()
               for f in facts["runs"])
    assert line.startswith(f"runs {a}, {b}: a=3.2 b=7.2 c=4.8 d=0.0001 k varied")
    assert _csv_facts(tmp_path / "cmp.csv") == facts


@pytest.mark.slow  # recomputes two runs (~1 s): out of the fast loop
def test_the_caption_sits_under_the_legends_and_panels(db, sweep, tmp_path):
    """Before: a line inside the figure overprinted the comparison's legend, which the
    constrained layout hangs from the figure's lower edge."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from slopetui.figures.figure_files import runs_figure
    from slopetui.figures.output import write
    from slopetui.store.queries import runs_of
    from slopetui.sweeps.recompute import load_run

    runs = [load_run(db, r.id) for r in runs_of(db, sweep)]
    drawing = runs_figure(runs)
    height = drawing.figure.get_size_inches()[1]
    write(drawing, tmp_path / "cmp.png", caption=True)
    figure = drawing.figure
    assert figure.get_size_inches()[1] == height  # the panels keep their size
    renderer = FigureCanvasAgg(figure).get_renderer()
    caption = figure.texts[-1].get_window_extent(renderer)
    above = [*(legend.get_window_extent(renderer) for legend in figure.legends),
             *(ax.get_tightbbox(renderer) for ax in figure.axes)]
    assert figure.legends and all(box.y0 >= caption.y1 for box in above)
    assert caption.y1 <= 0  # in the strip under the figure's own area


def _facts_of(**spec: object) -> dict:
    from types import SimpleNamespace

    from slopetui.figures.figure_facts import sweep_facts
    from slopetui.sweeps.spec import parse_spec

    data = {"x": {"param": "k", "start": 5, "stop": 10, "num": 3},
            "fixed": {"delta": 0.1}, "solver": {"t_end": 200.0, "history": "constant"}, **spec}
    return sweep_facts(SimpleNamespace(id=7, spec=parse_spec(data)), [source_digest()])


def test_a_sweep_from_initial_conditions_of_different_delta_and_history_claims_neither():
    facts = _facts_of(initial=[{"delta": 1e-6}, {"delta": 0.1, "history": "consistent"}])
    assert facts["varied"] == ["k", "delta"]
    assert facts["params"]["delta"] is None and facts["params"]["k"] is None
    assert facts["solver"]["history"] is None
    assert facts["initial"] == [{"delta": 1e-6, "history": "constant"},
                                {"delta": 0.1, "history": "consistent"}]
    line = figure_caption(facts)
    assert "delta varied" in line and "history" not in line and "None" not in line


def test_initial_conditions_that_share_a_delta_name_it_and_their_one_history():
    facts = _facts_of(initial=[{"delta": 1e-3, "history": "consistent"}, {"delta": 1e-3}])
    assert facts["varied"] == ["k"] and facts["params"]["delta"] == 1e-3
    assert facts["solver"]["history"] is None
    facts = _facts_of(initial=[{"delta": 1e-3, "history": "consistent"},
                               {"delta": 0.2, "history": "consistent"}])
    assert facts["solver"]["history"] == "consistent" and facts["params"]["delta"] is None


def test_a_sweep_of_one_condition_keeps_its_delta_and_history():
    facts = _facts_of()
    assert "initial" not in facts and facts["params"]["delta"] == 0.1
    assert facts["solver"]["history"] == "constant"


def test_a_sweeps_engines_are_its_computed_runs_not_its_inferred_ones(sweep, db):
    """An inferred run (never computed) keeps the digest written when it was queued: it
    names no engine of the sweep's results."""
    from sqlalchemy import update

    from slopetui.store.models import Run
    from slopetui.store.queries import runs_of, sweep_engines

    first = next(iter(runs_of(db, sweep))).id
    with db.sessions() as s, s.begin():
        s.execute(update(Run).where(Run.id == first)
                  .values(inferred=True, engine="0123456789abcdef"))
    assert sweep_engines(db, sweep) == (source_digest(),)


def test_runs_compared_at_different_steps_name_no_one_step():
    from slopetui.figures.figure_facts import runs_facts
    from tests.unit.test_figures import stored_run

    facts = runs_facts([stored_run(1, k=4.0, dt=0.01), stored_run(2, k=12.0, dt=0.005)])
    assert facts["varied"] == ["k", "dt"]
    assert facts["solver"]["dt"] is None and facts["solver"]["method"] == "rk4"
    assert [f["solver"]["dt"] for f in facts["runs"]] == [0.01, 0.005]
    line = figure_caption(facts)
    assert "k varied" in line and "rk4, dt varied, t_end=200" in line


def test_a_sweep_with_no_run_done_says_so_in_its_caption():
    from types import SimpleNamespace

    from slopetui.figures.figure_facts import sweep_facts
    from slopetui.sweeps.spec import parse_spec

    spec = parse_spec({"x": {"param": "k", "start": 5, "stop": 10, "num": 3}})
    line = figure_caption(sweep_facts(SimpleNamespace(id=3, spec=spec), []))
    assert line.endswith("; no runs done") and "None" not in line


@pytest.mark.parametrize("n_runs", [2, 12])
def test_a_long_caption_keeps_a_readable_size_and_fits_the_figure(n_runs):
    """Measured with the renderer, not the estimate the caption was set by: every line
    fits in the figure's width, at 5 pt or more."""
    import matplotlib.pyplot as plt

    from slopetui.figures.output import CAPTION_MIN_PT, add_caption

    shows = "runs " + ", ".join(str(1000 + i) for i in range(n_runs))
    text = (f"{shows}: a=3.2 b=7.2 c=4.8 d=0.0001 k varied v=0.1 tau=2 delta=0.1; rk4, "
            "dt=0.01, t_end=200, window=100, lyap=False, history=state:0123456789abcdef, "
            "stop=t_end; slopetui 0.1.0, engine 0123456789abcdef, fedcba9876543210")
    figure = plt.figure(figsize=DIAGRAM_SIZE)
    try:
        figure.add_subplot().plot([0, 1], [0, 1])
        add_caption(figure, text)
        drawn = figure.texts[-1]
        assert drawn.get_fontsize() >= CAPTION_MIN_PT
        words = drawn.get_text().replace("\n", " ").replace(";", "").split()
        assert words == text.replace(";", "").split()  # nothing lost, wrapped between words
        renderer = figure.canvas.get_renderer()
        box = drawn.get_window_extent(renderer)
        assert box.x0 >= 0 and box.x1 <= figure.bbox.width
    finally:
        plt.close(figure)


def test_the_figure_csv_reads_as_its_help_says(sweep, db_url, tmp_path, capsys):
    """The CSV's first line is the facts: `figure --help` says how to read past it, and
    read so, its header is the table's (a plain read_csv would take the facts line)."""
    import pandas as pd

    with pytest.raises(SystemExit):
        main(["figure", "--help"])
    assert "pandas.read_csv(path, skiprows=1)" in " ".join(capsys.readouterr().out.split())
    out = tmp_path / "fig.svg"
    assert main(["figure", str(sweep), "-o", str(out), "--db", db_url]) == 0
    path = tmp_path / "fig.csv"
    header = path.read_text(encoding="utf-8").splitlines()[1].split(",")
    table = pd.read_csv(path, skiprows=1)
    assert list(table.columns) == header and len(table) == 2
