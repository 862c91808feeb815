"""Every stop signal (INT, TERM, HUP) sent to a worker, to the pool and to the pool's whole
process group, with the pool idle and busy: the pool exits within a bound with status 0,
and every run is done exactly once or back in 'queued' (none is left 'running').

Pools are started side by side (one store each) to keep the wall time down. The store's
side of a stop (the run in the kernel finished, the rest given back, worker rows stopped)
runs on SQLite and PostgreSQL in test_signals_to_one_worker; the matrix of signals, targets
and states is about signals, not the store, and runs on SQLite files only (14 pools: on
both backends it would double the module's time).
"""

from __future__ import annotations

import os
import signal
import subprocess
import time
from dataclasses import dataclass
from pathlib import Path

from sqlalchemy import select

from slopetui.store.database import Database
from slopetui.store.models import Run
from slopetui.store.open import open_store
from tests.integration.pool_support import (
    LONG,
    MEDIUM,
    by_status,
    done_lines,
    gone,
    live_worker_rows,
    pid_of,
    start_pool,
    started_run,
    wait_until,
)
from tests.support import new_sqlite_store, submit_quick

#: A stopped pool must be gone within this many seconds of the signal.
EXIT_BOUND_S = 30.0
#: After a second signal the runs are given back at once: a tighter bound.
ABORT_BOUND_S = 10.0


@dataclass
class Case:
    signum: signal.Signals
    target: str          # "pool": its pid only; "group": kill(-pgid), as systemctl stop does
    state: str           # "idle", "busy", or "twice" (busy, and the signal sent twice)
    dir: Path | None = None
    db: Database | None = None
    proc: subprocess.Popen[str] | None = None
    in_kernel: int | None = None
    idle_since: float | None = None

    @property
    def name(self) -> str:
        return f"{self.signum.name}-{self.target}-{self.state}"

    def start(self, root: Path, template: Path) -> None:
        self.dir = root / self.name
        self.dir.mkdir()
        url = f"sqlite:///{self.dir / 'store.db'}"
        new_sqlite_store(url, template)  # 14 migrations in a row cost the pools ~2 s
        self.db = open_store(url)
        if self.state == "busy":
            submit_quick(self.db, 3, **MEDIUM)  # one batch of 3, computed one by one
        elif self.state == "twice":
            submit_quick(self.db, 1, **LONG)    # cannot finish between the two signals
        self.proc = start_pool(url, self.dir / "pool.log", "-j", "1", "--batch", "3",
                               group=True)

    def ready(self) -> bool:
        if self.state == "idle":  # up, and settled in its idle wait (where a handler that
            # touched the stop Event deadlocked)
            if self.idle_since is None and live_worker_rows(self.db):
                self.idle_since = time.monotonic()
            return self.idle_since is not None and time.monotonic() - self.idle_since > 0.5
        run = started_run(self.db)
        if run is not None:
            self.in_kernel = run.id
        return run is not None

    def send(self) -> None:
        for i in range(2 if self.state == "twice" else 1):
            if i:
                time.sleep(0.3)  # two signals back to back may merge into one
            if self.target == "pool":
                os.kill(self.proc.pid, self.signum)
            else:
                os.killpg(self.proc.pid, self.signum)

    def check(self, elapsed: float) -> None:
        _, err = self.proc.communicate()
        log = (self.dir / "pool.log").read_text()
        assert self.proc.returncode == 0, (self.name, err, log)
        assert elapsed < (ABORT_BOUND_S if self.state == "twice" else EXIT_BOUND_S), self.name
        assert "Traceback" not in err + log, (self.name, err, log)
        assert "running" not in by_status(self.db), self.name
        assert live_worker_rows(self.db) == [], self.name  # every worker row says stopped
        assert not list((self.dir / "state").rglob("*.json")), self.name  # pool file removed
        with self.db.sessions() as s:
            runs = list(s.scalars(select(Run)))
        lines = done_lines(self.dir / "pool.log")
        for run in runs:
            assert run.status in ("done", "queued"), (self.name, run.id, run.status)
            if run.status == "done":
                assert lines[run.id] == 1 and run.attempts == 1, (self.name, run.id)
            else:  # given back: the attempt is not counted against it
                assert run.attempts == 0 and run.worker_id is None, (self.name, run.id)
        if self.state == "busy":  # the run in the kernel was allowed to finish
            assert next(r for r in runs if r.id == self.in_kernel).status == "done", self.name
        if self.state == "twice":  # ... or given back at once
            assert [r.status for r in runs] == ["queued"], self.name
        self.db.dispose()


