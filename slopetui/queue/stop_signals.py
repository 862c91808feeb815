"""Stop signals without work in a handler: a wakeup pipe that the loop reads, the mask a
pool spawns its workers with, and the death signal that ties a worker to its pool.

A Python signal handler runs between two bytecodes of the main thread, possibly while
that thread holds a lock or waits on an Event; a handler that set or read a
multiprocessing Event deadlocked the pool that way. So the handlers here do nothing:
CPython's C-level handler writes the signal's number to the wakeup pipe, and the loops
(slopetui.queue.pool, slopetui.queue.worker_process) count those bytes.
"""

from __future__ import annotations

import os
import signal
import sys
from collections.abc import Callable, Iterable
from typing import Any

#: The signals a pool acts on; its workers act on SIGTERM only.
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)


class SignalPipe:
    """Counts signals without doing anything in a handler that could block.

    The Python handlers are empty on purpose: for each signal, CPython's C-level handler
    writes its number to the wakeup pipe (``signal.set_wakeup_fd``); ``poll()``, called by
    the loop, reads and counts those bytes (two signals are two bytes, even when the
    Python-level handler would run once for both). ``fileno()`` can be select()ed on to
    wake up at once. Main thread only, as signal handlers are."""

    def __init__(self, signums: Iterable[int]) -> None:
        self.signums = frozenset(int(s) for s in signums)
        self.count = 0
        self.last: int | None = None
        self._read, self._write = os.pipe()
        os.set_blocking(self._read, False)
        os.set_blocking(self._write, False)  # a full pipe drops the byte, never blocks
        self._old_fd = signal.set_wakeup_fd(self._write, warn_on_full_buffer=False)
        # A signal ignored when the process started stays ignored: `nohup slopetui worker`
        # sets SIGHUP to SIG_IGN so that the pool outlives the terminal's hang-up.
        self._old = {s: signal.signal(s, self._handler) for s in self.signums
                     if signal.getsignal(s) != signal.SIG_IGN}

    @staticmethod
    def _handler(_signum: int, _frame: Any) -> None:
        """Nothing: the byte in the wakeup pipe is the signal (see the class docstring)."""

    def fileno(self) -> int:
        return self._read

    def poll(self) -> int:
        """Count the signals received since the last poll; returns the total."""
        while True:
            try:
                data = os.read(self._read, 512)
            except BlockingIOError:
                break
            if not data:
                break
            for signum in data:
                if signum in self.signums:
                    self.count += 1
                    self.last = signum
        return self.count

    def name(self) -> str:
        return signal.Signals(self.last).name if self.last else "a signal"

    def close(self, *, then_ignore: bool = False) -> None:
        """Put back the previous handlers and wakeup fd (a pool may run inside another
        program, e.g. `slopetui reproduce`).

        then_ignore : leave the signals ignored instead: the process exits next (`slopetui
                      worker`), and a late signal, such as the second SIGTERM of `worker
                      --stop --now` or systemd's to the whole group, landing after the
                      pool stopped turned its exit status 0 into 143. SIG_IGN, not an
                      empty handler: the interpreter's finalisation puts the default
                      action back under a Python handler, but leaves SIG_IGN alone."""
        for signum, old in self._old.items():
            signal.signal(signum, signal.SIG_IGN if then_ignore else old)
        signal.set_wakeup_fd(self._old_fd)
        os.close(self._read)
        os.close(self._write)


def block_stop_signals() -> Callable[[], None]:
    """Block INT/TERM/HUP in this thread; returns the function that restores the mask.

    A spawned child inherits the mask through fork and exec: the pool spawns its workers
    with these signals blocked, and each worker unblocks them once its own handlers are in,
    so a signal that comes while it is still starting waits instead of killing it half
    made (a KeyboardInterrupt traceback, or a death that the pool would count)."""
    if not hasattr(signal, "pthread_sigmask"):
        return lambda: None
    old = signal.pthread_sigmask(signal.SIG_BLOCK, STOP_SIGNALS)

    def restore() -> None:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)
    return restore


def die_with_parent() -> None:
    """Ask Linux to send SIGTERM to this process when its parent (the pool) dies, even a
    kill -9 of it: an orphan worker must not claim runs and pose as live (prctl
    PR_SET_PDEATHSIG). Elsewhere a no-op: the getppid() check in the loop still works."""
    if not sys.platform.startswith("linux"):
        return
    try:
        import ctypes
        libc = ctypes.CDLL(None, use_errno=True)
        pr_set_pdeathsig = 1
        libc.prctl(pr_set_pdeathsig, int(signal.SIGTERM), 0, 0, 0)
    except (OSError, AttributeError):  # no libc prctl (e.g. musl without it)
        pass


