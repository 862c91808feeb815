"""A queued row whose stored inputs cannot be computed: what a worker checks at the claim,
and what it does with such a row.

Submission validates every input, but a store can be edited by hand (SQL, another tool,
an older slopetui): ``dt = 0``, a parameter out of range, a NULL where a number belongs, a
history naming a state that is not kept. Built in the worker's main thread, such a row
raised there and killed the worker before the run was charged an attempt, so every pool
that claimed it died the same way, for ever. Now each claimed row is built and
checked at the claim (slopetui.queue.jobs, branch_jobs, hysteresis_jobs): a row that
fails is marked failed at once with the reason, naming the field (the same values would
fail in every worker: no retry, no attempt), the worker logs one line without a
traceback, and goes on with the other rows.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Iterable
from typing import Any, Protocol, TypeVar

from core.params import ParameterError, Params, check_positive
from slopetui.queue.thread_steps import LeaseRows
from slopetui.store.database import Database

log = logging.getLogger("slopetui.worker")

J = TypeVar("J")


class StoredRow(Protocol):
    """A job's row as the store reads it (a frozen dataclass): its id, and its columns as
    attributes."""

    @property
    def id(self) -> int: ...


R = TypeVar("R", bound=StoredRow)


#: What building a job from a row's values raises for values it cannot use: ParameterError
#: (a ValueError) for a value out of range, TypeError and ArithmeticError for a value of
#: the wrong kind (text in a number's column of SQLite), IndexError for a truncated state.
#: Only pure functions of the row run under it: an error of the store itself (a lost
#: connection) is not the row's fault and still propagates.
INPUT_ERRORS: tuple[type[Exception], ...] = (ValueError, TypeError, ArithmeticError, IndexError)

#: The largest tau / dt an orbit's grid may have (its state holds 2 tau / dt numbers): the
#: bound of the command line's orbit commands (slopetui.cli.orbit.point_of).
MAX_ORBIT_STEPS = 1e5


def present(row: object, names: Iterable[str]) -> None:
    """ParameterError naming the first of the columns ``names`` (attributes of the stored
    ``row``) that holds NULL: a NULL must not fall back to a default (a NULL dt would take
    the method's default step)."""
    for name in names:
        if getattr(row, name) is None:
            raise ParameterError(name, None, "a value (the store holds NULL)")


def whole(field: str, value: Any, low: int) -> int:
    """``value`` as an integer >= low, or ParameterError naming the field."""
    if isinstance(value, bool) or not isinstance(value, int) or value < low:
        raise ParameterError(field, value, f"an integer >= {low}")
    return value


def orbit_step(params: Params, dt: Any) -> float:
    """The grid step of an orbit computation (continuations, hysteresis sweeps), checked as
    the command line checks it: tau > 0, 0 < dt <= tau, tau / dt at most MAX_ORBIT_STEPS
    (a tiny step would lay out a state of any size in the worker's main thread)."""
    if params.tau <= 0.0:
        raise ParameterError("tau", params.tau, "tau > 0 (periodic orbits of this model need "
                                                "a delay)")
    step = check_positive("dt", dt)
    if step > params.tau or params.tau / step > MAX_ORBIT_STEPS:
        raise ParameterError("dt", dt, f"a number in [tau / {MAX_ORBIT_STEPS:g}, tau] = "
                                       f"[{params.tau / MAX_ORBIT_STEPS:g}, {params.tau:g}]")
    return step


def reason(error: BaseException) -> str:
    """The error text stored on a row refused at its claim: what was wrong, by field."""
    return f"not computed: invalid input in the store: {error}"


def log_refused(what: str, job_id: int, text: str) -> None:
    """The worker's one line for a refused row (no traceback: the reason says it all)."""
    log.error("%s %d failed at its claim: %s", what, job_id, text)


def refuse(rows: LeaseRows, what: str, db: Database, worker_id: str, job_id: int,
           error: BaseException) -> None:
    """Fail a held job computed point by point (``rows``: slopetui.store.jobs.continuations,
    hysteresis_sweeps) whose stored inputs cannot be computed, at once with the reason, and
    log its one line; ``what`` names its kind ("continuation")."""
    text = reason(error)
    rows.fail(db, job_id, worker_id, text, give_up=True)
    log_refused(what, job_id, text)


def claim_computable(rows: LeaseRows, claim: Callable[[Database, str], R | None], what: str,
                     db: Database, worker_id: str, build: Callable[[R], J]) -> J | None:
    """The job ``build`` makes of the row ``claim`` leases (the oldest queued of ``rows``,
    one attempt charged), or None when nothing is queued; a row whose stored inputs
    ``build`` refuses (INPUT_ERRORS) fails at once with the reason (``refuse``), and the
    next one is claimed. Each round fails one row for good, so this ends."""
    while (row := claim(db, worker_id)) is not None:
        try:
            return build(row)
        except INPUT_ERRORS as exc:
            refuse(rows, what, db, worker_id, row.id, exc)
    return None
