"""The application's background actions, and the one way their outcome comes back.

A background action (opening the store, finding or starting the worker pool, pausing a
sweep, writing a figure or an export) is a plain function run in one of Textual's
thread workers, so that the UI never waits on a database, a process or a disk. What
follows it runs on the UI thread once the worker has ended: ``done`` with the function's
return value, or ``failed`` with what it raised. Any exception is ``failed``'s to show,
never a traceback: the workers run with ``exit_on_error=False``, without which Textual
quits the application on a worker's first exception.

Textual reports a worker's end with ``Worker.StateChanged``, to the node that started it
(it does not bubble); the app hands that message to ``BackgroundActions.ended``, which
finds the outcome by its worker. A cancelled action (the application quitting, or a newer
one of an ``exclusive`` group) has no outcome.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Generic, TypeVar, cast

from textual.app import App
from textual.worker import Worker, WorkerState

ResultT = TypeVar("ResultT")


@dataclass(frozen=True)
class Outcome(Generic[ResultT]):
    """What to do on the UI thread once a background action has ended."""

    done: Callable[[ResultT], None]  # with the action's return value
    failed: Callable[[Exception], None]  # with what it raised


class BackgroundActions:
    """The background actions of one application, each with its outcome until it ends."""

    def __init__(self, app: App[Any]) -> None:
        self._app = app
        self._outcomes: dict[Worker[Any], Outcome[Any]] = {}

    def start(self, action: Callable[[], ResultT], *, done: Callable[[ResultT], None],
              failed: Callable[[Exception], None], group: str,
              exclusive: bool = False) -> Worker[ResultT]:
        """Run ``action`` in a thread worker of ``group``; then ``done(result)`` or
        ``failed(exception)`` on the UI thread. Call it on the UI thread."""
        worker = self._app.run_worker(action, thread=True, group=group, exclusive=exclusive,
                                      exit_on_error=False)
        self._outcomes[worker] = Outcome(done, failed)
        return worker

    def ended(self, event: Worker.StateChanged) -> None:
        """A worker of the app changed state: once one of ours has ended, its outcome."""
        if event.state not in (WorkerState.SUCCESS, WorkerState.ERROR, WorkerState.CANCELLED):
            return
        outcome = self._outcomes.pop(event.worker, None)
        if outcome is None:  # not a background action of this module's
            return
        if event.state is WorkerState.SUCCESS:
            outcome.done(event.worker.result)
        elif event.state is WorkerState.ERROR:
            # a BaseException that is not an Exception (SystemExit...) is not caught by
            # the worker: only an Exception arrives here
            outcome.failed(cast(Exception, event.worker.error))
