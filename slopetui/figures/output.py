"""A drawing and the files it becomes: the figure (PDF, SVG or PNG, by the extension) and
its data as CSV beside it.

Decisions:

* **Validate first.** ``check_output`` refuses a bad target (unknown extension, missing or
  unwritable folder, a folder as the target) before anything is computed or written, so
  that a mistyped path costs nothing: the figure command calls it before it loads a sweep
  or recomputes a run.
* **Atomic files.** Each file is written to a hidden temporary file in the target's
  folder (same file system, so ``os.replace`` is a rename) and flushed to disk, then
  renamed over the target. All files are staged before the first rename: a failure or an
  interruption while drawing or writing leaves the folder as it was, with no partial
  file and no temporary file. Once the renames start, each file is whole, old or new
  (there is no atomic rename of several files).
* **rc settings at save time only**, with ``matplotlib.rc_context``: never the global
  rcParams, which a notebook importing this module owns. ``pdf.fonttype`` 42 (and
  ``ps.fonttype``) embed TrueType fonts (/FontFile2) instead of Type 3 outlines: text stays
  editable in Illustrator and Inkscape, and journals' checks accept it. SVG keeps its
  default ``svg.fonttype`` 'path' (text as outlines), which renders the same everywhere.
  rc_context changes the process-wide rcParams while it is active, so saves are
  serialised by a lock: two of the TUI's worker threads saving at once cannot restore
  each other's settings midway.
* **Reproducible files.** The PDF and SVG carry Creator "slopetui <version>" and no
  creation date, and SVG ids are salted with a fixed string (matplotlib's default salt is
  random per process): the same data gives byte-identical PDF and SVG files, which diff
  and cache like any other output.
* **Resolution.** PNG_DPI 200: a 6.4 x 4.8 in diagram is 1280 x 960 pixels, sharp on a
  screen and in a draft. Rasterised parts of a PDF or SVG (the cells of a phase
  diagram, dense traces) take RASTER_DPI 300, the resolution journals ask of images.
* **CSV cells** as ``slopetui export --csv`` writes them, by its own function
  (slopetui.sweeps.export.cell): NaN and infinities as nan, inf, -inf; None (a value that
  does not exist) as an empty cell; lists as JSON; numpy values as the numbers they hold.
* **What it was computed at** (a drawing's ``facts``: slopetui.figures.figure_facts)
  travels with every file. The figure's metadata: the facts as one line of strict JSON
  (``Keywords`` of a PDF or SVG, ``slopetui`` of a PNG) and as one line of text
  (``Subject`` of a PDF, ``Description`` of an SVG or PNG). Each CSV: one comment line
  before its header, ``# slopetui: <the JSON>``, rather than columns, which would repeat
  the same 20 values on each of thousands of rows of traces (read it with
  ``pandas.read_csv(path, skiprows=1)``). The caption (``write(caption=True)``): the text
  line in a strip saved under the figure, in two lines (add_caption; the panels keep their
  size).
"""

from __future__ import annotations

import contextlib
import csv
import os
import secrets
import threading
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import IO, TYPE_CHECKING, Any

from slopetui import __version__
from slopetui.display_text import terminal_safe
from slopetui.json_text import json_text
from slopetui.sweeps.export import cell

if TYPE_CHECKING:  # matplotlib is imported when a figure is drawn or saved, not before
    from matplotlib.figure import Figure
    from matplotlib.transforms import Bbox

__all__ = ["CREATOR", "FORMATS", "PNG_DPI", "RASTER_DPI", "Drawing", "FigureError", "Table",
           "check_output", "data_paths", "write"]

