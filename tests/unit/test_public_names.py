"""The names scripts and notebooks import from the packages themselves (README: ``from
core import Params, SolverSettings, run_point``, ``from slopetui.store import
open_store``) still resolve, and importing the packages alone stays light: the names load
their modules on first use."""

from __future__ import annotations

import subprocess
import sys

import core
import slopetui.store


def test_the_documented_names_resolve_to_their_defining_modules():
    from core.params import Params
    from core.point import run_point
    from core.solve import SolverSettings
    from slopetui.store.database import Database
    from slopetui.store.open import open_store

    assert (core.Params, core.SolverSettings, core.run_point) == (Params, SolverSettings, run_point)
    assert (slopetui.store.open_store, slopetui.store.Database) == (open_store, Database)
    assert set(core.__all__) <= set(dir(core))


def test_importing_the_packages_loads_no_numpy_numba_or_sqlalchemy():
    probe = ("import sys, core, slopetui.store; "
             "print(sorted(m for m in ('numpy', 'numba', 'sqlalchemy') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"
