"""``slopetui db upgrade|downgrade|current|check|revision``: the schema and health of the
store; ``slopetui db serve``: a PostgreSQL server of one's own for the workers
(slopetui.ops.local_server)."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import TYPE_CHECKING

from slopetui.cli.arguments.db import MAX_CONNECTIONS_RANGE
from slopetui.cli.options import UsageError, int_arg
from slopetui.ops import local_server
from slopetui.queue.stop_signals import STOP_SIGNALS, SignalPipe
from slopetui.store.database import Database
from slopetui.store.failures import StoreError
from slopetui.store.integrity import integrity_problems
from slopetui.store.migrate import alembic_config, current_revision, downgrade, head_revision, plan_downgrade, upgrade
from slopetui.store.open import open_store
from slopetui.store.server_dump import find_pg_dump

if TYPE_CHECKING:
    from slopetui.store.database import Database
    from slopetui.store.migrate import DowngradePlan


def _serve_settings(args: argparse.Namespace) -> local_server.Settings:
    if args.stop or args.status or args.url:
        given = [flag for flag, value in (("--port", args.port), ("--listen", args.listen),
                                          ("--max-connections", args.max_connections))
                 if value is not None]
        if given:
            raise UsageError(f"{given[0]} goes with starting the server, not with "
                             f"{'--stop' if args.stop else '--status' if args.status else '--url'}")
    return local_server.Settings(
        port=None if args.port is None else int_arg(
            "--port", args.port, 1024, 65535, " (below 1024 needs root)"),
        listen=args.listen,
        max_connections=None if args.max_connections is None else int_arg(
            "--max-connections", args.max_connections, *MAX_CONNECTIONS_RANGE))


def _say(text: str) -> None:
    # flushed line by line: a script or a test reads the URL while the server runs
    print(text, flush=True)


def _seconds(timings: dict[str, float], key: str) -> str:
    return f"{timings.get(key, 0.0):.1f} s"


def _say_started(server: local_server.Server) -> None:
    made = (f"new cluster (initdb {_seconds(server.timings, 'initdb')})" if server.created
            else "existing cluster")
    _say(f"PostgreSQL {server.binaries.version} server of {server.folder}: {made}, started "
         f"in {_seconds(server.timings, 'start')}, database ready in "
         f"{_seconds(server.timings, 'setup')}")
    _say(f"listening on {server.listen} port {server.port} (pid {server.pid}), at most "
         f"{server.max_connections} connections; log {server.log}")
    _say(f"give the workers this URL (also in {server.folder / 'url'}; "
         "`slopetui db serve --url` prints it):")
    _say(f"  export SLOPETUI_DB='{server.worker_url}'")
    if server.host_note:
        _say(f"note: {server.host_note}")
    _say(f"on this machine: {server.this_machine_url}")
    _say("Ctrl-C, SIGTERM or SIGHUP (or `slopetui db serve --stop`) stops it")


def _serve_foreground(folder: Path, settings: local_server.Settings,
                      pg_bin: Path | None, default_dir: bool) -> int:
    local_server.check_not_root()  # before looking for programs root could not run
    local_server.check_driver()
    binaries = local_server.find_binaries(pg_bin)
    # the handlers are in before initdb: a signal during the start is acted on after it,
    # never halfway through (the handlers do nothing but wake the loop below)
    # (a SIGHUP that nohup set to be ignored stays ignored: SignalPipe)
    signals = SignalPipe(STOP_SIGNALS)
    try:
        server = local_server.start(folder, settings, binaries, make_parents=default_dir)
        try:
            _say_started(server)
            died = signals.poll() == 0 and server.wait(signals.fileno())
            if not died:
                signals.poll()
                _say(f"{signals.name()}: stopping the server (pg_ctl stop -m fast)")
        finally:
            failure = _stop(server)  # whatever happened above: no server left behind
    finally:
        signals.close()
    if died:
        why = local_server.log_reason(server.log, server.log_offset,
                                      silent="its log says nothing of why (killed by a "
                                             "signal? by the out-of-memory killer?)")
        print(f"slopetui db serve: the server (pid {server.pid}) stopped on its own: {why} "
              f"(log: {server.log})", file=sys.stderr)
        return 1
    if failure:
        print(f"slopetui db serve: {failure} (log: {server.log})", file=sys.stderr)
        return 1
    _say(f"server of {server.folder} stopped")
    return 0


def _stop(server: local_server.Server) -> str | None:
    """Stop the server; None, or why it could not be stopped."""
    try:
        server.stop()
    except StoreError as exc:
        return str(exc)
    return None


def _serve_status(folder: Path) -> int:
    state = local_server.status(folder)
    where = state.folder
    if state.server is None:
        _say(f"{where}: not running" + (
            f" here; it may run on {state.elsewhere}, which started it last" if state.elsewhere
            else "" if state.initialised else " (no server made yet)"))
        return 1
    by = (f"run by `slopetui db serve` pid {state.serve_pid}" if state.serve_pid
          else "no `slopetui db serve` runs it (started by hand, or its serve was killed): "
               "`slopetui db serve --stop` stops it")
    since = time.strftime("%Y-%m-%d %H:%M", time.localtime(state.server.started))
    _say(f"{where}: {state.server.status or 'running'} since {since}, pid "
         f"{state.server.pid}, port {state.server.port}; {by}")
    return 0 if state.server.status in ("ready", "") else 1


def _serve(args: argparse.Namespace) -> int:
    settings = _serve_settings(args)
    folder = Path(args.dir) if args.dir else local_server.default_folder()
    pg_bin = Path(args.pg_bin) if args.pg_bin else None
    if args.status:
        return _serve_status(folder)
    if args.url:
        print(local_server.stored_url(folder))
        return 0
    if args.stop:
        done = local_server.stop_folder(folder, pg_bin)
        _say({"serve": f"server of {folder} stopped (its `slopetui db serve` has exited)",
              "server": f"server of {folder} stopped (pg_ctl stop -m fast)",
              "none": f"no server runs on {folder}"}[done])
        return 0
    return _serve_foreground(folder, settings, pg_bin, default_dir=args.dir is None)


def _backup_note(db: Database, no_backup: bool) -> str:
    if db.path is not None:
        return "A backup copy is made first."
    if no_backup:
        return "No backup is made (--no-backup)."
    return "pg_dump writes a backup first."


def _confirm(db: Database, plan: DowngradePlan, no_backup: bool, assume_yes: bool) -> None:
    if assume_yes:
        return
    drops = ("Every table is dropped, with " if plan.after == "base" else "It drops ")
    question = (f"migrate {db.display_url} back to revision {plan.after}? {drops}"
                f"{plan.dropped}. {_backup_note(db, no_backup)} [y/N] ")
    if not sys.stdin.isatty():
        raise UsageError(f"a downgrade needs confirmation: add --yes (it drops "
                         f"{plan.dropped})")
    if input(question).strip().lower() not in ("y", "yes"):
        raise UsageError("not confirmed; nothing was changed")


def _check(db: Database) -> int:
    problems = integrity_problems(db)
    if db.path is None:
        print(f"{db.display_url}: not a SQLite file; PostgreSQL checks its own pages")
        return 0
    if not problems:
        print(f"{db.path}: ok (integrity and foreign keys)")
        return 0
    print(f"{db.path}: DAMAGED, {len(problems)} problem{'s' if len(problems) > 1 else ''}:")
    for line in problems:
        print(f"  {line}")
    print(f"restore a backup ({db.path.name}.bak-* beside it) or copy out what is readable "
          "with the sqlite3 shell's .recover")
    return 1


def handle(args: argparse.Namespace) -> int:
    if args.db_action == "serve":
        return _serve(args)
    # Alembic here, not at the top: it costs ~0.2 s that `slopetui --help` should not pay

    if args.db_action == "upgrade":
        db = Database(args.db)
        before, after = upgrade(db)
        print(f"{db.display_url}: {before or 'empty'} -> {after}"
              if before != after else f"{db.display_url}: already at {after}")
    elif args.db_action == "downgrade":

        db = Database(args.db)
        plan = plan_downgrade(db, args.revision)
        if not db.is_sqlite and not args.no_backup:
            find_pg_dump()  # refused before asking, not after the answer
        _confirm(db, plan, args.no_backup, args.yes)
        before, after, copy = downgrade(db, args.revision, backup=not args.no_backup)
        kept = (f"backup copy {copy}" if db.is_sqlite else f"backup {copy} (pg_dump)"
                if copy else "no backup (--no-backup)")
        print(f"{db.display_url}: {before} -> {after}; dropped {plan.dropped}; {kept}")
        print("note: any command of this slopetui upgrades it again")
    elif args.db_action == "current":
        db = Database(args.db)
        rev = current_revision(db)
        state = "current" if rev == head_revision() else f"head is {head_revision()}"
        print(f"{db.display_url}: revision {rev or 'none (empty)'} ({state})")
    elif args.db_action == "check":
        try:
            db = Database(args.db)
        except StoreError as exc:  # a file SQLite cannot even open is damaged too
            print(exc)
            return 1
        return _check(db)
    else:
        from alembic import command

        db = open_store(args.db)  # autogenerate compares the models with the head schema
        command.revision(alembic_config(db), message=args.message, autogenerate=True)
    return 0