#: The figure formats, by extension (without the dot).
FORMATS: tuple[str, ...] = ("pdf", "svg", "png")
#: Pixels per inch of a PNG (module docstring).
PNG_DPI = 200
#: Pixels per inch of the rasterised parts of a PDF or SVG (module docstring).
RASTER_DPI = 300
#: The Creator of every file's metadata.
CREATOR = f"slopetui {__version__}"
#: A fixed salt for SVG element ids (matplotlib's default is random: module docstring).
SVG_HASH_SALT = "slopetui"
#: Fonts in PDF (and PostScript) files: 42, TrueType embedded (module docstring).
FONTTYPE = 42
#: The comment line that opens each CSV beside a figure: this, then the facts as JSON.
FACTS_PREFIX = "# slopetui: "
#: Temporary names keep at most this many bytes of the target's name, so that
#: ".<name>.<8 hex>.tmp" stays within the usual 255-byte limit of a file name.
TEMP_NAME_KEEP = 200

_SAVE_LOCK = threading.Lock()


class FigureError(ValueError):
    """A user error: the message names the field (e.g. "--output") or the path, and what
    is allowed. ``field`` is the field, when there is one."""

    def __init__(self, message: str, field: str | None = None) -> None:
        super().__init__(message)
        self.field = field


@dataclass(frozen=True)
class Table:
    """The data behind a figure: ``header`` names the columns, each row one tuple."""

    name: str
    header: tuple[str, ...]
    rows: list[tuple[Any, ...]]


@dataclass(frozen=True)
class Drawing:
    """A figure and its data tables (the first one is the figure's main data), and what
    it was computed at (``facts``, slopetui.figures.figure_facts; None: not known)."""

    figure: Figure
    tables: tuple[Table, ...]
    facts: Mapping[str, Any] | None = None


def _allowed() -> str:
    return ", ".join(f".{f}" for f in FORMATS)


def _format_of(path: Path, field: str) -> str:
    ext = path.suffix.lower()
    if not ext:
        raise FigureError(f"{field}: no extension in {terminal_safe(path)}; name the format "
                          f"with one (allowed: {_allowed()})", field)
    if ext[1:] not in FORMATS:
        raise FigureError(f"{field}: unknown extension {terminal_safe(repr(path.suffix))} in "
                          f"{terminal_safe(path)} (allowed: {_allowed()})", field)
    return ext[1:]


def check_output(path: str | os.PathLike[str], field: str = "--output") -> Path:
    """The absolute path of a figure to write, once it is known to be writable there.

    Writes nothing. Raises FigureError naming ``field`` for: an extension (case-
    insensitive) not in FORMATS; a parent folder that does not exist, is not a folder or
    is not writable (os.access, W_OK and X_OK: a file is created in it); a target that is
    an existing folder. Paths in messages are escaped (terminal_safe): they may come from
    stored text.
    """
    given = Path(os.fspath(path))
    _format_of(given, field)
    target = Path(os.path.abspath(given))
    folder = target.parent
    if not folder.exists():
        raise FigureError(f"{field}: the folder {terminal_safe(folder)} does not exist", field)
    if not folder.is_dir():
        raise FigureError(f"{field}: {terminal_safe(folder)} is not a folder", field)
    if not os.access(folder, os.W_OK | os.X_OK):
        raise FigureError(f"{field}: the folder {terminal_safe(folder)} is not writable", field)
    if target.is_dir():
        raise FigureError(f"{field}: {terminal_safe(target)} is a folder; name a file in it, "
                          f"e.g. {terminal_safe(target / ('figure.' + FORMATS[0]))}", field)
    return target


def data_paths(path: Path, drawing: Drawing) -> list[Path]:
    """Where the drawing's tables go, beside the figure: the first one ``<stem>.csv``,
    the others ``<stem>.<name>.csv``. An existing file there is replaced, as the figure is."""
    path = Path(path)
    return [path.with_name(f"{path.stem}.csv" if i == 0 else f"{path.stem}.{table.name}.csv")
            for i, table in enumerate(drawing.tables)]


