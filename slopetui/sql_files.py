"""A read-only statement's rows as CSV or JSON, the same for both faces: ``slopetui sql
--csv | --json`` to stdout, ``slopetui sql --out FILE`` and the application's console
(ctrl+s) to a file. No UI here; the rows come from ``slopetui.sql_results``.

Streams write rows as they come (``start(columns)``, ``write(chunk)``..., ``finish()``):
a CSV with its header line, JSON as one object a line (stdout: ``jq`` reads it as it
arrives) or, into a ``.json`` file, a list of them, one a line (strict JSON, what
``slopetui export --json`` writes). Values stay as stored; a NaN or ±inf float is
``null`` in JSON (``slopetui.json_text``), its text in CSV. A file is written whole or not
at all (``slopetui.whole_files``): a query that fails half way leaves no file, and an
older file as it was.

Light on purpose: ``slopetui --help`` builds the ``sql`` parser, which imports the CLI's
module, which imports this.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import IO, TypeVar

from slopetui.display_text import TextOut
from slopetui.json_text import json_text
from slopetui.store.read_query import Row
from slopetui.whole_files import as_text, write_new, write_whole

#: A file's format by its extension (case ignored).
FILE_FORMATS = ("csv", "json")

ResultT = TypeVar("ResultT")


class NothingToSave(Exception):
    """The statement returns no rows at all (not even a header): there is nothing to
    write, and no file is left."""


def file_format(path: str | Path, field: str = "--out") -> str:
    """``csv`` or ``json``, by the extension of ``path``; a ValueError naming ``field`` and
    the allowed extensions otherwise."""
    ext = Path(path).suffix.lower().removeprefix(".")
    if ext not in FILE_FORMATS:
        allowed = " or ".join(f".{f}" for f in FILE_FORMATS)
        raise ValueError(f"{field} = {str(path)!r}: the extension names the format: allowed "
                         f"a file name ending in {allowed}")
    return ext


def _json_value(value: object) -> object:
    return None if isinstance(value, float) and not math.isfinite(value) else value


def _json_row(columns: Sequence[str], row: Row) -> str:
    return json_text({c: _json_value(v) for c, v in zip(columns, row, strict=True)}, default=str)


class RowStream:
    """Rows out as they come: start(columns), write(chunk)..., finish() once every row
    asked for was read, else stop() (the rows so far stay written, a stream's last line
    complete)."""

    def __init__(self, out: TextOut) -> None:
        self.out = out
        self.started = False
        self.columns: list[str] = []

    def start(self, columns: list[str]) -> None:
        self.columns = columns
        self.started = True

    def write(self, rows: list[Row]) -> None:
        raise NotImplementedError

    def finish(self) -> None:
        self.stop()

    def stop(self) -> None:
        self.out.flush()


class CsvStream(RowStream):
    def start(self, columns: list[str]) -> None:
        super().start(columns)
        self.csv = csv.writer(self.out, lineterminator="\n")
        self.csv.writerow(columns)

    def write(self, rows: list[Row]) -> None:
        self.csv.writerows([tuple(map(_csv_cell, row)) for row in rows])
        self.out.flush()  # a reader downstream sees rows as they arrive


def _csv_cell(value: object) -> object:
    """A JSON column's value as JSON text: PostgreSQL's driver gives it as a dict or a list,
    which the csv module would write as Python's repr ({'x': None}); SQLite gives the text
    as stored."""
    if isinstance(value, (dict, list)):
        return json_text(value, ensure_ascii=False, default=str)
    return value


class JsonLinesStream(RowStream):
    """One JSON object a line (``slopetui sql --json``)."""

    def write(self, rows: list[Row]) -> None:
        for row in rows:
            self.out.write(_json_row(self.columns, row) + "\n")
        self.out.flush()


class JsonListStream(RowStream):
    """A JSON list of one object per row, one a line: a ``.json`` file that every JSON
    reader takes whole."""

    def start(self, columns: list[str]) -> None:
        super().start(columns)
        self.out.write("[")
        self.first = True

    def write(self, rows: list[Row]) -> None:
        for row in rows:
            self.out.write(("\n" if self.first else ",\n") + _json_row(self.columns, row))
            self.first = False

    def finish(self) -> None:
        self.out.write("]\n" if self.first else "\n]\n")
        super().finish()


#: The stream that writes each file format.
FILE_STREAMS: dict[str, type[RowStream]] = {"csv": CsvStream, "json": JsonListStream}


def _filled(fmt: str, fill: Callable[[RowStream], ResultT],
            result: list[ResultT]) -> Callable[[IO[bytes]], int]:
    """What writes a file of ``fmt``: ``fill``'s stream started, filled and finished, what
    ``fill`` returned appended to ``result``."""

    def text(out: IO[str]) -> int:
        stream = FILE_STREAMS[fmt](out)
        result.append(fill(stream))
        if not stream.started:
            raise NothingToSave("the statement returns no rows: nothing to save")
        stream.finish()
        return 0

    return lambda out: as_text(out, text)


def save(path: Path, fmt: str, fill: Callable[[RowStream], ResultT]) -> ResultT:
    """Write ``path`` whole or not at all as ``fmt`` (one of FILE_FORMATS): ``fill(stream)``
    starts the stream and writes its rows (it may raise: then no file is left, and an older
    one stays as it was); the stream is finished after it. Returns what ``fill`` returned.
    Raises NothingToSave when ``fill`` never started the stream, OSError as the file system
    raised it."""
    result: list[ResultT] = []
    write_whole(path, _filled(fmt, fill, result))
    return result[0]


def _rows_read(columns: list[str], rows: Sequence[Row]) -> Callable[[RowStream], int]:
    """A fill (see save) that writes rows already read: the number of rows written."""

    def fill(stream: RowStream) -> int:
        stream.start(columns)
        stream.write(list(rows))
        return len(rows)

    return fill


def save_rows(path: Path, columns: list[str], rows: Sequence[Row]) -> int:
    """Rows already read (the console's) written to ``path`` as its extension says:
    the number of rows written."""
    return save(path, file_format(path), _rows_read(columns, rows))


def save_new_results(folder: Path, fmt: str, columns: list[str],
                     rows: Sequence[Row]) -> tuple[Path, int]:
    """Rows already read (the console's) written whole to folder/sql-results.fmt, or -2,
    -3... the first that does not exist when the file is complete, claimed atomically
    (whole_files.write_new): a key press never replaces an earlier file, not even one a
    second press is writing at the same time. The path and the number of rows written."""

    result: list[int] = []
    path, _ = write_new(folder, "sql-results", fmt, _filled(fmt, _rows_read(columns, rows), result))
    return path, result[0]
