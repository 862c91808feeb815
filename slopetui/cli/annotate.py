"""``slopetui rename | note | tag | sweeps``: what the user writes on a sweep (its name, a
note, tags; ``slopetui.sweeps.annotations`` checks them), and the sweeps listed with it.

Stored text reaches the terminal through ``slopetui.display_text`` (a name or a note
written by another tool may hold an escape sequence); ``--json`` writes it as stored
(``slopetui.json_text`` escapes control characters itself).
"""

from __future__ import annotations

import argparse

from slopetui.cli.options import UsageError, open_db, sweep_arg
from slopetui.display_text import terminal_safe, terminal_safe_lines
from slopetui.json_text import json_text
from slopetui.store.sweeps.annotations import sweep_list
from slopetui.sweeps import annotations as sweep_annotations

#: How much of a note's first line ``slopetui sweeps`` shows (characters).
NOTE_SHOWN = 60


def handle_rename(args: argparse.Namespace) -> int:
    sweep = sweep_arg(args.sweep)
    name = sweep_annotations.check_name(args.name)  # before the database opens
    sweep_annotations.rename(open_db(args), sweep, name)
    print(f"sweep {sweep} renamed {terminal_safe(name)!r}")
    return 0


def handle_note(args: argparse.Namespace) -> int:
    sweep = sweep_arg(args.sweep)
    if args.clear and args.text is not None:
        raise UsageError("note: give TEXT or --clear, not both")
    if args.text is not None:
        sweep_annotations.check_note(args.text)  # before the database opens
    db = open_db(args)
    if args.text is None and not args.clear:
        note = sweep_annotations.labels(db, sweep).note
        print(terminal_safe_lines(note) if note else f"sweep {sweep} has no note")
        return 0
    stored = sweep_annotations.set_note(db, sweep, "" if args.clear else args.text)
    print(f"sweep {sweep}: note {'saved' if stored else 'removed'}")
    return 0


def handle_tag(args: argparse.Namespace) -> int:
    sweep = sweep_arg(args.sweep)
    # checked before the database opens: a bad tag writes nothing
    add = [sweep_annotations.check_tag(t, "TAG") for t in args.tags]
    remove = [sweep_annotations.check_tag(t, "--remove") for t in args.remove]
    db = open_db(args)
    if add or remove:
        after = sweep_annotations.change_tags(db, sweep, add, remove)
    else:
        after = sweep_annotations.labels(db, sweep).tags
    # stored text: checked when slopetui wrote it, but any tool may write the store
    print(f"sweep {sweep} tags: {terminal_safe(', '.join(after)) or 'none'}")
    return 0


def handle_sweeps(args: argparse.Namespace) -> int:
    tag = None if args.tag is None else sweep_annotations.check_tag(args.tag, "--tag")
    listed = sweep_list(open_db(args), tag)
    if args.json:
        print(json_text([{"id": s.id, "name": s.name, "status": s.status,
                          "created_at": s.created_at.isoformat(), "runs": s.n_runs,
                          "tags": list(s.tags), "note": s.note} for s in listed]))
        return 0
    if not listed:
        print(f"no sweep is tagged {tag}" if tag else "no sweeps yet: slopetui submit --help")
        return 0
    print(f"{'id':>4}  {'status':9} {'runs':>7}  {'tags':20} name")
    for s in listed:
        print(f"{s.id:>4}  {terminal_safe(s.status):9} {s.n_runs:>7}  "
              f"{terminal_safe(','.join(s.tags)) or '-':20} {terminal_safe(s.name)}")
        if s.note:
            first = s.note.splitlines()[0]
            more = "…" if len(first) > NOTE_SHOWN or "\n" in s.note else ""
            print(f"{'':6}note: {terminal_safe(first[:NOTE_SHOWN])}{more}")
    return 0
