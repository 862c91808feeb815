"""The arguments of ``slopetui worker``."""

from __future__ import annotations

import argparse

from slopetui.cli.arguments import add_db_option
from slopetui.ops.connection_slots import DEFAULT_CONNECTIONS
from slopetui.queue import defaults
from slopetui.queue.local_pool import default_jobs, default_log

#: A batch is held in memory whole: the paper's window (1000 time units at 0.01) is 4 MB a
#: run, so 256 runs take 1 GB per worker. Beyond the kernel's 16 slots, a larger batch only
#: keeps the slots full when some runs end early.
MAX_BATCH = 256

#: More processes than this is a typo, not a machine (each one holds a database connection).
MAX_JOBS = 512

#: Heartbeats faster than this load the database for nothing; slower ones than this make
#: dead workers' runs wait (s).
HEARTBEAT_RANGE = (0.1, 600.0)

#: A lease covers at least two heartbeats, and at most a day (s).
MAX_LEASE_S = 86_400.0

MAX_ATTEMPTS_RANGE = (1, 100)

#: A worker's memory budget for a batch (MiB): 64 MiB holds a few paper runs (~10 MB
#: each); 512 GiB is beyond any node we run on.
MEMORY_RANGE = (64, 512 * 1024)

#: A pool's connection budget on a server database (slopetui.ops.connection_slots).
CONNECTIONS_RANGE = (1, 64)

#: --idle-grace: up to a day (s).
MAX_IDLE_GRACE_S = 86_400.0


def declare(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "worker", help="run (or stop) the worker pool that computes queued runs",
        description="Run N worker processes that claim queued runs, compute them and store "
                    "the results. Ctrl-C, SIGTERM or SIGHUP to the pool: the runs being "
                    "computed finish, then the pool exits; a second signal gives them back "
                    "to the queue at once. SIGTERM to one worker stops that worker alone. "
                    "Progress goes to stderr (and the log). Exit status: 0 after a stop, 1 "
                    "if the pool gave up because workers kept dying, 2 for bad options or "
                    "a pool of the store already running on this host.")
    p.add_argument("-j", "--jobs", type=int, default=default_jobs(), metavar="N",
                   help=f"worker processes, 1 to {MAX_JOBS} (default: the cores available, "
                        f"{default_jobs()})")
    p.add_argument("--log", metavar="FILE", help=f"log file, created 0600 (default "
                                                 f"{default_log()}; the foreground pool's "
                                                 "own messages also go to stderr)")
    p.add_argument("--detach", action="store_true",
                   help="run in the background, in its own session: it survives the end of "
                        "the SSH session (prints its pid)")
    p.add_argument("--another-pool", action="store_true",
                   help="start even though a pool of this store already runs on this host "
                        "(by default that is refused: its workers would share the cores)")
    p.add_argument("--stop", action="store_true",
                   help="stop the pools of this store on this host (SIGTERM: the runs being "
                        "computed finish) and wait until they have exited")
    p.add_argument("--now", action="store_true",
                   help="with --stop: give the running runs back to the queue and exit at "
                        "once (a second SIGTERM)")
    p.add_argument("--exit-when-idle", action="store_true",
                   help="exit once nothing is queued or running; while queued runs are left "
                        "only in paused sweeps, once nothing has been claimable for "
                        "--idle-grace seconds")
    p.add_argument("--idle-grace", type=float, default=defaults.IDLE_GRACE_S, metavar="S",
                   help=f"with --exit-when-idle or --owner-pid: seconds with nothing "
                        f"claimable before the pool leaves while work may still come back "
                        f"(a paused sweep, the owner's user), 0 to {MAX_IDLE_GRACE_S:g} "
                        f"(default {defaults.IDLE_GRACE_S:g})")
    p.add_argument("--owner-pid", type=int, metavar="PID",
                   help="the pool works for process PID (the application starts its pool "
                        "so): once PID has exited, the pool leaves when nothing has been "
                        "claimable or running for --idle-grace seconds")
    p.add_argument("--lease", type=float, default=defaults.LEASE_S, metavar="S",
                   help=f"seconds without heartbeat before a run is requeued, from 2 x "
                        f"--heartbeat to {MAX_LEASE_S:g} (default {defaults.LEASE_S:g})")
    p.add_argument("--heartbeat", type=float, default=defaults.HEARTBEAT_S, metavar="S",
                   help=f"seconds between heartbeats, {HEARTBEAT_RANGE[0]:g} to "
                        f"{HEARTBEAT_RANGE[1]:g} (default {defaults.HEARTBEAT_S:g})")
    p.add_argument("--max-attempts", type=int, default=defaults.MAX_ATTEMPTS, metavar="N",
                   help=f"attempts before a run is marked failed, {MAX_ATTEMPTS_RANGE[0]} to "
                        f"{MAX_ATTEMPTS_RANGE[1]} (default {defaults.MAX_ATTEMPTS})")
    p.add_argument("--batch", type=int, default=defaults.DEFAULT_BATCH, metavar="N",
                   help="runs with the same solver settings claimed together, 1 to "
                        f"{MAX_BATCH} (default {defaults.DEFAULT_BATCH}); Euler and RK4 batches "
                        "go through the batched kernels, stiff runs are computed and stored "
                        "one by one")
    p.add_argument("--memory", type=int, default=defaults.MEMORY_MIB, metavar="MIB",
                   help=f"memory the runs of a batch may take together, {MEMORY_RANGE[0]} to "
                        f"{MEMORY_RANGE[1]} MiB (default {defaults.MEMORY_MIB}): a batch of "
                        "long windows is cut to fit, the rest left queued")
    p.add_argument("--connections", type=int, default=DEFAULT_CONNECTIONS, metavar="N",
                   help=f"on a PostgreSQL store: database connections the pool and its "
                        f"workers hold at once, {CONNECTIONS_RANGE[0]} to "
                        f"{CONNECTIONS_RANGE[1]}, whatever -j (default {DEFAULT_CONNECTIONS}; "
                        "a worker needs one only to claim and to write)")
    p.add_argument("--host-id", metavar="NAME",
                   help="the host name the workers' ids carry (default: this host's name); "
                        "several pools on one machine with distinct names stand for "
                        "several hosts (`workers` and `worker --stop` then count them as "
                        "another host's)")
    add_db_option(p)
