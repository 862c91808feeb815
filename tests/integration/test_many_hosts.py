"""Many hosts on one PostgreSQL, simulated: pools started as separate processes,
each with a --host-id of its own as if on its own node, reach one server over TCP; workers
and whole pools are killed with SIGKILL at random while they compute; restarted pools
carry on. Every run is done exactly once, every pool did work, no claim exceeded its
batch, and the connections stayed within the pools' budget (--connections): a pool holds
a connection only to claim and to write (slopetui.ops.connection_slots), where before
each worker held two.

The figures the closing note quotes come from a run of this test with -s (it prints
them); benchmarks/bench_pools.py measures the throughput of 1, 2 and 4 pools."""

from __future__ import annotations

import os
import random
import re
import signal
import subprocess
import threading
import time
from collections import Counter
from pathlib import Path

from sqlalchemy import create_engine, func, select, text
from sqlalchemy.engine import make_url

from slopetui.store.models import Run
from slopetui.store.open import open_store
from slopetui.sweeps.spec import parse_spec
from slopetui.sweeps.submit import submit
from tests.integration.pool_support import DONE_LINE, gone, start_pool

#: One connection a pool for two workers: the budget (4) is below the workers (8), where
#: before each worker held two and each pool one more (20).
POOLS, WORKERS, BATCH, CONNECTIONS = 4, 2, 8, 1
#: 25 x 20 = 500 short Euler runs (t_end = 20 at dt = 1e-3: 2e4 steps, a few ms a run in
#: a batch of 8): the test measures the queue, not the kernels. (2,000 and 1,000 runs took
#: two and four times the queue's time of 500 for no more faults: they come with the
#: queue's progress, FAULT_AT.)
PLANE = {"name": "many hosts", "x": {"param": "k", "start": 2, "stop": 20, "num": 25},
         "y": {"param": "tau", "start": 0.5, "stop": 10, "num": 20},
         "solver": {"method": "euler", "dt": 1e-3, "t_end": 20.0, "window": 10.0,
                    "lyap": False}}
N_RUNS = 25 * 20
#: The faults come as the queue drains, not on a clock: fault i once FAULT_AT[i] of the
#: runs are done (10% to 59%: a pool restarted by the last one still finds work), so that
#: the queue is hurt as often on a fast machine as on a loaded one; each at a random pool,
#: a random 0.1-0.4 s after the previous look.
FAULT_AT = [0.10 + 0.07 * i for i in range(8)]
BATCH_LINE = re.compile(r"batch of (\d+)\)")


def _children(pid: int) -> list[int]:
    try:
        return [int(p) for p in Path(f"/proc/{pid}/task/{pid}/children").read_text().split()]
    except OSError:
        return []


def _workers(pool: subprocess.Popen[str]) -> list[int]:
    """The pool's worker processes: multiprocessing spawned them (spawn_main), not its
    resource tracker."""
    found = []
    for pid in _children(pool.pid):
        try:
            if b"spawn_main" in Path(f"/proc/{pid}/cmdline").read_bytes():
                found.append(pid)
        except OSError:  # it exited meanwhile
            pass
    return found


class ConnectionWatch(threading.Thread):
    """Samples the pools' connections to one database every 20 ms; ``peak`` is the most
    seen at once. Not counted: this watcher's own connection (to another database) and
    the test process's (slopetui names each connection after its process)."""

    def __init__(self, server: str, database: str) -> None:
        super().__init__(daemon=True)
        self.engine = create_engine(server, isolation_level="AUTOCOMMIT")
        self.database, self.peak, self.samples = database, 0, 0
        self.halt = threading.Event()

    def run(self) -> None:
        query = text("SELECT count(*) FROM pg_stat_activity WHERE datname = :d "
                     "AND backend_type = 'client backend' AND application_name != :me")
        me = f"slopetui pid {os.getpid()}"
        with self.engine.connect() as conn:
            while not self.halt.wait(0.02):
                n = conn.execute(query, {"d": self.database, "me": me}).scalar_one()
                self.peak, self.samples = max(self.peak, n), self.samples + 1
        self.engine.dispose()


