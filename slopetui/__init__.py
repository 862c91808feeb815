"""slopetui: sweeps, storage and terminal views over the mean-field landslide model.

The numerical engine lives in the separate top-level package ``core``; this package
depends on it, never the reverse.

``slopetui.open_store(url)`` (a URL, or a plain path to a SQLite file) opens a store for a
notebook (``slopetui.notebook``: its runs and sweeps as pandas DataFrames). It is imported
on first use (PEP 562), so that ``import slopetui`` (and ``slopetui --help``, which reads
``__version__``) loads no pandas, SQLAlchemy or numpy; ``dir(slopetui)`` names it before.
"""

from __future__ import annotations

import importlib
from typing import Any

__version__ = "0.1.0"

#: Public name -> its module. Named as text, not imported under TYPE_CHECKING: modules of
#: every layer import ``slopetui`` (for ``__version__``), and an import of the notebook face
#: here would be an upward import of theirs to import-linter's layers contract.
_EXPORTS = {"open_store": "slopetui.notebook", "Store": "slopetui.notebook"}


def __getattr__(name: str) -> Any:
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'slopetui' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    """The module's own names and the lazy ones, which exist before their first use."""
    return sorted({*globals(), *_EXPORTS})
