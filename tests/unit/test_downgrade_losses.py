"""Downgrades that drop data say so: the prompt of `slopetui db
downgrade` counts and names what goes, before anything changes; the line after it says
what went. The PostgreSQL backup (pg_dump): tests/integration/test_downgrade_backup_postgres.py."""

from __future__ import annotations

import io

import pytest

from slopetui.cli import main
from slopetui.store.database import Database
from slopetui.store.downgrade_losses import DROPS
from slopetui.store.migrate import current_revision, downgrade, head_revision, plan_downgrade, revisions
from tests.unit.test_ids_kept import _rows, populate

#: What populate() twice leaves that 0005 -> 0003 drops.
JOBS = ("the certificates, accuracy estimates and Lyapunov spectra of 14 runs, "
        "2 hysteresis sweeps (6 points) and 2 continuations (4 branch points)")


class Terminal(io.StringIO):
    """A stdin that says it is a terminal."""

    def isatty(self) -> bool:
        return True


def _ask(monkeypatch: pytest.MonkeyPatch, answer: str) -> list[str]:
    asked: list[str] = []
    monkeypatch.setattr("sys.stdin", Terminal())
    monkeypatch.setattr("builtins.input", lambda q: (asked.append(q), answer)[1])
    return asked


def test_every_revision_says_what_its_downgrade_drops():
    assert list(DROPS) == list(reversed(revisions()))


def test_the_prompt_counts_and_names_what_goes_and_no_changes_nothing(
        store, store_url, capsys, monkeypatch):
    """From 0005 to 0003 every continuation, branch point and hysteresis sweep went, and
    the prompt said only "migrate ... back to revision 0003? A backup copy is made first."."""
    populate(store)
    populate(store)
    rows = _rows(store)
    assert main(["db", "downgrade", "0003", "--db", store_url]) == 2  # no terminal, no --yes
    assert f"add --yes (it drops {JOBS})" in capsys.readouterr().err
    asked = _ask(monkeypatch, "n")
    assert main(["db", "downgrade", "0003", "--no-backup", "--db", store_url]) == 2
    assert len(asked) == 1 and f"back to revision 0003? It drops {JOBS}. " in asked[0]
    assert "not confirmed; nothing was changed" in capsys.readouterr().err
    assert current_revision(store) == head_revision() and _rows(store) == rows


def test_the_line_after_a_downgrade_says_what_went(db, db_url, capsys):
    populate(db)
    populate(db)
    assert main(["db", "downgrade", "0003", "--yes", "--db", db_url]) == 0
    out = capsys.readouterr().out
    assert f"{head_revision()} -> 0003; dropped {JOBS}; backup copy " in out
    assert main(["db", "downgrade", "0002", "--yes", "--db", db_url]) == 0
    assert ("0003 -> 0002; dropped the attractor, settled, flags and maxima per period of "
            "14 runs" in capsys.readouterr().out)


def test_a_downgrade_that_drops_nothing_says_so(store):
    populate(store)
    downgrade(store, "0011")  # what the runs computed at the head were given goes first
    assert plan_downgrade(store, "0006").dropped == "no stored data"


def test_to_base_names_the_rows_not_the_columns_that_go_with_them(store):
    populate(store)
    populate(store)
    plan = plan_downgrade(store, "base")
    assert plan.dropped == ("2 hysteresis sweeps (6 points), 2 continuations (4 branch points) "
                            "and 4 sweeps (14 runs)")


def test_adaptive_sweeps_lose_their_levels_and_inferred_runs_their_mark(refined):
    """Below 0002 an inferred run reads as a computed run with no measurement."""
    url, _ = refined
    db = Database(url)
    plan = plan_downgrade(db, "0001")
    db.dispose()
    assert "the refinement levels of 1 sweep" in plan.drops
    inferred = [p for p in plan.drops if p.startswith("the inferred mark of ")]
    assert len(inferred) == 1 and int(inferred[0].split()[-2].replace(",", "")) > 0
