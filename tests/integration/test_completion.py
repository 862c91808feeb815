"""Shell completion (slopetui.cli.completion), asked the way a shell asks: the real CLI in
a fresh process with argcomplete's environment (_ARGCOMPLETE, COMP_LINE, COMP_POINT),
the completions read back from the file named by _ARGCOMPLETE_STDOUT_FILENAME.

The ids come from real stores; a store that is not there, or not a store, completes to
nothing, silently, and is not created.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

from slopetui.cli import build_parser
from slopetui.cli.arguments.completion import SHELLS
from slopetui.cli.completion import attach, complete_runs, complete_sweeps, walk
from slopetui.store.database import parse_url, sqlite_path
from slopetui.store.id_lists import sqlite_file
from slopetui.sweeps.spec import parse_spec
from slopetui.sweeps.submit import submit
from tests.support import QUICK_SOLVER, slopetui_cli, submit_quick


def complete(line: str, tmp_path: Path, *, env: dict[str, str] | None = None,
             shell: str = "bash") -> tuple[list[str], subprocess.CompletedProcess[str]]:
    """The completions of ``line`` (the cursor at its end) and the finished process.
    HOME and XDG_DATA_HOME point into tmp_path, so the default store is a file of the
    test's own (absent unless the test makes it), and $SLOPETUI_DB is unset unless given."""
    out = tmp_path / "completions.out"
    home = tmp_path / "home"
    base = {k: v for k, v in os.environ.items() if k != "SLOPETUI_DB"}
    full = {**base, "HOME": str(home), "XDG_DATA_HOME": str(home / "data"),
            "_ARGCOMPLETE": "1", "COMP_LINE": line, "COMP_POINT": str(len(line)),
            "COMP_TYPE": "9", "_ARGCOMPLETE_IFS": "\n",
            "_ARGCOMPLETE_STDOUT_FILENAME": str(out), **(env or {})}
    if shell == "fish":  # "completion<TAB>description", as argcomplete's fish code asks
        full.update(_ARGCOMPLETE_SHELL="fish", _ARGCOMPLETE_DFS="\t")
    proc = subprocess.run([sys.executable, "-m", "slopetui"], env=full, capture_output=True,
                          text=True, timeout=120)
    text = out.read_text(encoding="utf-8") if out.exists() else ""
    return [c.rstrip(" ") for c in text.split("\n") if c], proc


def ids(completions: list[str]) -> list[str]:
    """The completions that are ids (not options)."""
    return [c for c in completions if not c.startswith("-")]


def described(completions: list[str]) -> dict[str, str]:
    """id -> description, from fish's "id<TAB>description" lines."""
    return dict(c.split("\t", 1) for c in completions if not c.startswith("-"))


def test_subcommands_complete(tmp_path):
    completions, proc = complete("slopetui sh", tmp_path)
    assert (completions, proc.returncode, proc.stderr) == (["show"], 0, "")


def test_options_complete(tmp_path):
    completions, _ = complete("slopetui runs --st", tmp_path)
    assert completions == ["--status"]


def test_choices_complete(tmp_path):
    completions, _ = complete("slopetui runs --regime osc", tmp_path)
    assert completions == ["oscillatory"]


def test_sweep_ids_from_the_db_on_the_line(db, db_url, tmp_path):
    first = submit_quick(db, 3).sweep_id
    named = submit(db, parse_spec({"name": "ramp of k", "solver": QUICK_SOLVER,
                                   "x": {"param": "k", "start": 4, "stop": 12, "num": 2}})).sweep_id
    db.dispose()  # as a user's store between commands: no connection, no -wal file
    completions, proc = complete(f"slopetui show --db {db_url} ", tmp_path)
    assert ids(completions) == [str(named), str(first)]  # newest first
    assert "--width" in completions and proc.stderr == ""
    fish, _ = complete(f"slopetui show --db {db_url} ", tmp_path, shell="fish")
    assert described(fish)[str(named)] == "ramp of k"
    # a SWEEP option, and the digits typed so far
    completions, _ = complete(f"slopetui runs --db {db_url} --sweep {named}", tmp_path)
    assert completions == [str(named)]


def test_sweep_ids_from_slopetui_db(db, db_url, tmp_path):
    sweep = submit_quick(db, 2).sweep_id
    completions, _ = complete("slopetui cancel ", tmp_path, env={"SLOPETUI_DB": db_url})
    assert ids(completions) == [str(sweep)]


def test_sweep_ids_from_the_default_store(tmp_path):
    from slopetui.store.open import open_store

    default = tmp_path / "home" / "data" / "slopetui" / "slopetui.db"
    default.parent.mkdir(parents=True)
    store = open_store(f"sqlite:///{default}")
    sweep = submit_quick(store, 2).sweep_id
    store.dispose()
    completions, _ = complete("slopetui status ", tmp_path)
    assert ids(completions) == [str(sweep)]


def test_run_ids_newest_first_with_sweep_and_status(db, db_url, tmp_path):
    first = submit_quick(db, 3).sweep_id
    second = submit_quick(db, 2).sweep_id
    fish, proc = complete(f"slopetui continue --db {db_url} --from-run ", tmp_path, shell="fish")
    runs = described(fish)
    assert list(runs) == ["5", "4", "3", "2", "1"] and proc.stderr == ""
    assert runs["5"] == f"sweep {second}, queued" and runs["1"] == f"sweep {first}, queued"
    completions, _ = complete(f"slopetui continue --db {db_url} --from-run 4", tmp_path)
    assert completions == ["4"]