def run_side_by_side(cases: list[Case], root: Path, template: Path) -> None:
    for case in cases:
        case.start(root, template)
    try:
        pending = list(cases)
        deadline = time.monotonic() + 120
        sent: dict[str, float] = {}
        while pending:  # signal each pool as soon as it is ready
            assert time.monotonic() < deadline, [c.name for c in pending]
            for case in list(pending):
                assert case.proc.poll() is None, (case.name, case.proc.communicate())
                if case.ready():
                    case.send()
                    sent[case.name] = time.monotonic()
                    pending.remove(case)
            time.sleep(0.03)
        failures = []  # every case is checked, and every failure reported
        for case in cases:
            try:
                case.proc.wait(timeout=max(1.0, sent[case.name] + EXIT_BOUND_S
                                           - time.monotonic()))
                case.check(time.monotonic() - sent[case.name])
            except subprocess.TimeoutExpired:
                failures.append(f"{case.name}: still running {EXIT_BOUND_S:g} s after the "
                                "signal")
            except AssertionError as exc:
                failures.append(f"{case.name}: {str(exc)[:300]}")
        assert not failures, "\n".join(failures)
    finally:
        for case in cases:
            if case.proc.poll() is None:
                os.killpg(case.proc.pid, signal.SIGKILL)
                case.proc.communicate()


SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)


def test_a_signal_to_the_pool_or_its_group_stops_it_idle_or_busy(tmp_path, sqlite_template):
    cases = [Case(sig, target, state) for target in ("pool", "group") for sig in SIGNALS
             for state in ("idle", "busy")]
    # the second signal: Ctrl-C twice at the pool, systemctl's SIGTERM twice at the group
    cases += [Case(signal.SIGINT, "pool", "twice"), Case(signal.SIGTERM, "group", "twice")]
    run_side_by_side(cases, tmp_path, sqlite_template)


def test_signals_to_one_worker(tmp_path, store, store_url):
    """INT and HUP sent to a worker are ignored (the pool decides for Ctrl-C and hang-ups);
    SIGTERM stops that worker alone, idle or busy (its run in the kernel finishes first),
    and the pool neither replaces it nor counts it as a death; a second SIGTERM gives its
    run back at once. The pool exits when its last worker has left."""
    log = tmp_path / "pool.log"
    pool = start_pool(store_url, log, "-j", "3", "--batch", "3", group=True)
    try:
        workers = wait_until("3 workers", lambda: len(live_worker_rows(store)) == 3
                             and live_worker_rows(store))
        idle, busy, aborted = (pid_of(w.id) for w in workers)
        for sig in (signal.SIGINT, signal.SIGHUP):
            os.kill(idle, sig)
        os.kill(idle, signal.SIGTERM)           # idle: it leaves
        wait_until("the idle worker to exit", lambda: gone(idle), 30)
        assert pool.poll() is None and len(live_worker_rows(store)) == 2

        submit_quick(store, 3, **MEDIUM)        # one worker takes the batch of 3
        run = wait_until("a run in a kernel", lambda: started_run(store))
        holder = pid_of(run.worker_id)
        other = aborted if holder == busy else busy
        for sig in (signal.SIGINT, signal.SIGHUP):
            os.kill(holder, sig)
        time.sleep(0.3)
        assert not gone(holder) and pool.poll() is None
        os.kill(holder, signal.SIGTERM)         # busy: its run finishes, the rest go back
        wait_until("the busy worker to exit", lambda: gone(holder), 30)
        with store.sessions() as s:
            assert s.get(Run, run.id).status == "done"

        long_sweep = submit_quick(store, 1, **LONG).sweep_id  # the last worker: SIGTERM twice
        long_run = wait_until("the long run in a kernel", lambda: (
            (r := started_run(store)) and r.sweep_id == long_sweep and r))
        assert long_run.worker_id.endswith(f":{other}")
        os.kill(other, signal.SIGTERM)
        time.sleep(0.3)
        os.kill(other, signal.SIGTERM)
        t0 = time.monotonic()
        _, err = pool.communicate(timeout=EXIT_BOUND_S)
        assert time.monotonic() - t0 < ABORT_BOUND_S
    finally:
        if pool.poll() is None:
            os.killpg(pool.pid, signal.SIGKILL)
            pool.communicate()
    assert pool.returncode == 0, err
    text = log.read_text()
    assert "died" not in text and "Traceback" not in text + err
    assert text.count("not replaced") == 3  # each worker's own stop, none replaced
    with store.sessions() as s:
        runs = {r.id: r for r in s.scalars(select(Run))}
        assert runs[long_run.id].status == "queued" and runs[long_run.id].attempts == 0
    lines = done_lines(log)
    for r in runs.values():
        assert r.status in ("done", "queued"), r.id
        assert (lines[r.id], r.attempts) == ((1, 1) if r.status == "done" else (0, 0)), r.id
