"""A file written whole or not at all: into a new file beside it, synced, then renamed
over the target, so that a failure (a full disk, a database error, Ctrl-C, kill -9) leaves
no partial file and an older file as it was. The one writer of ``slopetui export -o`` and
the application's exports.

The new file gets the mode the target would get: the old file's, or 0o666 less the umask
(mkstemp's 0o600 would survive the rename). A shared leaf: it imports nothing of slopetui.
(The figures stage several files before renaming any, so that a figure and its data
appear together: ``slopetui.figures.output.write``, the same steps for a set of files.)
"""

from __future__ import annotations

import io
import os
import stat
import tempfile
from collections.abc import Callable
from itertools import count
from pathlib import Path
from typing import IO


def write_whole(target: Path, write: Callable[[IO[bytes]], int]) -> int:
    """Call ``write(out)`` on a new binary file beside ``target``, sync it, and rename it
    over ``target``; returns what ``write`` returned. Raises what the write or the file
    system raised (OSError), leaving no temporary file behind."""
    mode = stat.S_IMODE(target.stat().st_mode) if target.is_file() else 0o666 & ~_umask()
    temp, n = _staged(target.parent, target.name, mode, write)
    try:
        os.replace(temp, target)
    except BaseException:
        temp.unlink(missing_ok=True)
        raise
    return n


def write_new(folder: Path, stem: str, ext: str,
              write: Callable[[IO[bytes]], int]) -> tuple[Path, int]:
    """write_whole into the first free name of first_free(folder, stem, ext), the name
    claimed only once the file is whole and claimed atomically: two writers at once (two
    key presses, two applications) get two names, and neither replaces the other's file.
    Returns the path written and what ``write`` returned."""
    temp, n = _staged(folder, f"{stem}.{ext}", 0o666 & ~_umask(), write)
    try:
        while True:
            path = first_free(folder, stem, ext)
            try:
                # a hard link fails with EEXIST where the name was taken since first_free
                # looked, where os.replace would overwrite it
                os.link(temp, path)
                return path, n
            except FileExistsError:
                continue
            except OSError:  # a file system without hard links: reserve the name, then fill it
                try:
                    os.close(os.open(path, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o600))
                except FileExistsError:
                    continue
                os.replace(temp, path)
                return path, n
    finally:
        temp.unlink(missing_ok=True)


def _staged(folder: Path, name: str, mode: int,
            write: Callable[[IO[bytes]], int]) -> tuple[Path, int]:
    """``write(out)`` into a new hidden file in ``folder`` (named after ``name``), synced and
    given ``mode``: the temporary file's path and what ``write`` returned. Leaves no file
    behind when it raises."""
    # the name cut short: a name near the limit of 255 bytes must still fit
    fd, temp = tempfile.mkstemp(dir=folder, prefix=f".{name[:64]}.", suffix=".part")
    try:
        with os.fdopen(fd, "wb") as out:
            n = write(out)
            out.flush()
            os.fsync(out.fileno())
        os.chmod(temp, mode)
    except BaseException:
        Path(temp).unlink(missing_ok=True)
        raise
    return Path(temp), n


def first_free(folder: Path, stem: str, ext: str,
               taken: Callable[[Path], bool] = Path.exists) -> Path:
    """folder/stem.ext, or stem-2.ext, stem-3.ext... the first that ``taken`` says is free
    (by default: no file by that name): what a key press writes never replaces an earlier
    file."""
    for n in count(1):
        path = folder / (f"{stem}.{ext}" if n == 1 else f"{stem}-{n}.{ext}")
        if not taken(path):
            return path
    raise AssertionError("unreachable")


def as_text(out: IO[bytes], write: Callable[[IO[str]], int]) -> int:
    """``write`` text into the binary file ``out`` (UTF-8, newlines as written); ``out``
    stays open for its owner (write_whole syncs and closes it)."""
    text = io.TextIOWrapper(out, encoding="utf-8", newline="")
    try:
        return write(text)
    finally:
        text.flush()
        text.detach()


def _umask() -> int:
    mask = os.umask(0)  # the only way to read it: set it, and set it back at once
    os.umask(mask)
    return mask
