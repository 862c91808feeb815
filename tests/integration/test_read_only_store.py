"""A SQLite store this user cannot write (another user's folder): the read commands and
the notebook API open it read-only and say so in one line; writes are refused with their
cause and change nothing (slopetui.store.database's module docstring says how).

The tests run as root, for whom permissions do not apply: the commands run in a process
that has dropped root's power to ignore them (setpriv --bounding-set=-dac_override...), as
root but bound by the files' modes as any user. Without root, the files' modes bind the
test's own processes, and no setpriv is needed.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import sqlite3
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

import migrations
from slopetui.store.open import open_store
from tests.support import submit_quick

#: What makes root obey the files' modes: no capability to override them.
DROP = ["setpriv", "--bounding-set=-dac_override,-dac_read_search,-fowner"]
NOTE = "store is read-only (no permission to write in {folder}): opened for reading"


def as_user(*argv: str) -> subprocess.CompletedProcess[str]:
    """argv in a fresh process bound by the files' modes."""
    prefix: list[str] = []
    if os.geteuid() == 0:
        if shutil.which("setpriv") is None:
            pytest.fail("running as root: setpriv (util-linux) is needed to drop the power "
                        "to ignore file modes")
        prefix = DROP
    return subprocess.run([*prefix, *argv], capture_output=True, text=True, timeout=300)


def slopetui(*args: str) -> subprocess.CompletedProcess[str]:
    return as_user(sys.executable, "-m", "slopetui", *args)


def lock(folder: Path) -> None:
    """The folder and its files as another user's: readable, not writable."""
    for path in [*folder.iterdir(), folder]:
        if os.geteuid() == 0:
            os.chown(path, 65534, 65534)  # nobody
        path.chmod(0o555 if path.is_dir() else 0o444)


def digest(folder: Path) -> dict[str, str]:
    return {p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in sorted(folder.iterdir())}


@pytest.fixture
def locked(tmp_path: Path) -> Iterator[tuple[Path, str]]:
    """A store of 5 queued runs in a folder this user cannot write; its URL."""
    folder = tmp_path / "theirs"
    folder.mkdir()
    url = f"sqlite:///{folder / 'store.db'}"
    db = open_store(url)
    submit_quick(db, 5)
    db.dispose()
    assert not (folder / "store.db-wal").exists()  # the last connection removed the log
    lock(folder)
    probe = as_user(sys.executable, "-c", f"open({str(folder / 'x')!r}, 'w')")
    assert probe.returncode != 0 and "PermissionError" in probe.stderr  # really unwritable
    yield folder, url
    folder.chmod(0o755)


def test_read_commands_open_it_read_only_and_say_so(locked):
    folder, url = locked
    before = digest(folder)
    note = NOTE.format(folder=folder) + ", as a snapshot (no writer has it open)"
    for args, expected in ((["status"], "0/5"), (["runs"], "queued"),
                           (["export", "1", "--csv"], "id,sweep_id"),
                           (["sql", "SELECT count(*) AS n FROM runs", "--csv"], "n\n5\n"),
                           (["show", "1", "--width", "60", "--height", "14", "--color", "never"],
                            "sweep 1"),
                           (["workers"], "no worker pool")):
        done = slopetui(*args, "--db", url)
        assert done.returncode == 0, (args, done.stderr)
        assert expected in done.stdout, (args, done.stdout)
        assert done.stderr == f"slopetui {args[0]}: {note}\n", (args, done.stderr)
    notebook = as_user(sys.executable, "-c", "import slopetui\n"
                       f"with slopetui.open_store({url!r}) as s: print(len(s.runs(1)))")
    assert notebook.returncode == 0, notebook.stderr
    assert notebook.stdout == "5\n" and notebook.stderr == f"slopetui.open_store: {note}\n"
    assert digest(folder) == before  # nothing written, not even a -wal or -shm file


