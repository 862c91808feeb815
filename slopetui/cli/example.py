"""``slopetui example [NAME]``: list the shipped sweep specs, or print one."""

from __future__ import annotations

import argparse
import tomllib

from slopetui import examples
from slopetui.cli.options import UsageError


def handle(args: argparse.Namespace) -> int:
    if args.name is None:
        for name in examples.names():
            title = tomllib.loads(examples.text(name)).get("name", "")
            print(f"{name:14} {title}")
        return 0
    try:
        text = examples.text(args.name)
    except KeyError:
        raise UsageError(f"NAME: no example {args.name!r}; one of "
                         f"{', '.join(examples.names())}") from None
    print(text, end="")
    return 0