def _save_options(fmt: str, facts: Mapping[str, Any] | None = None) -> dict[str, Any]:
    described: dict[str, str] = {}
    if facts is not None:  # the module docstring: "What it was computed at"
        from slopetui.figures.figure_facts import figure_caption

        text, machine = figure_caption(dict(facts)), json_text(facts)
        described = ({"Description": text, "slopetui": machine} if fmt == "png" else
                     {"Subject" if fmt == "pdf" else "Description": text, "Keywords": machine})
    if fmt == "png":
        return {"dpi": PNG_DPI, "metadata": {"Software": CREATOR, **described}}
    date_key = "CreationDate" if fmt == "pdf" else "Date"
    return {"dpi": RASTER_DPI, "metadata": {"Creator": CREATOR, date_key: None, **described}}


#: The caption's font size (points): under a 6.4 in diagram it matches the tick labels'
#: scale; never set below CAPTION_MIN_PT, about the smallest print a journal accepts (a line
#: that does not fit at it is wrapped instead).
CAPTION_PT = 6.5
CAPTION_MIN_PT = 5.0
#: The strip a caption takes under the figure (inches): a margin, and one line height
#: (1.2 font sizes, matplotlib's line spacing, at CAPTION_PT) per line.
CAPTION_MARGIN_IN = 0.08
CAPTION_LINE_IN = 1.2 * CAPTION_PT / 72
#: The share of the figure's width a caption line may take.
CAPTION_WIDTH = 0.97


def caption_strip_in(n_lines: int) -> float:
    """The height (inches) of the strip a caption of ``n_lines`` lines takes."""
    return CAPTION_MARGIN_IN + n_lines * CAPTION_LINE_IN


def caption_lines(text: str) -> list[str]:
    """The caption's line split in two where it is read in two parts: what the figure
    shows and its parameters, then the solver and the engine (after the first "; ")."""
    head, sep, tail = text.partition("; ")
    return [head, tail] if sep else [head]


def add_caption(figure: Figure, text: str) -> Bbox:
    """``text`` in a strip under the figure, in two lines (caption_lines), and the area to
    save with it (savefig's bbox_inches): the figure's own area and the strip below it.
    The layout is made at the figure's own size and then kept (the panels keep their size
    and place), and the figure's "outside" legends, which hang from the edge of the area
    saved, stay on the figure's own edge, above the strip. The lines are measured as the
    renderer sets them: wider than CAPTION_WIDTH of the figure at CAPTION_PT they are set smaller,
    down to CAPTION_MIN_PT, and wrapped where they are still too wide."""
    import textwrap

    from matplotlib.transforms import Bbox

    figure.draw_without_rendering()  # the constrained layout, at the figure's own size
    figure.set_layout_engine("none")
    for legend in figure.legends:
        legend.set_bbox_to_anchor((0.0, 0.0, 1.0, 1.0), transform=figure.transFigure)
    width, height = figure.get_size_inches()
    room = CAPTION_WIDTH * width * 72  # points
    lines = caption_lines(text)
    size = CAPTION_PT
    widest = _widest(figure, lines, size)
    if widest > room:
        size = max(CAPTION_MIN_PT, size * room / widest)
    for _ in range(4):  # wrap what does not fit at the floor (each pass narrows by 10 %)
        widths = [_widest(figure, [line], size) for line in lines]
        if max(widths) <= room:
            break
        lines = [wrapped for line, w in zip(lines, widths, strict=True)
                 for wrapped in (textwrap.wrap(line, max(int(len(line) * room / w * 0.9), 20))
                                 if w > room else [line])]
    strip = caption_strip_in(len(lines))
    figure.text(0.5, -strip / 2 / height, "\n".join(lines), ha="center", va="center",
                fontsize=size, color="0.25", linespacing=1.2)
    return Bbox([[0.0, -strip], [width, height]])


def _widest(figure: Figure, lines: list[str], size: float) -> float:
    """The width (points) of the widest of ``lines`` set at ``size`` in the figure's font,
    as Agg lays it out at the figure's dpi (PDF and SVG set the same font's metrics;
    matplotlib.textpath's measure differs from both by about 5 %)."""
    from matplotlib.backends.backend_agg import RendererAgg
    from matplotlib.font_manager import FontProperties

    renderer, font = RendererAgg(1, 1, figure.dpi), FontProperties(size=size)
    return max(renderer.get_text_width_height_descent(line, font, ismath=False)[0]
               for line in lines) * 72 / figure.dpi


