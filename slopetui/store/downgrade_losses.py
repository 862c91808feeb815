"""What a downgrade drops, counted before it runs: each revision's downgrade by the rows
and the values it removes, so that ``slopetui db downgrade`` can say "drops 3
continuations (412 branch points) and 2 hysteresis sweeps (80 points)" before it asks,
rather than after the data is gone.

The statements are plain SQL on the tables and columns as each revision made them, not
the models': a model may change in a later revision, the schema a revision dropped does
not. Every revision has an entry (tests/unit/test_downgrade_losses.py), so that a new
migration must say what its downgrade drops, if only "nothing".
"""

from __future__ import annotations

from dataclasses import dataclass

from slopetui.store.database import Database


@dataclass(frozen=True)
class Dropped:
    """What one downgrade drops, counted by ``count`` (one integer: rows, or rows whose
    value goes), named ``one``/``many`` after the count, with the rows of other tables
    that go with them (``parts``: "(412 branch points)"). ``rows``: the rows themselves go;
    false for values of columns that go while their rows stay (not worth naming when the
    whole table goes too, as in a downgrade to base)."""

    one: str
    many: str
    count: str
    parts: tuple[Dropped, ...] = ()
    rows: bool = True


def _values(what: str, table: str, where: str) -> Dropped:
    """The values of columns of ``table`` that go, for the rows where they say something."""
    return Dropped(f"the {what} of {{n}} {table[:-1]}", f"the {what} of {{n}} {table}",
                   f"SELECT count(*) FROM {table} WHERE {where}", rows=False)


#: Each revision's downgrade (to the one before it): what it drops.
DROPS: dict[str, tuple[Dropped, ...]] = {
    "0017": (Dropped("torus curve", "torus curves", "SELECT count(*) FROM curves WHERE kind = 'ns'",
                     (Dropped("point", "points", "SELECT count(*) FROM curve_points WHERE curve_id "
                                                 "IN (SELECT id FROM curves WHERE kind = 'ns')"),
                      Dropped("codimension-two point", "codimension-two points",
                              "SELECT count(*) FROM curve_bifurcations WHERE curve_id IN "
                              "(SELECT id FROM curves WHERE kind = 'ns')"))),),
    "0016": (Dropped("curve", "curves", "SELECT count(*) FROM curves",
                     (Dropped("point", "points", "SELECT count(*) FROM curve_points"),
                      Dropped("codimension-two point", "codimension-two points",
                              "SELECT count(*) FROM curve_bifurcations"))),
             _values("reason", "bifurcations", "reason IS NOT NULL AND reason <> ''"),
             _values("first Lyapunov coefficient", "continuations", "l1 IS NOT NULL")),
    # a continuation from a later Hopf point reads as one from the first: its points stay;
    # a queued or running one is failed first (an older worker would start at the first)
    "0015": (_values("Hopf point (a later one than the first)", "continuations",
                     "hopf_branch > 1"),),
    # the sweeps and runs stay; what the user wrote on them and marked goes
    "0014": (_values("note", "sweeps", "note IS NOT NULL"),
             Dropped("sweep tag", "sweep tags", "SELECT count(*) FROM sweep_tags"),
             Dropped("marked run", "marked runs", "SELECT count(*) FROM marks")),
    # a run that stopped early reads as one that ran to its t_end (t_stop is derived
    # again from t_blowup and t_end only for those that did)
    "0013": (_values("stop rule (certified) and stopping time", "runs", "stop <> 't_end'"),),
    # the runs stay, with the labels they were given; what certified them goes
    "0012": (_values("certificates, accuracy estimates and Lyapunov spectra", "runs",
                     "certified IS NOT NULL"),),
    # the refined values stay in onset_up and offset_down; their brackets and tolerance go
    "0011": (Dropped("the transition brackets of {n} hysteresis sweep",
                     "the transition brackets of {n} hysteresis sweeps",
                     "SELECT count(*) FROM hysteresis_sweeps WHERE onset_up_before IS NOT NULL "
                     "OR offset_down_before IS NOT NULL", rows=False),),
    # labels an older slopetui cannot hold: the runs stay, their label reads as pending
    "0010": (_values("attractor unstable-fixed-point", "runs", "length(attractor) > 16"),
             _values("regime undetermined", "runs", "regime = 'undetermined'"),
             _values("detail beyond 64 characters", "runs", "length(detail) > 64")),
    # AUTOINCREMENT goes: nothing is dropped (an older slopetui reuses the largest ids)
    "0009": (),
    "0008": (),  # an index
    "0007": (),  # NULL stays NULL
    "0006": (Dropped("carried initial state", "carried initial states",
                     "SELECT count(*) FROM initial_states"),
             _values("history (not constant)", "runs", "history <> 'constant'"),
             _values("initial condition (not the first)", "runs", "ic <> 0")),
    "0005": (Dropped("hysteresis sweep", "hysteresis sweeps",
                     "SELECT count(*) FROM hysteresis_sweeps",
                     (Dropped("point", "points", "SELECT count(*) FROM hysteresis_points"),)),),
    "0004": (Dropped("continuation", "continuations", "SELECT count(*) FROM continuations",
                     (Dropped("branch point", "branch points",
                              "SELECT count(*) FROM branch_points"),
                      Dropped("bifurcation", "bifurcations",
                              "SELECT count(*) FROM bifurcations"))),),
    "0003": (_values("attractor, settled, flags and maxima per period", "runs",
                     "attractor IS NOT NULL OR flags IS NOT NULL OR settled IS NOT NULL "
                     "OR maxima_per_period IS NOT NULL"),),
    # an inferred run left without its mark reads as a computed run with no measurement
    "0002": (_values("refinement levels", "sweeps", "adaptive_levels IS NOT NULL"),
             _values("inferred mark", "runs", "inferred = true")),
    "0001": (Dropped("sweep", "sweeps", "SELECT count(*) FROM sweeps",
                     (Dropped("run", "runs", "SELECT count(*) FROM runs"),)),
             Dropped("worker row", "worker rows", "SELECT count(*) FROM workers")),
}


def _phrase(db_counts: dict[str, int], item: Dropped) -> str | None:
    n = db_counts[item.count]
    if not n:
        return None
    parts = [p for p in (_phrase(db_counts, part) for part in item.parts) if p]
    name = item.one if n == 1 else item.many
    text = name.replace("{n}", f"{n:,}") if "{n}" in name else f"{n:,} {name}"
    return text + (f" ({', '.join(parts)})" if parts else "")


def _every(items: tuple[Dropped, ...]) -> list[Dropped]:
    return [x for item in items for x in (item, *_every(item.parts))]


def losses(db: Database, downgrades: list[str], *, to_base: bool) -> list[str]:
    """What the downgrades of ``downgrades`` (revisions, newest first, each undone in
    turn) drop from ``db``, as phrases ("3 continuations (412 branch points)"); nothing
    for what is not there. ``to_base``: every table goes, so only the rows are named."""
    items = [item for revision in downgrades for item in DROPS[revision]
             if item.rows or not to_base]
    with db.read() as conn:
        counts = {x.count: int(conn.exec_driver_sql(x.count).scalar() or 0)
                  for x in _every(tuple(items))}
    return [p for p in (_phrase(counts, item) for item in items) if p]


def sentence(phrases: list[str]) -> str:
    """"3 continuations (412 branch points) and 2 hysteresis sweeps"; "no stored data"."""
    if not phrases:
        return "no stored data"
    return phrases[0] if len(phrases) == 1 else f"{', '.join(phrases[:-1])} and {phrases[-1]}"
