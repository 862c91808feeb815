"""A PostgreSQL downgrade is backed up first: pg_dump writes the whole
database into a file of mode 600 whose path is printed, and that file restores (psql -f
into a new database); the password reaches pg_dump through its environment, never its
command line; without pg_dump the downgrade is refused unless --no-backup, and a pg_dump
that fails leaves the schema as it was."""

from __future__ import annotations

import os
import re
import stat
import subprocess
from pathlib import Path

import pytest

from slopetui.cli import main
from slopetui.store import server_dump
from slopetui.store.migrate import current_revision, head_revision
from slopetui.store.open import open_store
from tests.support import pg_database
from tests.unit.test_ids_kept import _rows, populate

#: The test server trusts every local connection: a password in the URL is ignored by the
#: server, and is what must not reach a command line.
PASSWORD = "pw-seen-nowhere-31"


def _with_password(url: str) -> str:
    return url.replace("postgres@", f"postgres:{PASSWORD}@", 1)


@pytest.fixture
def populated(pg_server, tmp_path, monkeypatch):
    """A database with rows in every job table, its URL with a password, and the backups'
    folder under tmp_path (platformdirs reads XDG_DATA_HOME)."""
    monkeypatch.setenv("XDG_DATA_HOME", str(tmp_path / "data"))
    with pg_server.database() as url:
        db = open_store(url)
        populate(db)
        populate(db)
        db.dispose()
        yield _with_password(url)


def test_the_dump_is_private_named_and_restores(populated, pg_server, capsys):
    db = open_store(populated)
    rows = _rows(db)
    assert main(["db", "downgrade", "0003", "--yes", "--db", populated]) == 0
    out = capsys.readouterr().out
    assert PASSWORD not in out
    found = re.search(r"; backup (\S+) \(pg_dump\)", out)
    assert found, out
    dump = Path(found[1])
    assert dump.parent == server_dump.backup_folder()
    assert stat.S_IMODE(dump.stat().st_mode) == 0o600
    assert stat.S_IMODE(dump.parent.stat().st_mode) == 0o700
    assert dump.name.endswith(f".bak-{head_revision()}.sql")
    assert current_revision(db) == "0003"
    db.dispose()

    restored_name = f"{pg_server.prefix}_restored"
    with pg_database(pg_server.url.render_as_string(hide_password=False),
                     restored_name) as restored:
        target = pg_server.url.set(database=restored_name)
        subprocess.run(["psql", "-X", "-q", "-v", "ON_ERROR_STOP=1", "-f", str(dump)],
                       env={**os.environ, "PGHOST": target.host, "PGPORT": str(target.port),
                            "PGUSER": target.username, "PGDATABASE": restored_name},
                       check=True, capture_output=True)
        back = open_store(restored)  # at the head already: nothing to migrate
        assert current_revision(back) == head_revision()
        assert _rows(back) == rows
        back.dispose()


def _fake_pg_dump(folder: Path, log: Path, exit_code: int) -> None:
    """A pg_dump that writes down its arguments and whether it was given PGPASSWORD."""
    folder.mkdir()
    program = folder / "pg_dump"
    program.write_text(f"#!/bin/sh\nprintf '%s\\n' \"$@\" > {log}\n"
                       f"echo \"PGPASSWORD=$PGPASSWORD\" >> {log}\n"
                       f"echo 'pg_dump: error: server version mismatch' >&2\nexit {exit_code}\n")
    program.chmod(0o755)


def test_the_password_goes_by_the_environment_and_a_failed_dump_changes_nothing(
        populated, tmp_path, capsys, monkeypatch):
    log = tmp_path / "argv"
    _fake_pg_dump(tmp_path / "bin", log, exit_code=1)
    monkeypatch.setenv("PATH", f"{tmp_path / 'bin'}:{os.environ['PATH']}")
    assert main(["db", "downgrade", "0003", "--yes", "--db", populated]) == 2
    err = capsys.readouterr().err
    assert "the schema was not changed: pg_dump failed (pg_dump: error: server version " \
           "mismatch)" in err and "--no-backup" in err
    seen = log.read_text().splitlines()
    assert seen[-1] == f"PGPASSWORD={PASSWORD}"
    assert not any(PASSWORD in arg for arg in seen[:-1])
    assert any(arg.startswith("--dbname=") and "dbname=" in arg for arg in seen)
    assert list(server_dump.backup_folder().iterdir()) == []  # the empty file went
    db = open_store(populated)
    assert current_revision(db) == head_revision()
    db.dispose()


def test_without_pg_dump_the_downgrade_is_refused_unless_no_backup(
        populated, capsys, monkeypatch):
    monkeypatch.setattr(server_dump.shutil, "which", lambda _name: None)
    monkeypatch.setattr(server_dump, "distribution_folders", lambda: [])
    db = open_store(populated)
    rows = _rows(db)
    assert main(["db", "downgrade", "0003", "--yes", "--db", populated]) == 2
    err = capsys.readouterr().err
    assert "no pg_dump" in err and "--no-backup" in err
    assert current_revision(db) == head_revision() and _rows(db) == rows
    assert main(["db", "downgrade", "0003", "--yes", "--no-backup", "--db", populated]) == 0
    out = capsys.readouterr().out
    assert "dropped the certificates" in out and ", 2 hysteresis sweeps" in out
    assert out.splitlines()[0].endswith(
        "; no backup (--no-backup)")
    assert current_revision(db) == "0003"
    db.dispose()
