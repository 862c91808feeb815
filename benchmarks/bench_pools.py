"""Pools on one PostgreSQL, as on several hosts: throughput and the queue's cost per run
with 1, 2 and 4 pools.

Run:  SLOPETUI_TEST_PG=postgresql+psycopg://postgres@127.0.0.1:PORT/postgres \\
          python benchmarks/bench_pools.py [--runs 2000] [--pools 1 2 4] [--connections 1]

Each configuration gets a fresh database (nothing cached) holding the same RUNS short Euler
runs (t_end = 20 at dt = 1e-3: the kernels take little, so the queue's own cost shows),
and P pools of one worker each, every pool with a --host-id of its own, reaching the server
over the URL given (TCP on loopback here). Printed per configuration:

* throughput: runs / (last result - first start), from the database's own timestamps, so
  the pools' start-up (numba's warm-up, ~1-2 s) is not counted;
* client CPU per run beyond the computation: the CPU of the pools and workers (this
  process's children, reaped) minus that of as many pools that found nothing to do (their
  start-up), over the runs, minus what computing a run costs in this process (the same
  runs through core.run_batch in batches of 8, CPU time): what a run costs a worker to
  claim, begin, look up and write;
* server CPU per run: PostgreSQL's backends, read from the postmaster's reaped children
  (a connection's backend exits with it, so its CPU lands there); needs the server on
  this machine and a superuser (SHOW data_directory).

On this 2-core machine more pools cannot compute faster; the figure that matters is the
cost per run, and that it does not grow with the number of pools (claims do not contend).
"""

from __future__ import annotations

import argparse
import contextlib
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from sqlalchemy import create_engine, func, select
from sqlalchemy.engine import make_url

from slopetui.store.models import Run
from slopetui.store.open import open_store
from slopetui.sweeps.spec import SweepSpec, parse_spec
from slopetui.sweeps.submit import submit

SOLVER = {"method": "euler", "dt": 1e-3, "t_end": 20.0, "window": 10.0, "lyap": False}


def _plane(runs: int) -> SweepSpec:
    nx = 50
    return parse_spec({"name": "bench pools", "x": {"param": "k", "start": 2, "stop": 20, "num": nx},
                       "y": {"param": "tau", "start": 0.5, "stop": 10, "num": runs // nx},
                       "solver": SOLVER})


@contextlib.contextmanager
def pg_database(server: str, name: str):
    """A database of its own on the server, dropped afterwards."""
    admin = create_engine(server, isolation_level="AUTOCOMMIT")
    with admin.connect() as conn:
        conn.exec_driver_sql(f"DROP DATABASE IF EXISTS {name}")
        conn.exec_driver_sql(f"CREATE DATABASE {name}")
    try:
        yield make_url(server).set(database=name).render_as_string(hide_password=False)
    finally:
        with admin.connect() as conn:
            conn.exec_driver_sql(f"DROP DATABASE IF EXISTS {name} WITH (FORCE)")
        admin.dispose()


def compute_cpu_ms(runs: int) -> float:
    """CPU per run of computing the plane's runs as a worker does (batches of 8), here (ms)."""
    from core.point import run_batch
    spec = _plane(runs)
    params = [p for _, _, p in spec.points()]
    settings = spec.solver
    run_batch(params[:8], settings)  # compiled or loaded from the cache: not timed
    t0 = time.process_time()
    for i in range(0, len(params), 8):
        run_batch(params[i:i + 8], settings)
    return 1e3 * (time.process_time() - t0) / len(params)


def _children_cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def _postmaster_cpu(server: str) -> float | None:
    """CPU of the server's exited backends (s), or None if the server is not readable."""
    engine = create_engine(server)
    try:
        with engine.connect() as conn:
            folder = conn.exec_driver_sql("SHOW data_directory").scalar_one()
        pid = int(Path(folder, "postmaster.pid").read_text().split()[0])
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except Exception:  # no superuser, a server elsewhere, not Linux: no figure
        return None
    finally:
        engine.dispose()
    return (int(fields[13]) + int(fields[14])) / os.sysconf("SC_CLK_TCK")  # cutime, cstime


def _pools(url: str, n: int, folder: Path, connections: int) -> None:
    procs = [subprocess.Popen(
        [sys.executable, "-m", "slopetui", "worker", "-j", "1", "--batch", "8",
         "--connections", str(connections), "--exit-when-idle", "--another-pool",
         "--host-id", f"bench{i}", "--log", str(folder / f"pool{i}.log"), "--db", url],
        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
        env={**os.environ, "XDG_STATE_HOME": str(folder / "state")}) for i in range(n)]
    for proc in procs:
        _, err = proc.communicate(timeout=900)
        if proc.returncode != 0:
            raise SystemExit(f"a pool failed ({proc.returncode}): {err}")


def measure(server: str, runs: int, n: int, connections: int, folder: Path) -> dict[str, float]:
    with pg_database(server, f"bench_pools_empty_{os.getpid()}") as url:
        open_store(url).dispose()
        cpu0 = _children_cpu()
        _pools(url, n, folder, connections)
        startup = _children_cpu() - cpu0
    with pg_database(server, f"bench_pools_{os.getpid()}") as url:
        db = open_store(url)
        assert submit(db, _plane(runs)).n_runs == runs
        cpu0, server0 = _children_cpu(), _postmaster_cpu(server)
        _pools(url, n, folder, connections)
        cpu, server1 = _children_cpu() - cpu0, _postmaster_cpu(server)
        with db.sessions() as s:
            first, last, done = s.execute(select(
                func.min(Run.started_at), func.max(Run.finished_at),
                func.count().filter(Run.status == "done"))).one()
        db.dispose()
    assert done == runs, f"{done} of {runs} runs done"
    span = (last - first).total_seconds()
    return {"throughput": runs / span, "span": span,
            "client_ms": 1e3 * (cpu - startup) / runs,
            "server_ms": (1e3 * (server1 - server0) / runs
                          if server0 is not None and server1 is not None else float("nan"))}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--runs", type=int, default=2000)
    ap.add_argument("--pools", type=int, nargs="+", default=[1, 2, 4])
    ap.add_argument("--connections", type=int, default=1)
    args = ap.parse_args()
    server = os.environ.get("SLOPETUI_TEST_PG")
    if not server:
        raise SystemExit("set SLOPETUI_TEST_PG to a PostgreSQL server URL (a superuser)")
    print(f"{args.runs} Euler runs (t_end 20, dt 1e-3), pools of 1 worker, batch 8, "
          f"{args.connections} connection(s) a pool, {os.cpu_count()} cores")
    compute = compute_cpu_ms(args.runs)
    print(f"computing a run here: {compute:.2f} ms CPU")
    print(f"{'pools':>5} {'runs/s':>8} {'span s':>7} {'client CPU ms/run':>18} "
          f"{'queue ms/run':>13} {'server CPU ms/run':>18}")
    for n in args.pools:
        with tempfile.TemporaryDirectory() as tmp:
            t0 = time.monotonic()
            m = measure(server, args.runs, n, args.connections, Path(tmp))
        print(f"{n:>5} {m['throughput']:>8.1f} {m['span']:>7.1f} {m['client_ms']:>18.2f} "
              f"{m['client_ms'] - compute:>13.2f} {m['server_ms']:>18.2f}   "
              f"({time.monotonic() - t0:.0f} s)")


if __name__ == "__main__":
    main()
