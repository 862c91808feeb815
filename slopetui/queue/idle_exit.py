"""When a worker leaves on its own, with nothing left to do: under ``--exit-when-idle``,
and in the pool the application started (``--owner-pid``), once the application has quit.

A worker looks each time it finds nothing to claim (slopetui.queue.worker_process), at
the store's backlog (slopetui.store.jobs.backlog):

* something claimable or running (on any host): not idle. A running run may come back to
  the queue if its worker dies, and an adaptive sweep queues its next level when a level
  is done, so a worker waits for them as long as they run;
* ``--exit-when-idle`` and nothing left at all, no paused sweep holding queued runs
  either (drained): it leaves at once, so that a script or CI waits for nothing;
* ``--exit-when-idle`` and queued runs only in paused sweeps: it leaves once nothing has
  been claimable for the grace period (``--idle-grace``). A sweep paused and resumed a
  few seconds later used to find every pool of a Slurm array gone;
* an owner (the application's pool): while the owner runs, or another application of the
  store that found the pool (slopetui.queue.open_apps), never; once they have quit, when
  nothing has been claimable or running for the grace period after that (drained or
  not: the user may open the application again, or submit from the command line).

The owner is a process id and its start time (pids are reused): a pid that now names a
process started at another time is an owner gone.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

from slopetui.queue.local_pool import is_alive, start_ticks
from slopetui.queue.open_apps import open_apps
from slopetui.store.jobs.backlog import Backlog


@dataclass(frozen=True)
class Owner:
    """The process a pool works for (the application that started it), and the other
    applications of its store open on this host (slopetui.queue.open_apps)."""

    pid: int
    #: Its start time (clock ticks after boot), None where /proc does not tell.
    ticks: int | None
    #: Was it running when the pool started? If not, it is gone for good, whatever later
    #: process takes its pid.
    found: bool
    #: The store's key (local_pool.store_key): while another application of the store
    #: is open on this host (one that found this pool), the owner is not gone. None: the
    #: owner alone counts.
    store: str | None = None

    @classmethod
    def of(cls, pid: int, store: str | None = None) -> Owner:
        """The owner as it is now (read at the pool's start, while the owner, which has
        just started the pool, still runs)."""
        found = is_alive(pid)
        return cls(pid, start_ticks(pid) if found else None, found, store)

    def _exited(self) -> bool:
        if not self.found or not is_alive(self.pid):
            return True
        ticks = start_ticks(self.pid)
        return self.ticks is not None and ticks is not None and ticks != self.ticks

    def gone(self) -> bool:
        """The owner has quit, and no other application of the store is open."""
        if not self._exited():
            return False
        return self.store is None or not open_apps(self.store)


def _paused(backlog: Backlog) -> str:
    if not backlog.paused:
        return ""
    return f" ({backlog.paused} run{'s' if backlog.paused != 1 else ''} queued in paused sweeps)"


class IdleExit:
    """A worker's clock of how long nothing has been claimable, and its decision to leave
    (see the module docstring). The worker calls ``new_round()`` at the top of each round
    of its loop and ``reason_to_leave()`` when a round found nothing to claim: a round in
    between that claimed work starts the clock again."""

    def __init__(self, exit_when_idle: bool, grace_s: float, owner: Owner | None = None,
                 clock: Callable[[], float] = time.monotonic) -> None:
        self.exit_when_idle, self.grace_s, self.owner, self.clock = (
            exit_when_idle, grace_s, owner, clock)
        self.rounds = 0
        self._looked_in: int | None = None
        self.idle_since: float | None = None
        self.owner_gone_at: float | None = None

    @property
    def watching(self) -> bool:
        """Does this worker ever leave on its own?"""
        return self.exit_when_idle or self.owner is not None

    def new_round(self) -> None:
        self.rounds += 1

    def _owner_gone(self, now: float) -> bool:
        """Asked every idle round, not once: an application opened on the store after the
        owner quit (it found the pool and recorded itself) keeps the pool again."""
        if self.owner is None:
            return False
        if not self.owner.gone():
            self.owner_gone_at = None
        elif self.owner_gone_at is None:
            self.owner_gone_at = now
        return self.owner_gone_at is not None

    def reason_to_leave(self, read_backlog: Callable[[], Backlog]) -> str | None:
        """Why the worker leaves now (its log line), or None to stay. ``read_backlog``
        reads the store (only when the answer depends on it)."""
        if not self.watching:
            return None
        now = self.clock()
        if self._looked_in != self.rounds - 1:  # a round since the last look claimed work
            self.idle_since = None
        self._looked_in = self.rounds
        owner_gone = self._owner_gone(now)
        if not (self.exit_when_idle or owner_gone):
            return None  # the owner still runs: no need to read the store
        backlog = read_backlog()
        if not backlog.idle:
            self.idle_since = None
            return None
        if self.idle_since is None:
            self.idle_since = now
        if self.exit_when_idle:
            if backlog.drained:
                return "nothing queued or running"
            if now - self.idle_since >= self.grace_s:
                return f"nothing claimable for {self.grace_s:g} s{_paused(backlog)}"
        if owner_gone and self.owner is not None and self.owner_gone_at is not None:
            since = max(self.idle_since, self.owner_gone_at)
            if now - since >= self.grace_s:
                return (f"the process that started the pool (pid {self.owner.pid}) and the "
                        f"applications of the store have quit, and nothing was claimable or "
                        f"running for {self.grace_s:g} s{_paused(backlog)}")
        return None
