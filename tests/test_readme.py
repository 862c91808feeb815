"""The README's SQL examples run against a real store (and stay read-only)."""

from __future__ import annotations

import re
from pathlib import Path

from slopetui.cli import main
from tests.conftest import finish_all, submit_quick

README = Path(__file__).resolve().parents[1] / "README.md"


def sql_examples() -> list[str]:
    return re.findall(r"```sql\n(.*?)```", README.read_text(), re.DOTALL)


def test_the_readme_sql_examples_run(db, db_url, capsys):
    examples = sql_examples()
    assert len(examples) >= 4
    for tau in (1.0, 2.0, 3.0):  # sweeps 1-3, so that "sweep 2" and "sweep 3" exist
        submit_quick(db, 4, tau=tau)
    finish_all(db)
    for query in examples:
        code = main(["sql", query, "--db", db_url])
        out = capsys.readouterr()
        assert code == 0, (query, out.err)
        assert "row" in out.out
