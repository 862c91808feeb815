"""Names for runs shown side by side (the compare screen, ``slopetui figure --run A --run
B``): each run by its id, the inputs that tell it apart from the others, and its regime.

Only what differs is named: two runs of a (k, tau) sweep read "run 12: k 10, τ 2
(oscillatory)" and "run 13: k 12, τ 2 (complex)" would repeat τ, so they read "run 12:
k 10 (oscillatory)". Inputs are the model parameters (core.PARAM_NAMES), then the solver
and the history before t = 0 and the stop rule, so that two runs at one point that differ
only in dt, history or stop rule still say how.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from types import MappingProxyType
from typing import TYPE_CHECKING

from core.params import PARAM_NAMES

if TYPE_CHECKING:
    from slopetui.sweeps.recompute import StoredRun

#: The inputs compared, in the order they are named.
INPUTS: tuple[str, ...] = (*PARAM_NAMES, "method", "dt", "t_end", "window", "history", "stop")
#: How the inputs are written (the paper's letters for tau and delta); the one mapping,
#: which the terminal plots' axes and the figures' labels use too.
SHOWN_AS: Mapping[str, str] = MappingProxyType({"tau": "τ", "delta": "δ"})


def differing(runs: Sequence[StoredRun]) -> list[str]:
    """The inputs (INPUTS order) whose value is not the same in every run."""
    return [name for name in INPUTS if len({getattr(r, name) for r in runs}) > 1]


def outcome(run: StoredRun) -> str:
    """The stored regime of a done run ("inferred oscillatory" for an inferred one), else
    its status."""
    if not run.done:
        return run.status
    return f"inferred {run.regime}" if run.inferred else str(run.regime)


def run_labels(runs: Sequence[StoredRun]) -> list[str]:
    """One label per run, "run ID: <differing inputs> (<outcome>)"; a single run, or runs
    alike in every input, are named by id and outcome only."""
    names = differing(runs)
    labels = []
    for run in runs:
        inputs = ", ".join(f"{SHOWN_AS.get(n, n)} {value_text(getattr(run, n))}" for n in names)
        labels.append(f"run {run.id}: " + (f"{inputs} " if inputs else "") + f"({outcome(run)})")
    return labels


def value_text(value: object) -> str:
    """An input's value as labels write it: a float by ``g`` (2, 0.01, 1e-05), else as text."""
    return format(value, "g") if isinstance(value, float) else str(value)
