"""The arguments of ``slopetui reproduce``."""

from __future__ import annotations

import argparse

from slopetui.cli.arguments import add_db_option
from slopetui.sweeps.sizes import CONFIRM_ABOVE_RUNS

#: The report's default: every phase diagram at 20 x 20 at the paper's t_end, about
#: 5300 runs, ~40 min on 2 cores (see docs/reproduction.md for the measured time).
REPORT_RESOLUTION = 20


def declare(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "reproduce", help="queue the paper's figures; write the reproduction report",
        description="List the presets of the paper's figures, queue one (or all), or compute "
                    "them all and write docs/reproduction.md: the paper's claims beside what "
                    "slopetui measures.")
    p.add_argument("figure", nargs="?", metavar="FIG",
                   help="a preset key (see --list), or 'all'")
    p.add_argument("--list", action="store_true", help="list the presets")
    p.add_argument("--report", action="store_true",
                   help="compute every preset (through the queue, with a local pool) and "
                        "write the report")
    p.add_argument("--resolution", type=int, metavar="N",
                   help="points per axis of a phase diagram (default: the preset's full "
                        f"resolution; {REPORT_RESOLUTION} for --report)")
    p.add_argument("--t-end", dest="t_end", type=float, metavar="T",
                   help="end time (default: the paper's 1e5)")
    p.add_argument("--out", default="docs/reproduction.md", metavar="FILE",
                   help="where --report writes (default docs/reproduction.md)")
    p.add_argument("-j", "--jobs", type=int, metavar="N",
                   help="worker processes for --report (default: the cores available)")
    p.add_argument("--yes", action="store_true",
                   help=f"queue more than {CONFIRM_ABOVE_RUNS} runs")
    p.add_argument("--no-orbits", dest="orbits", action="store_false",
                   help="--report without the continuation analysis of the periodic orbits "
                        "(the fold of cycles over tau takes a few minutes)")
    add_db_option(p)
