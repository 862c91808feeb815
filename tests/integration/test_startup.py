"""`slopetui --help` and `slopetui status` start without the imports they do not use.

A one-second `slopetui run` took ~5 s of wall time, most of it imports: every subcommand
module loaded numba, Alembic, SQLAlchemy and the plots at the top. The rule now: a
subcommand module imports what its parser needs at the top and the rest in its handler
(slopetui.cli.options); these tests keep it from drifting back.
"""

from __future__ import annotations

import json
import subprocess
import sys

#: Heavy imports no parser needs: numba and its kernels (~1 s), Alembic (~0.2 s), the
#: application (Textual, rich) and plotext.
NEVER_FOR_HELP = ("numba", "llvmlite", "core.batch", "alembic", "textual", "rich",
                  "plotext", "sqlalchemy", "argcomplete", "pandas", "matplotlib")


def loaded_after(code: str) -> set[str]:
    probe = (f"import sys, json\n{code}\n"
             f"print(json.dumps([m for m in {list(NEVER_FOR_HELP)!r} if m in sys.modules]))")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                         timeout=120, check=True)
    return set(json.loads(out.stdout.strip().splitlines()[-1]))


def test_building_every_parser_loads_no_heavy_module():
    assert loaded_after("from slopetui.cli import build_parser; build_parser()") == set()


def test_status_loads_the_database_driver_only(db_url):
    from slopetui.store import open_store
    open_store(db_url).dispose()  # an up-to-date store: no migration to run
    loaded = loaded_after(f"from slopetui.cli import main; main(['status', '--db', {db_url!r}])")
    assert loaded == {"sqlalchemy"}
