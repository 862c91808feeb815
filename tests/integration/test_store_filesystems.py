"""The store on real file systems of its own (tmpfs mounts, which need root): a read-only
one and a full one are named with their cause (the rest of the store's data safety, in one
process: tests/unit/test_store_safety.py)."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import pytest
from sqlalchemy import select

from slopetui.cli import main
from slopetui.store.models import Run
from slopetui.store.open import open_store


@pytest.fixture
def tmpfs(tmp_path):
    """A small file system of our own (a full disk, a read-only one): needs root, which
    CI and the development machines are."""
    if os.geteuid() != 0:
        pytest.skip("mounting a tmpfs needs root")
    mounts = []

    def make(name: str, options: str) -> Path:
        point = tmp_path / name
        point.mkdir()
        subprocess.run(["mount", "-t", "tmpfs", "-o", options, "tmpfs", str(point)],
                       check=True)
        mounts.append(point)
        return point

    yield make
    for point in mounts:
        subprocess.run(["umount", "-l", str(point)], check=False)


def test_a_read_only_file_system_is_named(tmpfs, capsys):
    point = tmpfs("ro", "size=1m,ro")
    assert main(["status", "--db", f"sqlite:///{point / 'x.db'}"]) == 2
    assert f"{point} is on a read-only file system" in capsys.readouterr().err


def test_a_full_disk_is_named_and_nothing_is_half_written(tmpfs, capsys):
    # room for a new store (168 KiB at revision 0016, with its journal while it migrates)
    # and not for 4000 runs
    point = tmpfs("full", "size=400k")
    url = f"sqlite:///{point / 'x.db'}"
    assert main(["status", "--db", url]) == 0
    capsys.readouterr()
    code = main(["submit", "--x", "k=1:20:4000", "--yes", "--t-end", "100", "--window",
                 "50", "--db", url])
    assert code == 1
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "the disk is full" in err and "x.db" in err
    with open_store(url).sessions() as s:
        assert s.scalars(select(Run)).first() is None  # the submit was rolled back whole
