"""What the user writes on a sweep: its name, a note and tags (``slopetui rename``,
``note``, ``tag``; the application's sweep actions), and the sweeps found by a tag.

The text arrives checked (``slopetui.sweeps.annotations`` says what a name, a note and a
tag may be); it is stored as given, and every face escapes it where it reaches a terminal
(``slopetui.display_text``). Each function is one transaction, or one read.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from datetime import datetime
from typing import Any

from sqlalchemy import Select, delete, insert, select, update

from slopetui.store.database import Database, rows_changed
from slopetui.store.models import Sweep, SweepTag


@dataclass(frozen=True)
class SweepLabels:
    """A sweep's name, note (None for none) and tags (sorted)."""

    id: int
    name: str
    note: str | None
    tags: tuple[str, ...]


@dataclass(frozen=True)
class SpecOfSweep:
    """A sweep's name and its spec as submitted (axes, fixed parameters, solver)."""

    id: int
    name: str
    spec: dict[str, Any]


@dataclass(frozen=True)
class ListedSweep:
    """A sweep as ``slopetui sweeps`` lists it."""

    id: int
    name: str
    status: str
    created_at: datetime
    n_runs: int
    note: str | None
    tags: tuple[str, ...]


def sweep_list(db: Database, tag: str | None = None) -> list[ListedSweep]:
    """Every sweep (with this tag: None, any), newest first, with its labels. One
    snapshot."""
    sweeps = select(Sweep.id, Sweep.name, Sweep.status, Sweep.created_at, Sweep.n_runs,
                    Sweep.note).order_by(Sweep.id.desc())
    tags = select(SweepTag.sweep_id, SweepTag.tag).order_by(SweepTag.tag)
    if tag is not None:
        sweeps = sweeps.where(Sweep.id.in_(tagged(tag)))
        tags = tags.where(SweepTag.sweep_id.in_(tagged(tag)))
    with db.read() as conn:
        found: dict[int, list[str]] = {}
        for sweep_id, name in conn.execute(tags):
            found.setdefault(sweep_id, []).append(name)
        return [ListedSweep(*row, tuple(found.get(row[0], ()))) for row in conn.execute(sweeps)]


def labels_of(db: Database, sweep_ids: Sequence[int] | None = None) -> dict[int, SweepLabels]:
    """The labels of these sweeps (None: every sweep), by id; a sweep not stored is
    absent. One snapshot."""
    ids = None if sweep_ids is None else list(sweep_ids)
    sweeps = select(Sweep.id, Sweep.name, Sweep.note)
    tags = select(SweepTag.sweep_id, SweepTag.tag).order_by(SweepTag.tag)
    if ids is not None:
        sweeps, tags = sweeps.where(Sweep.id.in_(ids)), tags.where(SweepTag.sweep_id.in_(ids))
    with db.read() as conn:
        found: dict[int, list[str]] = {}
        for sweep_id, tag in conn.execute(tags):
            found.setdefault(sweep_id, []).append(tag)
        return {i: SweepLabels(i, name, note, tuple(found.get(i, ())))
                for i, name, note in conn.execute(sweeps)}


def tagged(tag: str) -> Select[int]:
    """The ids of the sweeps with this tag, as a subquery for a filter on runs
    (``Run.sweep_id.in_(tagged(tag))``)."""
    return select(SweepTag.sweep_id).where(SweepTag.tag == tag)


def sweeps_tagged(db: Database, tag: str) -> list[int]:
    """The ids of the sweeps with this tag, newest first."""
    with db.read() as conn:
        return list(conn.scalars(tagged(tag).order_by(SweepTag.sweep_id.desc())))


def rename(db: Database, sweep_id: int, name: str) -> bool:
    """Give the sweep this name; False if there is no such sweep."""
    with db.transaction() as s:
        return rows_changed(s.execute(update(Sweep).where(Sweep.id == sweep_id)
                                      .values(name=name))) > 0


def set_note(db: Database, sweep_id: int, note: str | None) -> bool:
    """Replace the sweep's note (None: remove it); False if there is no such sweep."""
    with db.transaction() as s:
        return rows_changed(s.execute(update(Sweep).where(Sweep.id == sweep_id)
                                      .values(note=note))) > 0


def change_tags(db: Database, sweep_id: int, add: Iterable[str] = (),
                remove: Iterable[str] = ()) -> tuple[str, ...] | None:
    """Add and remove tags of the sweep (a tag it has already, or does not have, is no
    error); its tags after, sorted; None if there is no such sweep. The sweep's row is
    locked first (PostgreSQL; SQLite's write transaction holds the whole store), so that
    two changes of one sweep's tags, or a delete, come one after the other."""
    removing = sorted(set(remove))
    with db.transaction() as s:
        if s.get(Sweep, sweep_id, with_for_update=True) is None:
            return None
        if removing:
            s.execute(delete(SweepTag).where(SweepTag.sweep_id == sweep_id,
                                             SweepTag.tag.in_(removing)))
        has = set(s.scalars(select(SweepTag.tag).where(SweepTag.sweep_id == sweep_id)))
        adding = sorted(set(add) - has)
        if adding:
            s.execute(insert(SweepTag), [{"sweep_id": sweep_id, "tag": t} for t in adding])
        return tuple(sorted(has | set(adding)))


def specs_of(db: Database, sweep_ids: Sequence[int]) -> dict[int, SpecOfSweep]:
    """The names and specs of these sweeps, by id; a sweep not stored is absent."""
    with db.read() as conn:
        return {i: SpecOfSweep(i, name, spec) for i, name, spec in conn.execute(
            select(Sweep.id, Sweep.name, Sweep.spec).where(Sweep.id.in_(list(sweep_ids))))}