def test_stored_names_are_escaped_in_descriptions(db, db_url, evil_sweep, tmp_path):
    fish, _ = complete(f"slopetui show --db {db_url} ", tmp_path, shell="fish")
    description = described(fish)[str(evil_sweep)]
    assert "\x1b" not in description and "\u202e" not in description
    assert description.startswith("\\x1b[2J")


@pytest.mark.parametrize("where", ["on the line", "default"])
def test_no_store_completes_nothing_and_creates_nothing(tmp_path, where):
    missing = tmp_path / "nowhere" / "store.db"
    line = (f"slopetui show --db sqlite:///{missing} " if where == "on the line"
            else "slopetui show ")
    completions, proc = complete(line, tmp_path)
    assert proc.returncode == 0 and proc.stderr == ""
    assert ids(completions) == [] and "--width" in completions  # the options still complete
    assert not missing.parent.exists()
    assert not (tmp_path / "home").exists()  # the default folder was not made either


@pytest.mark.parametrize("content", [b"not a database at all" * 100, b""])
def test_a_file_that_is_no_store_completes_nothing(tmp_path, content):
    bogus = tmp_path / "bogus.db"
    bogus.write_bytes(content)
    completions, proc = complete(f"slopetui cancel --db sqlite:///{bogus} ", tmp_path)
    assert (ids(completions), proc.returncode, proc.stderr) == ([], 0, "")
    assert bogus.read_bytes() == content


def test_an_unreachable_server_completes_nothing(tmp_path):
    # port 9 (discard) on this host: nothing listens, the connection is refused at once
    url = "postgresql+psycopg://nobody@127.0.0.1:9/nothing"
    completions, proc = complete(f"slopetui show --db {url} ", tmp_path)
    assert (ids(completions), proc.returncode, proc.stderr) == ([], 0, "")


def test_the_completers_fail_silently_in_process(tmp_path):
    broken = argparse.Namespace(db="not a url at all")
    assert complete_sweeps(prefix="", parsed_args=broken) == {}
    assert complete_runs(prefix="", parsed_args=broken) == {}
    no_id = argparse.Namespace(db=f"sqlite:///{tmp_path / 'x.db'}")
    assert complete_sweeps(prefix="abc", parsed_args=no_id) == {}


def test_every_sweep_and_run_argument_gets_a_completer():
    parser = build_parser()
    attach(parser)
    by_completer: dict[str, set[str]] = {"sweeps": set(), "runs": set()}
    for action in walk(parser):
        completer = getattr(action, "completer", None)
        kind = "sweeps" if completer is complete_sweeps else "runs" if completer is complete_runs else None
        if kind:
            by_completer[kind].add(action.option_strings[0] if action.option_strings
                                   else action.dest)
    assert {"sweep", "sweeps", "--sweep"} <= by_completer["sweeps"]
    assert "--from-run" in by_completer["runs"]  # its metavar is ID: named in RUN_OPTIONS


def test_a_new_command_gets_completion_by_metavar():
    parser = argparse.ArgumentParser()
    sub = parser.add_subparsers()
    figure = sub.add_parser("figure")
    sweep = figure.add_argument("sweep", metavar="SWEEP")
    run = figure.add_argument("--run", metavar="RUN")
    other = figure.add_argument("--id", metavar="ID")
    attach(parser)
    assert getattr(sweep, "completer", None) is complete_sweeps
    assert getattr(run, "completer", None) is complete_runs
    assert getattr(other, "completer", None) is None


@pytest.mark.parametrize("url", ["sqlite:///relative.db", "sqlite:////abs/store.db",
                                 "sqlite:///~/store.db", "sqlite:///with%20space.db",
                                 "sqlite+pysqlite:///q.db?timeout=3", "sqlite://", "sqlite:///:memory:"])
def test_sqlite_file_reads_urls_as_the_database_does(url):
    assert sqlite_file(url) == sqlite_path(parse_url(url))


@pytest.mark.parametrize("shell", SHELLS)
def test_completion_prints_the_shell_code(shell):
    proc = slopetui_cli("completion", shell)
    assert proc.returncode == 0 and "slopetui" in proc.stdout


@pytest.mark.skipif(shutil.which("bash") is None, reason="no bash")
def test_the_bash_code_is_valid_bash():
    proc = slopetui_cli("completion", "bash")
    assert "complete" in proc.stdout
    subprocess.run(["bash", "-n"], input=proc.stdout, text=True, check=True, timeout=30)


def test_an_unknown_shell_is_refused():
    proc = slopetui_cli("completion", "ksh")
    assert proc.returncode == 2 and proc.stdout == ""
    assert "invalid choice: 'ksh'" in proc.stderr and "bash" in proc.stderr


def test_help_tells_how_to_install():
    proc = slopetui_cli("completion", "--help")
    assert 'eval "$(slopetui completion bash)"' in proc.stdout
    assert "slopetui completion fish | source" in proc.stdout


def test_time_one_completion(db, db_url, tmp_path):
    submit_quick(db, 3)
    db.dispose()
    times = []
    for _ in range(3):
        start = time.perf_counter()
        completions, _ = complete(f"slopetui show --db {db_url} ", tmp_path)
        times.append(time.perf_counter() - start)
        assert ids(completions) == ["1"]
    print(f"\ncompleting `slopetui show --db URL <TAB>`: {min(times) * 1000:.0f} ms "
          f"(best of 3; {', '.join(f'{t * 1000:.0f}' for t in times)} ms)")
