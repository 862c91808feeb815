"""The SQL console's history file, without the UI (slopetui.sql_history)."""

from __future__ import annotations

import json
import stat
from pathlib import Path

from slopetui.sql_history import (
    HISTORY_LIMIT,
    History,
    default_path,
    merge_history,
    read_history,
    write_history,
)


def test_history_file(tmp_path: Path) -> None:
    path = tmp_path / "deep" / "sql_history"
    queries = merge_history(["SELECT\n  1", " SELECT 2 ", "SELECT\n  1"],
                            [f"SELECT {i}" for i in range(300)])
    assert queries[:3] == ["SELECT\n  1", "SELECT 2", "SELECT 0"]
    assert len(queries) == HISTORY_LIMIT
    write_history(path, queries)
    assert read_history(path) == queries
    path.write_text(path.read_text() + "not json\n" + json.dumps(7) + "\n")
    assert read_history(path) == queries


def test_the_history_file_is_private(tmp_path: Path) -> None:
    path = tmp_path / "new" / "sql_history"
    write_history(path, ["SELECT 1"])
    assert stat.S_IMODE(path.stat().st_mode) == 0o600
    old = tmp_path / "old_history"
    old.write_text(json.dumps("SELECT 2") + "\n")
    old.chmod(0o644)
    write_history(old, ["SELECT 3"])  # a rewrite replaces it with a private file
    assert stat.S_IMODE(old.stat().st_mode) == 0o600


def test_a_missing_file_is_an_empty_history(tmp_path: Path) -> None:
    history = History(tmp_path / "none")
    assert history.read() == []
    assert not history.merge_read([])  # nothing added meanwhile: nothing to save


def test_queries_added_before_the_file_is_read_are_kept(tmp_path: Path) -> None:
    path = tmp_path / "sql_history"
    write_history(path, ["SELECT 1", "SELECT 2"])
    path.chmod(0o644)
    history = History(path)
    assert not history.add("SELECT 3")  # not saved yet: that would drop the file's
    assert history.read() == ["SELECT 1", "SELECT 2"]
    assert stat.S_IMODE(path.stat().st_mode) == 0o600  # reading made it private
    assert history.merge_read(["SELECT 1", "SELECT 2"])  # the new query needs saving
    assert history.queries == ["SELECT 3", "SELECT 1", "SELECT 2"]
    history.save()
    assert read_history(path) == history.queries
    assert history.add("SELECT 1")  # once read, every query can be saved at once
    assert history.queries == ["SELECT 1", "SELECT 3", "SELECT 2"]


def test_the_default_place() -> None:
    assert default_path().name == "sql_history"
    assert default_path().parent.name == "slopetui"
