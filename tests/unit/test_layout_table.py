"""docs/development.md's layout table names every module of ``core`` and ``slopetui``: a
new module fails here until the table says what it holds."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
TABLE_ROW = re.compile(r"^\| (?P<first>[^|]+)\|(?P<rest>.*)\|\s*$")


def table_rows() -> dict[str, str]:
    """Each path named in a row's first cell (`core/params.py`, `slopetui/store/`), with
    the row's whole text."""
    rows = {}
    for line in (ROOT / "docs" / "development.md").read_text().splitlines():
        m = TABLE_ROW.match(line)
        if m:
            for path in re.findall(r"`([^`]+)`", m["first"]):
                rows[path] = line
    return rows


def modules() -> list[str]:
    """The modules, as paths from the root; a package's __init__.py is its folder's row."""
    return sorted(p.relative_to(ROOT).as_posix() for package in ("core", "slopetui")
                  for p in (ROOT / package).rglob("*.py") if p.name != "__init__.py")


def unlisted(rows: dict[str, str], paths: list[str]) -> list[str]:
    """The paths the table does not name: named means a row of its own, or the row of the
    nearest folder above it naming it (as `runs/claims.py`, or as `claims.py` where no
    other module under that folder has the name)."""
    missing = []
    for path in paths:
        if path in rows:
            continue
        parts = path.split("/")
        folders = ["/".join(parts[:i]) + "/" for i in range(len(parts) - 1, 0, -1)]
        folder = next((f for f in folders if f in rows), None)
        if folder is None:
            missing.append(path)
            continue
        named = set(re.findall(r"`([^`]+)`", rows[folder]))
        name, relative = parts[-1], path.removeprefix(folder)
        alike = [p for p in paths if p.startswith(folder) and p.rsplit("/", 1)[-1] == name]
        if relative not in named and (name not in named or len(alike) > 1):
            missing.append(path)
    return missing


def test_every_module_is_in_the_layout_table():
    rows, paths = table_rows(), modules()
    assert len(paths) > 200 and "core/params.py" in rows  # the table and the tree were read
    assert unlisted(rows, paths) == []


def test_a_module_named_only_elsewhere_is_unlisted():
    """The rule itself: a name in another folder's row, or a name two modules share, does
    not count."""
    rows = {"slopetui/store/": "| `slopetui/store/` | models (`models.py`), `progress.py` |",
            "slopetui/sweeps/": "| `slopetui/sweeps/` | specs (`spec.py`) |"}
    paths = ["slopetui/store/models.py", "slopetui/store/runs/progress.py",
             "slopetui/store/sweeps/progress.py", "slopetui/sweeps/spec.py",
             "slopetui/sweeps/models.py", "slopetui/figures/style.py"]
    assert unlisted(rows, paths) == ["slopetui/store/runs/progress.py",
                                     "slopetui/store/sweeps/progress.py",
                                     "slopetui/sweeps/models.py", "slopetui/figures/style.py"]
