"""The arguments of ``slopetui cluster``."""

from __future__ import annotations

import argparse
import sys

from slopetui.ops import slurm
from slopetui.store.location import DB_ENV


def declare(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("cluster", help="run worker pools on a cluster's batch system",
                       description="Write the batch script that runs worker pools on the "
                                   "nodes of a cluster, on a database server they share.")
    systems = p.add_subparsers(dest="cluster_action", metavar="SYSTEM", required=True)
    s = systems.add_parser(
        "slurm", help="write an sbatch script: a job array of worker pools, one per node",
        description="Write an sbatch script: a job array of M tasks, each one node's pool of "
                    "N workers (slopetui worker -j N --exit-when-idle) on a PostgreSQL "
                    "database, with numba's kernels cached on the node. The pools are sent "
                    f"SIGTERM {slurm.SIGNAL_MARGIN_S} s before the time limit (they finish "
                    "the runs in progress), and give back what they still compute at the "
                    "limit. Then prints how to submit, watch and stop it. Nothing is "
                    "submitted; nothing is written on an error (exit 2).")
    s.add_argument("--workers-per-node", metavar="N", required=True,
                   help=f"workers of each pool, and the CPUs its task asks for, 1 to "
                        f"{slurm.MAX_WORKERS_PER_NODE}")
    s.add_argument("--nodes", metavar="M", required=True,
                   help=f"array tasks, one pool (one node) each, 1 to {slurm.MAX_NODES} "
                        "(Slurm's MaxArraySize, 1001 by default, may allow fewer)")
    s.add_argument("--time", metavar="TIME", required=True,
                   help=f"time limit of each task ({slurm.TIME_FORMS}), "
                        f"{slurm.format_time(slurm.MIN_TIME_S)} to "
                        f"{slurm.format_time(slurm.MAX_TIME_S)}")
    s.add_argument("--partition", metavar="NAME",
                   help="Slurm partition, or several separated by commas (default: the "
                        "cluster's default partition)")
    s.add_argument("--db", metavar="URL",
                   help=f"PostgreSQL URL that every node reaches (default: ${DB_ENV}, "
                        "better for a URL with a password: a command line is readable by "
                        "every user); SQLite is refused: it cannot be shared between nodes")
    s.add_argument("--python", metavar="PATH",
                   help="the Python that runs slopetui on the nodes (default: this one, "
                        f"{sys.executable or '?'}: put its virtual environment on the "
                        "shared file system)")
    s.add_argument("-o", "--output", metavar="FILE", default=slurm.DEFAULT_SCRIPT,
                   help=f"the script to write, readable by its owner only (default "
                        f"{slurm.DEFAULT_SCRIPT}, in the current folder)")
    s.add_argument("--force", action="store_true", help="overwrite FILE if it exists")
