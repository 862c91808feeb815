"""CI: import every module of the installed packages (a module that imports a package
the install does not declare fails here, not in a user's hands)."""

from __future__ import annotations

import importlib
import pkgutil
import sys

#: Not importable on their own: Alembic runs env inside a migration context, and
#: importing __main__ runs the command line (with no arguments: the application).
NOT_STANDALONE = {"migrations.env", "slopetui.__main__"}

failed = []
count = 0
for top in ("core", "slopetui", "migrations"):
    package = importlib.import_module(top)
    if "site-packages" not in (package.__file__ or ""):
        sys.exit(f"{top} was imported from {package.__file__}, not from the installed venv")
    for info in pkgutil.walk_packages(package.__path__, prefix=f"{top}."):
        if info.name in NOT_STANDALONE:
            continue
        try:
            importlib.import_module(info.name)
            count += 1
        except Exception as exc:  # report every failure, not only the first
            failed.append(f"{info.name}: {type(exc).__name__}: {exc}")
if failed:
    sys.exit("cannot import:\n  " + "\n  ".join(failed))
print(f"imported {count} modules of core, slopetui and migrations")
