"""CI runs the README's test command verbatim (.ci/run says so), and the options that
command gives pytest are ones the `test` extra installs and the pytest configuration
expects (pytest-xdist's -n, with --dist loadgroup from pyproject.toml)."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def readme_test_command() -> str:
    """The shell line after "Set up and run the tests" in the README."""
    text = (ROOT / "README.md").read_text()
    found = re.search(r"Set up and run the tests.*?```sh\n(.*?)\n```", text, re.DOTALL)
    assert found, "the README's test command block is gone"
    return found.group(1).strip()


def test_ci_runs_the_readme_test_command_verbatim():
    command = readme_test_command()
    assert command.startswith("python3 -m venv .venv && ")
    ci_lines = (ROOT / ".ci" / "run").read_text().splitlines()
    # .ci/run names the interpreter ("$PYTHON", python3 by default); the rest is the same
    assert f'"$PYTHON"{command.removeprefix("python3")}' in ci_lines


def test_the_parallel_run_is_installed_and_configured():
    command = readme_test_command()
    assert re.search(r"pytest -q -n 2(\s|$)", command)
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert any(dep.startswith("pytest-xdist")
               for dep in project["project"]["optional-dependencies"]["test"])
    assert "--dist loadgroup" in project["tool"]["pytest"]["ini_options"]["addopts"]
