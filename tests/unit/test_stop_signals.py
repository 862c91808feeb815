"""The pool's stop signals (slopetui.queue.stop_signals): counted, never acted on in a
handler; and a signal ignored at start stays ignored (`nohup slopetui worker &` must
outlive the hang-up at logout)."""

from __future__ import annotations

import os
import signal
import time

from slopetui.queue.stop_signals import STOP_SIGNALS, SignalPipe


def _poll_after(pipe: SignalPipe, signum: int) -> int:
    os.kill(os.getpid(), signum)
    time.sleep(0.05)  # delivered to the main thread at its next bytecode
    return pipe.poll()


def test_signals_are_counted():
    pipe = SignalPipe(STOP_SIGNALS)
    try:
        assert _poll_after(pipe, signal.SIGHUP) == 1
        assert _poll_after(pipe, signal.SIGTERM) == 2 and pipe.name() == "SIGTERM"
    finally:
        pipe.close()


def test_a_signal_ignored_at_start_stays_ignored():
    old = signal.signal(signal.SIGHUP, signal.SIG_IGN)  # as nohup leaves it
    try:
        pipe = SignalPipe(STOP_SIGNALS)
        try:
            assert signal.getsignal(signal.SIGHUP) == signal.SIG_IGN
            assert _poll_after(pipe, signal.SIGHUP) == 0  # not a stop
            assert _poll_after(pipe, signal.SIGTERM) == 1
        finally:
            pipe.close()
        assert signal.getsignal(signal.SIGHUP) == signal.SIG_IGN
    finally:
        signal.signal(signal.SIGHUP, old)
