"""The arguments of ``slopetui example``."""

from __future__ import annotations

import argparse


def declare(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "example", help="list the shipped sweep specs, or print one",
        description="Without NAME: list the sweep specs shipped with slopetui. With NAME: "
                    "print its TOML, e.g. `slopetui example fig4a > fig4a.toml` to edit a "
                    "copy. `slopetui submit NAME` queues one directly.")
    p.add_argument("name", nargs="?", metavar="NAME", help="an example's name, e.g. fig4a")