def _save_figure(figure: Figure, fmt: str, facts: Mapping[str, Any] | None, area: Bbox | None,
                 out: IO[bytes]) -> None:
    import matplotlib

    # the rc settings of the save (module docstring), for its duration only
    with _SAVE_LOCK, matplotlib.rc_context({"pdf.fonttype": FONTTYPE, "ps.fonttype": FONTTYPE,
                                            "svg.hashsalt": SVG_HASH_SALT}):
        figure.savefig(out, format=fmt, bbox_inches=area, **_save_options(fmt, facts))


def _write_table(table: Table, facts: Mapping[str, Any] | None, out: IO[str]) -> None:
    if facts is not None:  # one comment line before the header (module docstring)
        out.write(f"{FACTS_PREFIX}{json_text(facts)}\n")
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(table.header)
    width = len(table.header)
    for i, row in enumerate(table.rows):
        if len(row) != width:
            raise ValueError(f"table {table.name!r}: row {i} has {len(row)} cells, "
                             f"the header {width}")
        writer.writerow([cell(v) for v in row])


def _temp_for(target: Path) -> tuple[int, Path]:
    """A new hidden file beside ``target`` (mode 0o666 less the umask, as the target would
    get: mkstemp's 0o600 would survive the rename), opened for writing."""
    keep = target.name.encode()[:TEMP_NAME_KEEP].decode(errors="ignore")  # bytes, not characters
    while True:
        temp = target.with_name(f".{keep}.{secrets.token_hex(4)}.tmp")
        try:
            return os.open(temp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666), temp
        except FileExistsError:  # 2**32 names: another writer's, try the next
            continue


def _stage(target: Path, binary: bool, fill: Callable[[IO[Any]], None], temps: list[Path]) -> None:
    fd, temp = _temp_for(target)
    temps.append(temp)
    out: IO[Any] = os.fdopen(fd, "wb") if binary else os.fdopen(fd, "w", newline="", encoding="utf-8")
    with out:
        fill(out)
        out.flush()
        os.fsync(out.fileno())  # whole on disk before the rename makes it the target


def write(drawing: Drawing, path: str | os.PathLike[str], *, caption: bool = False) -> list[Path]:
    """Save the figure (its format from the extension of ``path``) and each table as CSV
    beside it (data_paths), each naming the drawing's facts; with ``caption``, the facts'
    line under the figure too. Returns the paths written, the figure first.

    Atomic per file (module docstring): on any failure no partial or temporary file is
    left. Raises FigureError for an unknown extension, and for an OSError (naming the
    path and the cause); other exceptions (a bug) propagate as they are.
    """
    target = Path(os.path.abspath(os.fspath(path)))
    fmt = _format_of(target, "figure path")
    targets = [target, *data_paths(target, drawing)]
    temps: list[Path] = []
    current = target
    area = None  # the figure's own area, unless a caption adds a strip under it
    if caption and drawing.facts is not None:
        from slopetui.figures.figure_facts import figure_caption

        area = add_caption(drawing.figure, figure_caption(dict(drawing.facts)))
    try:
        _stage(target, True, partial(_save_figure, drawing.figure, fmt, drawing.facts, area),
               temps)
        for table, csv_path in zip(drawing.tables, targets[1:], strict=True):
            current = csv_path
            _stage(csv_path, False, partial(_write_table, table, drawing.facts), temps)
        for temp, final in zip(list(temps), targets, strict=True):
            current = final
            os.replace(temp, final)
            temps.remove(temp)
    except BaseException as exc:  # KeyboardInterrupt too: leave no temporary file behind
        for temp in temps:
            with contextlib.suppress(OSError):
                temp.unlink()
        if isinstance(exc, OSError):
            cause = exc.strerror or str(exc)
            raise FigureError(f"cannot write {terminal_safe(current)}: {cause}") from exc
        raise
    return targets

