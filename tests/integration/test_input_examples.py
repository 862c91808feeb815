"""The shipped examples work from any directory: `slopetui example` lists and prints them,
`slopetui submit fig4a` takes one by name (a file of that name wins)."""

from __future__ import annotations

import tomllib
from pathlib import Path

from slopetui import examples
from slopetui.cli import main
from slopetui.sweeps.spec import parse_spec, read_spec
from tests.support import slopetui_cli

ROOT = Path(__file__).resolve().parents[2]


def test_every_shipped_example_is_a_valid_new_sweep():
    assert {"fig4a", "k-tau-plane"} <= set(examples.names())
    for name in examples.names():
        spec = parse_spec(read_spec(name), submitting=True)  # the loader submit uses
        assert spec.n_runs > 1


def test_they_are_package_data():
    """Shipped in the wheel: declared in pyproject.toml, inside the package."""
    pyproject = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    assert "*.toml" in pyproject["tool"]["setuptools"]["package-data"]["slopetui.examples"]
    assert (ROOT / "slopetui" / "examples" / "fig4a.toml").is_file()
    assert not (ROOT / "examples").exists()  # one copy, not two that drift apart


def test_example_lists_and_prints(capsys):
    assert main(["example"]) == 0
    listing = capsys.readouterr().out
    assert "fig4a" in listing and "Fig. 4A" in listing and "k-tau-plane" in listing
    assert main(["example", "fig4a"]) == 0
    assert capsys.readouterr().out == examples.text("fig4a")
    assert main(["example", "fig9z"]) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and "NAME: no example 'fig9z'; one of fig4a" in err


def test_submit_takes_an_example_by_name_from_any_directory(tmp_path):
    """Before: `slopetui submit examples/fig4a.toml` worked only inside the checkout."""
    db = f"sqlite:///{tmp_path / 'store.db'}"
    out = slopetui_cli("submit", "fig4a", "--t-end", "2000", "--db", db, cwd=str(tmp_path))
    assert out.returncode == 0, out.stderr
    assert out.stdout.startswith("sweep 1: 43 runs queued")
    out = slopetui_cli("example", "fig4a", cwd=str(tmp_path))
    assert out.returncode == 0 and out.stdout == examples.text("fig4a")


def test_a_file_of_that_name_wins_and_an_unknown_name_is_one_line(tmp_path, capsys):
    db = f"sqlite:///{tmp_path / 'store.db'}"
    own = tmp_path / "fig4a"
    own.write_text('name = "mine"\n[x]\nparam = "k"\nstart = 1\nstop = 2\nnum = 2\n',
                   encoding="utf-8")
    assert main(["submit", str(own), "--t-end", "200", "--db", db]) == 0
    assert "2 runs queued" in capsys.readouterr().out
    assert main(["submit", "fig9z", "--db", db]) == 2
    err = capsys.readouterr().err
    assert err.startswith("slopetui submit: error: fig9z: no such file, and no shipped example")
    assert len(err.splitlines()) == 1
