"""A history named on the command line: ``constant``, ``consistent``, or ``run:ID``, the
final state of a stored run (core.history.CarriedState), which is recomputed here: the
store keeps a run's summary, not its state, and the model is deterministic
(slopetui.sweeps.recompute)."""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

from core.history import HISTORIES, CarriedState
from core.params import ParameterError

if TYPE_CHECKING:
    from slopetui.store.database import Database

RUN_PREFIX = "run:"
#: What --history accepts, for messages and help.
HISTORY_CHOICES = "constant (default), consistent, or run:ID (the final state of a stored run)"
#: The largest run id: what a SQL INTEGER holds (slopetui.cli.options.MAX_SQL_INT). A
#: larger one cannot name a run, and the drivers refuse it with an OverflowError.
MAX_RUN_ID = 2**63 - 1


def parse_history(text: str) -> tuple[str, int | None]:
    """(name, None) for a named history, ("run", id) for run:ID; ParameterError naming
    the field otherwise."""
    if text in HISTORIES:
        return text, None
    digits = text[len(RUN_PREFIX):]
    # isascii: str.isdigit also takes "²" and "٣", which int() refuses or reads
    if text.startswith(RUN_PREFIX) and digits.isascii() and digits.isdigit():
        if 1 <= int(digits) <= MAX_RUN_ID:
            return "run", int(digits)
        raise ParameterError("history", text, f"run:ID with ID from 1 to {MAX_RUN_ID} (a run id)")
    raise ParameterError("history", text, HISTORY_CHOICES)


def final_state_of(db: Database, run_id: int) -> CarriedState:
    """Run ``run_id``'s state at its t_end, recomputed from its parameters and settings as
    its worker computed it (the stiff scheme where it fell back to it)."""
    # here: slopetui.sweeps.spec reads run:ID with parse_history, and `show` reads specs;
    # the recomputation loads numba's kernels (core.point), which neither needs
    from core.point import run_point
    from slopetui.sweeps.recompute import load_run

    run = load_run(db, run_id)
    if run is None:
        raise ParameterError("history", f"{RUN_PREFIX}{run_id}", "run:ID of a run in this store")
    params, settings = run.inputs()
    end = run_point(params, replace(settings, lyap=False), run.carried_state()).trajectory.final
    if end is None:
        raise ParameterError("history", f"{RUN_PREFIX}{run_id}",
                             "a run that stays in the finite range (this one diverges, so it "
                             "has no final state to start from)")
    return end
