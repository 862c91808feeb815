"""`slopetui --help`, `status`, `runs`, `sql` and `show` start without the imports they do
not use.

A one-second `slopetui run` took ~5 s of wall time, most of it imports: every subcommand
module loaded numba, Alembic, SQLAlchemy and the plots at the top. The rule now: a
subcommand module imports what its parser needs at the top and the rest in its handler
(slopetui.cli.options); the commands that compute nothing load neither numba nor numpy
(the targets: `--help` ≤ 0.5 s, `status` ≤ 1 s, `show` of a 100 x 100 sweep
≤ 1 s; benchmarks/bench_startup.py times them), and `show` reads a SQLite store without
SQLAlchemy. These tests keep it from drifting back: each command runs in a fresh
process, which then names the heavy modules it loaded.
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

import migrations
from slopetui.store.database import Database
from slopetui.sweeps.spec import parse_spec
from slopetui.sweeps.submit import submit
from tests.support import QUICK_SOLVER, finish_all, submit_quick

#: Heavy imports no parser needs: numba and its kernels (~1 s), numpy (~0.1 s: the engine's
#: core.solve and core.stability, the sweeps' specs), Alembic (~0.2 s), the application
#: (Textual, rich) and plotext.
NEVER_FOR_HELP = ("numba", "llvmlite", "core.batch", "numpy", "alembic", "textual", "rich",
                  "plotext", "sqlalchemy", "argcomplete", "pandas", "matplotlib", "scipy")
#: What the commands that read the store (status, runs, sql) may load of NEVER_FOR_HELP.
THE_DRIVER = {"sqlalchemy"}


def loaded_after(code: str) -> set[str]:
    """The modules of NEVER_FOR_HELP loaded after ``code`` ran in a fresh interpreter (a
    SystemExit, as of `--help`, ends the code, not the probe)."""
    probe = (f"import sys, json\ntry:\n    {code}\nexcept SystemExit:\n    pass\n"
             f"print(json.dumps([m for m in {list(NEVER_FOR_HELP)!r} if m in sys.modules]))")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                         timeout=120, check=True)
    return set(json.loads(out.stdout.strip().splitlines()[-1]))


def loaded_by(*argv: str) -> set[str]:
    """The heavy modules `slopetui ARGV` loads (main() in a fresh process, its output
    captured)."""
    return loaded_after(f"from slopetui.cli import main; main({list(argv)!r})")


def test_building_every_parser_loads_no_heavy_module():
    assert loaded_after("from slopetui.cli import build_parser; build_parser()") == set()


def test_help_loads_no_heavy_module():
    assert loaded_by("--help") == set()


def test_the_jobs_modules_and_the_method_names_load_no_numpy():
    """The queue's kinds of job (which `status` and `workers` reach through the registry's
    activity() counts) import numpy only in the functions that compute or decode, and
    ``from core.methods import METHODS`` (a form's choices) loads none."""
    assert loaded_after("import slopetui.sweeps.branches, slopetui.sweeps.hysteresis_runs, "
                        "slopetui.queue.registry, slopetui.queue.worker_process; "
                        "from core.methods import METHODS") == THE_DRIVER


@pytest.fixture
def busy_store(db, db_url):
    """An up-to-date store (no migration to run) with two sweeps: two runs done, one queued."""
    submit_quick(db, 2)
    finish_all(db)
    submit_quick(db, 1, tau=3.0)
    return db_url


@pytest.mark.parametrize("argv", [
    ["status"], ["status", "--all", "--json"], ["runs"], ["runs", "--sweep", "1"],
    ["sql", "select count(*) from runs"]], ids=" ".join)
def test_reading_commands_load_the_database_driver_only(busy_store, argv):
    """status, runs and sql: SQLAlchemy (the store), no numpy, no numba."""
    assert loaded_by(*argv, "--db", busy_store) == THE_DRIVER


#: What `slopetui show` may load of NEVER_FOR_HELP from a SQLite store at the current
#: schema: numpy and plotext (the drawing, the Hopf curve), not SQLAlchemy
#: (slopetui.store.diagrams.sqlite_reads: 0.35-0.45 s less), nor numba.
THE_DRAWING = {"numpy", "plotext"}


@pytest.mark.parametrize("sweep", [[], ["1"], ["3"]], ids=["newest", "1-D", "2-D"])
def test_show_loads_the_drawing_only(busy_store, db, sweep):
    """`show` of a 1-D and of a 2-D sweep, and of the newest sweep."""
    submit(db, parse_spec({"x": {"param": "k", "start": 4, "stop": 12, "num": 3},
                           "y": {"param": "tau", "start": 1, "stop": 3, "num": 2},
                           "solver": QUICK_SOLVER}))
    assert loaded_by("show", *sweep, "--width", "80", "--height", "24", "--db",
                     busy_store) == THE_DRAWING


def test_show_of_an_old_store_migrates_it(busy_store, db):
    """A store at an older schema goes through open_store (SQLAlchemy, Alembic), which
    migrates it before it is read."""
    from slopetui.store.migrate import downgrade, revisions

    downgrade(db, revisions()[-2])
    db.dispose()
    assert {"sqlalchemy", "alembic"} <= loaded_by("show", "1", "--width", "80", "--height",
                                                  "24", "--db", busy_store)
    assert Database(busy_store).opened_revision == migrations.HEAD


def test_runs_as_csv_loads_no_numba(busy_store):
    """`runs --csv` writes through the exporter, which knows numpy's scalars (so numpy may
    come), never the kernels."""
    assert not loaded_by("runs", "--csv", "--db", busy_store) & {"numba", "llvmlite",
                                                                  "core.batch"}


#: What the commands and the application that only read stored results must not load:
#: the kernels, scipy (continuation, shooting) and pandas (the notebooks' frames).
NEVER_FOR_READING = {"numba", "llvmlite", "core.batch", "scipy", "pandas"}


@pytest.mark.parametrize("argv", [
    ["branch"], ["hysteresis", "--show", "1"], ["export", "1", "--csv"]], ids=" ".join)
def test_commands_that_read_stored_results_load_no_kernels_and_no_pandas(busy_store, argv):
    """`branch` (its lines are the walk's, not the walk), `hysteresis --show` and `export
    --csv` read the store; the kernels and pandas load only where something is computed or
    a DataFrame built."""
    assert not loaded_by(*argv, "--db", busy_store) & NEVER_FOR_READING


def test_the_application_loads_no_kernels_scipy_or_pandas_to_start():
    """The application imports what its first screens need; the run detail, the fold
    overlay, a figure and a JSON export load their heavy modules when first used."""
    assert not loaded_after("import slopetui.tui.app") & NEVER_FOR_READING
