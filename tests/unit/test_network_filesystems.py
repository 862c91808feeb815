"""Cluster home directories: the kernel cache moves off a network
file system to node-local storage, and a SQLite store on one is refused, pointing to
PostgreSQL. The mount table is the kernel's (core.mounts.MOUNTINFO); here a file of the
test's own says which folder is NFS, as on a cluster."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import pytest

from core import jit_cache, mounts
from slopetui.cli import main
from slopetui.store.database import Database
from slopetui.store.failures import StoreError


def _mount_table(tmp_path: Path, network: Path, kind: str = "nfs4") -> Path:
    """A mountinfo where / is ext4 and ``network`` (a folder with a space in its name, as
    the kernel escapes it) is ``kind``."""
    escaped = str(network).replace(" ", "\\040")
    table = tmp_path / "mountinfo"
    table.write_text(
        "22 27 0:21 / /proc rw,relatime - proc proc rw\n"
        "27 1 8:1 / / rw,relatime - ext4 /dev/sda1 rw\n"
        f"90 27 0:50 / {escaped} rw,relatime - {kind} server:/export/home rw,vers=4.2\n")
    return table


@pytest.fixture
def nfs_home(tmp_path, monkeypatch) -> Path:
    home = tmp_path / "home of user"
    home.mkdir()
    monkeypatch.setattr(mounts, "MOUNTINFO", _mount_table(tmp_path, home))
    return home


def test_the_mount_table_is_read_with_its_escapes(nfs_home):
    assert mounts.filesystem_type(nfs_home / "a" / "b.db") == "nfs4"  # not there yet
    assert mounts.network_filesystem(nfs_home) == "nfs4"
    assert mounts.filesystem_type(nfs_home.parent) == "ext4"
    # a sibling whose name starts like the mount point is not inside it
    sibling = nfs_home.with_name(nfs_home.name + "2")
    assert mounts.network_filesystem(sibling) is None


def test_this_machines_own_mount_table_is_read():
    if not Path("/proc/self/mountinfo").exists():
        pytest.skip("no /proc/self/mountinfo: not Linux")
    assert mounts.filesystem_type(Path("/proc/self")) == "proc"


def test_the_kernel_cache_leaves_a_network_home(nfs_home, monkeypatch):
    monkeypatch.delenv(jit_cache.KERNEL_CACHE_ENV, raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(nfs_home / ".cache"))
    jit_cache._node_local.cache_clear()
    folder = jit_cache.cache_dir()
    assert not folder.is_relative_to(nfs_home)
    assert folder.is_relative_to(Path(tempfile.gettempdir()))
    base = folder.parent
    assert base.stat().st_uid == os.getuid() and not base.stat().st_mode & 0o077


def test_the_kernel_cache_stays_on_a_local_disk_and_where_it_is_told(tmp_path, monkeypatch):
    monkeypatch.setattr(mounts, "MOUNTINFO", _mount_table(tmp_path, tmp_path / "elsewhere"))
    monkeypatch.delenv(jit_cache.KERNEL_CACHE_ENV, raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    assert jit_cache.cache_dir().parent == tmp_path / "cache" / "slopetui" / "numba"
    monkeypatch.setenv(jit_cache.KERNEL_CACHE_ENV, str(tmp_path / "scratch"))
    assert jit_cache.cache_dir().parent == tmp_path / "scratch"


def test_a_private_cache_folder_that_another_may_write_is_not_used(tmp_path, monkeypatch):
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    planted = tmp_path / f"slopetui-kernels-{os.getuid()}"
    planted.mkdir(mode=0o777)
    planted.chmod(0o777)  # world-writable: someone could plant pickles in it
    jit_cache._node_local.cache_clear()
    try:
        folder = jit_cache._node_local()
    finally:
        jit_cache._node_local.cache_clear()
    assert folder != planted and not folder.stat().st_mode & 0o077


def test_a_sqlite_store_on_a_network_file_system_is_refused(nfs_home, capsys):
    target = nfs_home / "runs.db"
    with pytest.raises(StoreError, match=r"network file system \(nfs4\).*PostgreSQL"):
        Database(f"sqlite:///{target}")
    assert not target.exists()  # nothing written
    assert main(["status", "--db", f"sqlite:///{target}"]) == 2
    err = capsys.readouterr().err
    assert "db serve" in err and str(target) in err and not target.exists()
