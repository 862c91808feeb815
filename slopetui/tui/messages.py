"""Small messages shared by the screens: from thread workers (a failed store call) and
from the diagram widgets (a run chosen or marked)."""

from __future__ import annotations

from dataclasses import dataclass

from textual.message import Message


@dataclass
class RunChosen(Message):
    """The user chose a run in a diagram (phase grid or bifurcation view) to open."""

    run_id: int


@dataclass
class RunMarked(Message):
    """The user marked (or unmarked) the run under a diagram's cursor for comparison."""

    run_id: int


@dataclass
class StoreFailed(Message):
    """A database call in a worker failed: shown to the user, never as a traceback."""

    action: str
    error: str
