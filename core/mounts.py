"""Which file system holds a path, read from the kernel's mount table (Linux's
/proc/self/mountinfo), and whether it is one that several hosts share over a network.

Two things must not live on such a file system, and both default to the home directory,
which is on NFS on most clusters: numba's kernel cache (every node writing into one
cache at start corrupts it, numba#4807 and #10128: core.jit_cache moves it to node-local
storage) and a SQLite store (its write-ahead log needs shared memory that a network file
system does not give, and its file locks are unsafe there: slopetui's store refuses it).
"""

from __future__ import annotations

import os
from pathlib import Path

#: The kernel's mount table of this process (tests point it at a file of their own).
MOUNTINFO = Path("/proc/self/mountinfo")

#: Types of file systems shared between hosts over a network: NFS and SMB, the parallel
#: file systems of HPC centres (Lustre, GPFS/Spectrum Scale, BeeGFS, CephFS, GlusterFS),
#: AFS, FUSE clients of remote hosts (sshfs), and 9p (WSL 2's Windows drives, where
#: SQLite's WAL is known to fail).
NETWORK_TYPES = frozenset({
    "nfs", "nfs4", "cifs", "smb3", "smbfs", "ncpfs", "afs", "lustre", "gpfs", "beegfs",
    "ceph", "glusterfs", "fuse.glusterfs", "fuse.sshfs", "fuse.ceph", "fuse.cephfs",
    "fuse.s3fs", "9p",
})


def _unescape(field: str) -> str:
    r"""A mountinfo path field: the kernel writes space, tab, newline and backslash as
    octal escapes (\040, \011, \012, \134)."""
    out, i = [], 0
    while i < len(field):
        if field[i] == "\\" and field[i + 1:i + 4].isdigit():
            out.append(chr(int(field[i + 1:i + 4], 8)))
            i += 4
        else:
            out.append(field[i])
            i += 1
    return "".join(out)


def mounts() -> list[tuple[str, str]]:
    """(mount point, file-system type) of every mount, in the kernel's order (a later
    mount on the same point hides an earlier one); empty where there is no mount table
    (not Linux)."""
    try:
        text = MOUNTINFO.read_text(encoding="utf-8", errors="replace")
    except OSError:
        return []
    table = []
    for line in text.splitlines():
        head, sep, tail = line.partition(" - ")
        fields = head.split()
        if sep and len(fields) >= 5 and tail:
            table.append((_unescape(fields[4]), tail.split()[0]))
    return table


def _existing(path: Path) -> Path:
    """The path resolved, or its nearest ancestor that exists (a file about to be made)."""
    path = Path(os.path.abspath(path))
    while not path.exists() and path != path.parent:
        path = path.parent
    return path.resolve()


def filesystem_type(path: Path) -> str | None:
    """The type of the file system that holds ``path`` (e.g. "ext4", "nfs4"), or None if
    it cannot be told."""
    where = str(_existing(path))
    best, kind = -1, None
    for point, fstype in mounts():
        inside = where == point or where.startswith(point.rstrip("/") + "/")
        if inside and len(point) >= best:  # the longest, and the latest of equals
            best, kind = len(point), fstype
    return kind


def network_filesystem(path: Path) -> str | None:
    """The type of the network file system that holds ``path``, or None if it is local
    (or cannot be told)."""
    kind = filesystem_type(path)
    return kind if kind in NETWORK_TYPES else None
