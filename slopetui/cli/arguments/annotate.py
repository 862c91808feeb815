"""The arguments of ``slopetui rename``, ``note``, ``tag`` and ``sweeps``: what the user
writes on a sweep, and the sweeps listed with it."""

from __future__ import annotations

import argparse

from slopetui.cli.arguments import add_db_option

#: What a tag may be (slopetui.sweeps.annotations.TAG_FORM, which checks it; said here
#: for --help, which must not import the store).
TAG_HELP = ("1 to 32 letters, digits, '.', '_' or '-', starting with a letter or a digit; "
            "read in lower case")


def declare(sub: argparse._SubParsersAction) -> None:
    r = sub.add_parser("rename", help="give a sweep a new name",
                       description="Give a sweep a new name: printable text, 1 to 200 "
                                   "characters. Its runs and results are unchanged.")
    r.add_argument("sweep", metavar="SWEEP", help="sweep id")
    r.add_argument("name", metavar="NAME", help="the new name")
    add_db_option(r)

    n = sub.add_parser("note", help="write, show or remove a sweep's note",
                       description="A sweep's note: what it was for, what was found. With "
                                   "TEXT: replace the note (printable text and line breaks, "
                                   "at most 2000 characters); without: show it.")
    n.add_argument("sweep", metavar="SWEEP", help="sweep id")
    n.add_argument("text", metavar="TEXT", nargs="?", help="the note (replaces the old one)")
    n.add_argument("--clear", action="store_true", help="remove the note")
    add_db_option(n)

    t = sub.add_parser("tag", help="tag a sweep (or --remove tags); runs --tag filters by them",
                       description=f"Add tags to a sweep, remove some (--remove TAG...), or "
                                   f"with neither, show its tags. A tag: {TAG_HELP}. `slopetui runs "
                                   f"--tag T`, `slopetui sweeps --tag T` and "
                                   f"open_store().runs(tag=T) select by tag.")
    t.add_argument("sweep", metavar="SWEEP", help="sweep id")
    t.add_argument("tags", metavar="TAG", nargs="*", help="tags to add")
    t.add_argument("--remove", metavar="TAG", nargs="+", default=[], help="tags to remove")
    add_db_option(t)

    s = sub.add_parser("sweeps", help="list the sweeps with their tags and notes",
                       description="Every sweep, newest first: id, status, runs, tags, name, "
                                   "and the first line of its note.")
    s.add_argument("--tag", metavar="TAG", help="only the sweeps with this tag")
    s.add_argument("--json", action="store_true", help="machine-readable output")
    add_db_option(s)