def test_pools_on_many_hosts_survive_kills_and_do_every_run_once(tmp_path, pg_server):
    rng = random.Random(18)
    with pg_server.database() as url:
        name = make_url(url).database
        assert name is not None
        db = open_store(url)
        n_runs = submit(db, parse_spec(PLANE)).n_runs
        assert n_runs == N_RUNS
        logs = [tmp_path / f"host{i}.log" for i in range(POOLS)]
        args = ("-j", str(WORKERS), "--batch", str(BATCH), "--connections", str(CONNECTIONS),
                "--max-attempts", "20", "--exit-when-idle", "--another-pool")

        def start(i: int) -> subprocess.Popen[str]:
            return start_pool(url, logs[i], *args, "--host-id", f"host{i}", group=True)

        watch = ConnectionWatch(pg_server.url.render_as_string(hide_password=False), name)
        watch.start()
        t0 = time.monotonic()
        pools = [start(i) for i in range(POOLS)]
        faults: Counter[str] = Counter()
        try:
            deadline = time.monotonic() + 240
            while time.monotonic() < deadline:
                if all(pool.poll() is not None for pool in pools):
                    break
                time.sleep(rng.uniform(0.1, 0.4))
                n_faults = sum(faults.values())
                if n_faults >= len(FAULT_AT):
                    continue
                with db.sessions() as s:
                    done_now = s.scalar(select(func.count()).select_from(Run)
                                        .where(Run.status == "done"))
                if done_now < FAULT_AT[n_faults] * n_runs or done_now == n_runs:
                    continue
                i = rng.randrange(POOLS)
                pool = pools[i]
                if pool.poll() is not None:
                    continue
                action = rng.choice(["worker", "worker", "pool", "host"])
                if action == "worker" and (workers := _workers(pool)):
                    os.kill(rng.choice(workers), signal.SIGKILL)  # the pool replaces it
                elif action == "pool":  # the pool alone: its workers finish and leave
                    workers = _workers(pool)
                    pool.kill()
                    pool.communicate()
                    for pid in workers:
                        while not gone(pid):
                            time.sleep(0.05)
                    pools[i] = start(i)
                elif action == "host":  # the node: the pool and its workers at once
                    os.killpg(pool.pid, signal.SIGKILL)
                    pool.communicate()
                    pools[i] = start(i)
                else:
                    continue
                faults[action] += 1
            outs = [pool.communicate(timeout=120) for pool in pools]
            elapsed = time.monotonic() - t0
        finally:
            for pool in pools:
                if pool.poll() is None:
                    os.killpg(pool.pid, signal.SIGKILL)
                    pool.communicate()
            watch.halt.set()
            watch.join()

        assert [pool.returncode for pool in pools] == [0] * POOLS, [e for _, e in outs]
        with db.sessions() as s:
            rows = s.execute(select(Run.status, Run.worker_id)).all()
        db.dispose()
        texts = [log.read_text() for log in logs]
        done = Counter(int(m.group(1)) for t in texts for m in DONE_LINE.finditer(t))
        batches = [int(m.group(1)) for t in texts for m in BATCH_LINE.finditer(t)]
        hosts = Counter(wid.split(":")[0] for _, wid in rows)
        print(f"\n{n_runs} runs, {POOLS} pools x {WORKERS} workers, batch {BATCH}, "
              f"{CONNECTIONS} connections a pool: {elapsed:.1f} s; faults {dict(faults)}; "
              f"runs a host {dict(sorted(hosts.items()))}; largest claim {max(batches)}; "
              f"peak connections {watch.peak} in {watch.samples} samples; "
              f"duplicates {sum(n > 1 for n in done.values())}")
        assert {status for status, _ in rows} == {"done"} and len(rows) == n_runs
        assert sum(faults.values()) >= 4, faults  # the queue lasted long enough to be hurt
        assert all(n == 1 for n in done.values()), [r for r, n in done.items() if n > 1]
        # a worker killed between its commit and its log line leaves a run with no line
        assert len(done) >= n_runs - faults["worker"] - faults["host"] * WORKERS * BATCH
        assert set(hosts) == {f"host{i}" for i in range(POOLS)}  # every pool did work
        assert max(batches) <= BATCH
        assert watch.samples > 100 and watch.peak <= POOLS * CONNECTIONS