def test_writes_are_refused_with_their_cause_and_change_nothing(locked):
    folder, url = locked
    before = digest(folder)
    submit = slopetui("submit", "--x", "k=1:2:2", "--db", url)
    assert submit.returncode != 0 and submit.stdout == ""
    assert submit.stderr.count("\n") == 1 and f"no permission to write in {folder}" in submit.stderr
    refused = slopetui("sql", "DELETE FROM runs", "--db", url)
    assert refused.returncode == 2
    assert "refused: the store is opened read-only" in refused.stderr
    assert digest(folder) == before


def test_beside_a_live_writer_it_reads_the_writers_commits(locked):
    """A writer (the owner's pool) has the store open: its -shm exists, and the reader
    reads through it (mode=ro), not a snapshot of the file alone."""
    folder, url = locked
    writer = subprocess.Popen(
        [sys.executable, "-c", "import sqlite3, sys, time\n"
         f"c = sqlite3.connect({str(folder / 'store.db')!r}, isolation_level=None)\n"
         "c.execute('PRAGMA journal_mode = WAL')\n"
         "c.execute('PRAGMA wal_autocheckpoint = 0')\n"  # the commit stays in the -wal
         "c.execute(\"UPDATE runs SET status = 'cancelled' WHERE id = 1\")\n"
         "print('ready', flush=True)\n"
         "sys.stdin.read()\n"], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    try:
        assert writer.stdout is not None and writer.stdout.readline() == "ready\n"
        assert (folder / "store.db-shm").exists() and (folder / "store.db-wal").stat().st_size
        done = slopetui("sql", "SELECT status FROM runs WHERE id = 1", "--csv", "--db", url)
        assert done.returncode == 0, done.stderr
        assert done.stdout == "status\ncancelled\n"
        assert done.stderr == f"slopetui sql: {NOTE.format(folder=folder)}\n"
    finally:
        writer.communicate("", timeout=30)


def test_an_old_schema_it_cannot_migrate_is_refused_saying_why(tmp_path):
    folder = tmp_path / "old"
    folder.mkdir()
    url = f"sqlite:///{folder / 'store.db'}"
    open_store(url).dispose()
    with sqlite3.connect(folder / "store.db") as conn:
        conn.execute("UPDATE alembic_version SET version_num = '0001'")
    conn.close()
    lock(folder)
    done = slopetui("status", "--db", url)
    assert done.returncode != 0 and done.stdout == ""
    assert done.stderr.count("\n") == 1, done.stderr
    assert (f"its schema is at revision 0001, not {migrations.HEAD}" in done.stderr
            and f"no permission to write in {folder}" in done.stderr)
    folder.chmod(0o755)


def test_a_log_left_by_a_crashed_writer_is_not_ignored(locked):
    """Without its -shm, a -wal with transactions can only be recovered by a writer: an
    immutable read would silently miss them. An empty one is nothing to miss."""
    folder, url = locked
    folder.chmod(0o755)
    (folder / "store.db-wal").write_bytes(b"\0" * 32)
    lock(folder)
    done = slopetui("status", "--db", url)
    assert done.returncode == 2 and done.stdout == ""
    assert done.stderr.count("\n") == 1 and "only a writer can recover" in done.stderr
    folder.chmod(0o755)
    (folder / "store.db-wal").write_bytes(b"")
    lock(folder)
    done = slopetui("status", "--db", url)
    assert done.returncode == 0 and "as a snapshot" in done.stderr, done.stderr


def test_a_file_it_cannot_write_in_a_folder_it_can_is_read_beside_writers(locked):
    """The reader can make the -shm itself: mode=ro, not a snapshot."""
    folder, url = locked
    folder.chmod(0o777)  # anyone may write the folder; the file stays read-only (444)
    done = slopetui("sql", "SELECT count(*) AS n FROM runs", "--csv", "--db", url)
    assert done.returncode == 0 and done.stdout == "n\n5\n", done.stderr
    assert done.stderr == (f"slopetui sql: store is read-only (no permission to write "
                           f"{folder / 'store.db'}): opened for reading\n")
