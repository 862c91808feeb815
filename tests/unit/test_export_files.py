"""The palette's export of a sweep (slopetui.sweeps.export_files): a new file each time,
never one that replaces another, not even when two exports of one sweep write at once."""

from __future__ import annotations

import threading
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import IO

import pytest

from slopetui.sweeps import export_files
from slopetui.sweeps.export import write_csv
from tests.support import submit_quick


def test_two_exports_at_once_take_two_names(db, tmp_path: Path,
                                            monkeypatch: pytest.MonkeyPatch) -> None:
    """The first export is held while it writes; the second, started meanwhile, finishes
    first. Each keeps its own file: a name picked before writing would be picked by both,
    and the first to finish would be replaced by the other."""
    submit_quick(db, 3)
    folder = tmp_path / "figures"
    folder.mkdir()
    writing, release = threading.Event(), threading.Event()
    calls: list[int] = []

    def held_write_csv(runs: object, out: IO[str]) -> int:
        calls.append(1)
        if len(calls) == 1:  # the first export: held until the second has finished
            writing.set()
            assert release.wait(10)
        return write_csv(runs, out)  # type: ignore[arg-type]

    monkeypatch.setattr(export_files, "write_csv", held_write_csv)
    with ThreadPoolExecutor(2) as pool:
        first = pool.submit(export_files.export_sweep, db, 1, "csv", folder)
        assert writing.wait(10)
        second = export_files.export_sweep(db, 1, "csv", folder)
        release.set()
        first_done = first.result(10)
    assert {first_done.path.name, second.path.name} == {"sweep-1-runs.csv", "sweep-1-runs-2.csv"}
    assert sorted(p.name for p in folder.iterdir()) == ["sweep-1-runs-2.csv", "sweep-1-runs.csv"]
    for done in (first_done, second):
        assert done.runs == 3
        assert len(done.path.read_text().splitlines()) == 4  # the header and three runs


def test_an_export_never_replaces_an_earlier_file(db, tmp_path: Path) -> None:
    submit_quick(db, 2)
    (tmp_path / "sweep-1-runs.json").write_text("kept\n")
    done = export_files.export_sweep(db, 1, "json", tmp_path)
    assert done.path == tmp_path / "sweep-1-runs-2.json" and done.runs == 2
    assert (tmp_path / "sweep-1-runs.json").read_text() == "kept\n"
