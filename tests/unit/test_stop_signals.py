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


def test_a_pipe_closed_before_the_process_exits_leaves_the_signals_ignored():
    """`slopetui worker` exits once its pool has stopped: a SIGTERM landing after that
    (the second of `worker --stop --now`) must not kill it with 143. SIG_IGN survives the
    interpreter's finalisation, which puts SIG_DFL back under a Python handler."""
    old = {s: signal.getsignal(s) for s in STOP_SIGNALS}
    try:
        SignalPipe(STOP_SIGNALS).close(then_ignore=True)
        assert all(signal.getsignal(s) == signal.SIG_IGN for s in STOP_SIGNALS)
        os.kill(os.getpid(), signal.SIGTERM)  # would end the test run under SIG_DFL
        time.sleep(0.05)
    finally:
        for signum, handler in old.items():
            signal.signal(signum, handler)
