"""The benchmark tables in the documents are the scripts' output: every table in
benchmarks/results/ is in a block of docs/speed.md that benchmarks/update_tables.py fills,
as the file has it, and the README, a short getting-started page, holds none."""

from __future__ import annotations

import importlib.util
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def update_tables():
    spec = importlib.util.spec_from_file_location("update_tables", ROOT / "benchmarks" / "update_tables.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_every_table_is_marked_in_speed_md_and_up_to_date():
    tool = update_tables()
    tables = {p.stem: p.read_text() for p in sorted((ROOT / "benchmarks" / "results").glob("*.md"))}
    assert {"kernels", "e2e", "tui", "startup"} <= set(tables)
    used: set[str] = set()
    missing: set[str] = set()
    for doc in tool.DOCUMENTS:
        text = doc.read_text()
        assert tool.splice(text, tables, used, missing) == text, f"{doc.name}: run benchmarks/update_tables.py"
    assert missing == set() and used == set(tables)


def test_the_readme_holds_no_benchmark_table():
    assert "<!-- bench:" not in (ROOT / "README.md").read_text()
