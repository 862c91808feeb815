"""Data safety of the store: migrations keep every run, backups, damaged files, and files
that cannot be created are named with their cause (full and read-only file systems:
tests/integration/test_store_filesystems.py)."""

from __future__ import annotations

import os
import sqlite3
from pathlib import Path

import pytest
from sqlalchemy import text

from slopetui.cli import main
from slopetui.store.database import Database
from slopetui.store.failures import StoreError
from slopetui.store.integrity import integrity_problems
from slopetui.store.migrate import (
    current_revision,
    downgrade,
    head_revision,
    revisions,
    upgrade,
)
from slopetui.store.models import Run
from slopetui.store.open import open_store
from tests.support import finish_all, submit_quick


def _results(db: Database) -> list[tuple]:
    with db.engine.connect() as conn:
        return [tuple(r) for r in conn.execute(text(
            "SELECT id, sweep_id, status, regime, lambda_max, amplitude FROM runs "
            "ORDER BY id"))]


@pytest.fixture
def populated(db: Database) -> Database:
    submit_quick(db, 6)
    finish_all(db)
    submit_quick(db, 3)  # and some still queued
    return db


@pytest.mark.parametrize("older", revisions()[:-1])
def test_downgrade_and_upgrade_keep_every_run(populated, older):
    """Alembic rebuilds `sweeps` on SQLite by copy, DROP, rename; with foreign keys on the
    DROP cascaded to `runs`: a downgrade of a store with done runs left none."""
    before = _results(populated)
    assert len(before) == 9
    _, after, copy = downgrade(populated, older)
    assert current_revision(populated) == after == older
    assert [r[:3] for r in _results(populated)] == [r[:3] for r in before]
    assert copy is not None and copy.name == f"store.db.bak-{head_revision()}"
    upgrade(populated)
    assert current_revision(populated) == head_revision()
    assert _results(populated)[:6] == before[:6]  # the results too, not only the rows
    assert integrity_problems(populated) == []


def test_every_migration_first_copies_the_file_aside(populated):
    downgrade(populated, revisions()[0])
    upgrade(populated)
    copy = populated.path.with_name(f"store.db.bak-{revisions()[0]}")
    assert copy.exists() and oct(copy.stat().st_mode & 0o777) == oct(0o600)
    with sqlite3.connect(copy) as conn:
        assert conn.execute("SELECT count(*) FROM runs").fetchone()[0] == 9
        assert conn.execute("SELECT version_num FROM alembic_version").fetchone()[0] \
            == revisions()[0]
    downgrade(populated, revisions()[0])  # a second copy of that revision: never over it
    assert len(list(populated.path.parent.glob(f"store.db.bak-{head_revision()}*"))) == 2


def test_a_migration_that_would_orphan_rows_is_rolled_back(populated):
    downgrade(populated, revisions()[0])
    raw = sqlite3.connect(populated.path, isolation_level=None)
    raw.execute("PRAGMA foreign_keys = OFF")
    raw.execute("UPDATE runs SET sweep_id = 999 WHERE id = 1")  # points nowhere
    raw.close()
    with pytest.raises(StoreError, match=r"rolled back.*foreign keys"):
        upgrade(populated)
    assert current_revision(populated) == revisions()[0]


def test_downgrade_asks_for_confirmation_and_names_bad_revisions(populated, capsys):
    url = str(populated.url)
    assert main(["db", "downgrade", revisions()[0], "--db", url]) == 2  # stdin: not a tty
    assert "--yes" in capsys.readouterr().err
    assert main(["db", "downgrade", "nope", "--yes", "--db", url]) == 2
    assert "REV: unknown revision 'nope'" in capsys.readouterr().err
    assert main(["db", "downgrade", head_revision(), "--yes", "--db", url]) == 2
    assert "not older" in capsys.readouterr().err
    assert current_revision(populated) == head_revision()
    assert main(["db", "downgrade", revisions()[0], "--yes", "--db", url]) == 0
    assert "backup copy" in capsys.readouterr().out


def _damage(path: Path) -> None:
    """4 KB of garbage over the middle leaf page of the runs table (after a checkpoint
    moved the WAL in): a page every read of the runs must cross. The middle of the file
    was used before, until new tables moved an index page of runs there, which a plain
    listing never reads."""
    with sqlite3.connect(path) as conn:
        conn.execute("PRAGMA wal_checkpoint(TRUNCATE)")
        pages = [n for (n,) in conn.execute(
            "SELECT pageno FROM dbstat WHERE name = 'runs' AND pagetype = 'leaf' ORDER BY pageno")]
        page_size = conn.execute("PRAGMA page_size").fetchone()[0]
    with path.open("r+b") as f:
        f.seek((pages[len(pages) // 2] - 1) * page_size)
        f.write(os.urandom(page_size))


def test_db_check_finds_a_damaged_page(db_url, capsys, tmp_path):
    db = open_store(db_url)
    sub = submit_quick(db, 2)
    with db.transaction() as s:  # enough rows for the file to have a middle
        for i in range(3000):
            s.add(Run(sweep_id=sub.sweep_id, ix=i + 10, iy=0, a=1, b=1, c=1, d=0, k=i, v=1,
                      tau=1, delta=0.1, method="rk4", dt=0.01, t_end=1, window=1,
                      engine="x", cache_key=f"{i:064d}"))
    assert main(["db", "check", "--db", db_url]) == 0
    assert "ok" in capsys.readouterr().out
    db.dispose()
    _damage(db.path)
    assert main(["db", "check", "--db", db_url]) == 1
    out = capsys.readouterr().out
    assert "DAMAGED" in out and str(db.path) in out
    # a command that reads the broken page says which file is damaged, in one line
    assert main(["runs", "--limit", "0", "--db", db_url]) == 1
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and f"{db.path} is damaged" in err
    not_a_db = tmp_path / "garbage.db"
    not_a_db.write_bytes(os.urandom(8192))
    assert main(["status", "--db", f"sqlite:///{not_a_db}"]) == 2
    assert f"{not_a_db} is damaged" in capsys.readouterr().err


def test_an_explicit_store_in_a_missing_folder_is_refused(tmp_path, capsys):
    url = f"sqlite:///{tmp_path / 'no' / 'such' / 'x.db'}"
    assert main(["status", "--db", url]) == 2
    err = capsys.readouterr().err
    assert f"the folder {tmp_path / 'no' / 'such'} does not exist" in err
    assert not (tmp_path / "no").exists()


def test_a_path_under_proc_is_refused_in_one_line(capsys):
    assert main(["status", "--db", "sqlite:////proc/self/x.db"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "/proc is a virtual file system" in err


def test_a_pool_does_not_start_on_a_damaged_file(db_url, tmp_path, caplog):
    from slopetui.queue.pool import Pool
    from slopetui.queue.worker_process import WorkerOptions

    db = open_store(db_url)
    sub = submit_quick(db, 2)
    with db.transaction() as s:
        for i in range(3000):
            s.add(Run(sweep_id=sub.sweep_id, ix=i + 10, iy=0, a=1, b=1, c=1, d=0, k=i, v=1,
                      tau=1, delta=0.1, method="rk4", dt=0.01, t_end=1, window=1,
                      engine="x", cache_key=f"{i:064d}"))
    db.dispose()
    _damage(db.path)
    opts = WorkerOptions(db_url=db_url, exit_when_idle=True)
    assert Pool(opts, 1).run() == 1
    assert "is damaged" in caplog.text
