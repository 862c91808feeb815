"""Dependencies point one way (README, "Layers"): the import-linter contracts hold, the
queue loads no sweeps, and the sweeps' steps reach the pool as hooks: they pickle by
reference into the spawned workers, and a real `slopetui worker` refines an adaptive
sweep through them."""

from __future__ import annotations

import pickle
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from sqlalchemy import select

from slopetui.queue.worker_process import WorkerOptions
from slopetui.store.models import Sweep
from slopetui.store.open import open_store
from slopetui.sweeps.adaptive import advance_all
from slopetui.sweeps.progress import PoolProgress
from slopetui.sweeps.spec import parse_spec
from slopetui.sweeps.submit import submit
from tests.support import QUICK_SOLVER, slopetui_cli

ROOT = Path(__file__).resolve().parents[2]


def test_the_layer_contracts_hold():
    pytest.importorskip("importlinter", reason="the lint extra: pip install -e '.[lint]'")
    lint = shutil.which("lint-imports", path=str(Path(sys.executable).parent))
    assert lint, "import-linter is installed but its lint-imports command is not"
    done = subprocess.run([lint, "--no-cache"], cwd=ROOT, capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 0, done.stdout + done.stderr


def test_the_queue_loads_no_sweeps_and_the_plots_no_store():
    code = ("import sys, slopetui.queue.pool, slopetui.queue.local_pool, "
            "slopetui.queue.workers_table, slopetui.queue.jobs, slopetui.queue.cache; "
            "bad = sorted(m for m in sys.modules if m.startswith(('slopetui.sweeps', "
            "'slopetui.plots', 'slopetui.cli', 'slopetui.tui', 'slopetui.reproduce'))); "
            "assert not bad, bad")
    done = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 0, done.stderr


def test_the_hooks_pickle_by_reference():
    """The pool spawns its workers: WorkerOptions travels pickled, hooks included."""
    opts = WorkerOptions(db_url="sqlite:///x.db", idle_hook=advance_all, progress=PoolProgress)
    back = pickle.loads(pickle.dumps(opts))
    assert back == opts and back.idle_hook is advance_all and back.progress is PoolProgress
    assert WorkerOptions(db_url="sqlite:///x.db").idle_hook is None


def test_a_worker_pool_refines_an_adaptive_sweep_through_its_hook(tmp_path):
    url = f"sqlite:///{tmp_path / 'store.db'}"
    db = open_store(url)
    spec = {"name": "adaptive", "x": {"param": "k", "start": 2, "stop": 20, "num": 7},
            "y": {"param": "tau", "start": 0.5, "stop": 10, "num": 5},
            "adaptive": {"levels": 1}, "solver": {**QUICK_SOLVER, "lyap": False}}
    sweep_id = submit(db, parse_spec(spec)).sweep_id
    log = tmp_path / "worker.log"
    done = slopetui_cli("worker", "-j", "1", "--exit-when-idle", "--db", url, "--log",
                        str(log), env={"XDG_STATE_HOME": str(tmp_path / "state")})
    assert done.returncode == 0, done.stderr
    with db.sessions() as s:
        sweep = s.scalars(select(Sweep).where(Sweep.id == sweep_id)).one()
        assert sweep.refined, log.read_text()
    # the pool's progress line came through its hook too
    assert " runs done" in log.read_text()
    db.dispose()
