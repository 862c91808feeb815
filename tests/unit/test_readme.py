"""The README and docs/: their SQL examples run against a real store (and stay read-only),
the notebook example runs, and every command they show is one the CLI takes."""

from __future__ import annotations

import re
from pathlib import Path

from slopetui.cli import main
from slopetui.sweeps.spec import parse_spec
from slopetui.sweeps.submit import submit
from tests.support import QUICK_SOLVER, finish_adaptive, finish_all, submit_quick

README = Path(__file__).resolve().parents[2] / "README.md"


def sql_examples() -> list[str]:
    """The SQL blocks of the README and of docs/*.md (the schema's examples live there)."""
    return [query for path in (README, *sorted((README.parent / "docs").glob("*.md")))
            for query in re.findall(r"```sql\n(.*?)```", path.read_text(), re.DOTALL)]


def test_the_readme_sql_examples_run(db, db_url, capsys):
    examples = sql_examples()
    assert len(examples) >= 4
    for tau in (1.0, 2.0, 3.0):  # sweeps 1-3, so that "sweep 2" and "sweep 3" exist
        submit_quick(db, 4, tau=tau)
    finish_all(db)
    adaptive = submit(db, parse_spec({  # sweep 4: computed and inferred runs
        "x": {"param": "k", "start": 2, "stop": 20, "num": 9},
        "y": {"param": "tau", "start": 0.5, "stop": 10, "num": 5},
        "adaptive": {"levels": 2}, "solver": QUICK_SOLVER}))
    finish_adaptive(db, adaptive.sweep_id)
    for query in examples:
        code = main(["sql", query, "--db", db_url])
        out = capsys.readouterr()
        assert code == 0, (query, out.err)
        assert "row" in out.out


def notebook_examples() -> list[str]:
    return [block for path in (README, *sorted((README.parent / "docs").glob("*.md")))
            for block in re.findall(r"```python\n(.*?)```", path.read_text(), re.DOTALL)
            if "slopetui.open_store" in block]


def test_the_readme_notebook_example_runs(db, db_url):
    """The notebook example, on a store with a finished (k, tau) plane as sweep 1: its
    URL replaced by the test's, every line run, and what it leaves checked."""
    (example,) = notebook_examples()
    submit(db, parse_spec({"x": {"param": "k", "start": 2, "stop": 20, "num": 3},
                           "y": {"param": "tau", "start": 0.5, "stop": 10, "num": 2},
                           "solver": QUICK_SOLVER}))
    finish_all(db)
    url = re.search(r'open_store\("([^"]+)"\)', example)
    assert url is not None, "the example names a store URL"
    scope: dict = {}
    exec(example.replace(url.group(1), db_url), scope)
    assert len(scope["sweeps"]) == 1 and len(scope["runs"]) == 6
    assert scope["table"].shape == (2, 3)  # tau rows, k columns


DOCS = sorted((README.parent / "docs").glob("*.md"))


def shown_commands() -> list[tuple[str, str]]:
    """(file, command line) of every `slopetui ...` command in the shell and text blocks
    of the README and docs/*.md: continuation lines joined, `$ ` prompts, comments and
    redirections dropped, each side of a pipe or && taken apart. Usage synopses (with
    [--option] or [PLACEHOLDER] in brackets) are not commands and are left out."""
    found = []
    for path in (README, *DOCS):
        for block in re.findall(r"```(?:sh|text|bash|console)\n(.*?)```", path.read_text(), re.S):
            pending = ""
            for line in re.sub(r"\\\n\s*", " ", block).split("\n"):
                line = pending + line.strip()
                if line.count('"') % 2 or line.count("'") % 2:  # a quote that goes on
                    pending = line + "\n"
                    continue
                pending = ""
                for part in re.split(r"&&|\|\||;|\|", re.sub(r"^\$ ", "", line)):
                    m = re.match(r"^(?:\S*/)?slopetui(\s.*)?$", part.strip(), re.S)
                    if not m:
                        continue
                    cmd = re.sub(r"\s#.*$", "", m.group(1) or "")
                    cmd = re.sub(r"\s\d?>\s*\S+", "", cmd)  # > file, 2> file
                    if not re.search(r"\[(--|[A-Z])", cmd):
                        found.append((path.name, cmd))
    return found


def test_every_command_the_readme_and_docs_show_parses():
    """Each command shown is one the CLI takes: a renamed option or subcommand in the code
    fails here until the text says the new one."""
    import shlex

    from slopetui.cli import build_parser

    commands = shown_commands()
    assert len(commands) >= 40  # 44 when this was written
    for name, cmd in commands:
        try:
            build_parser().parse_args(shlex.split(cmd))
        except SystemExit as exc:
            assert not exc.code, f"{name}: slopetui {cmd}"
