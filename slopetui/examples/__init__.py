"""The sweep specs shipped with slopetui, as package data (``slopetui/examples/*.toml``).

They are installed with the package, so they work from any directory: ``slopetui
example`` lists them, ``slopetui example fig4a`` prints one (to edit a copy:
``slopetui example fig4a > fig4a.toml``), and ``slopetui submit fig4a`` queues one when
no file of that name exists.
"""

from __future__ import annotations

from importlib import resources

SUFFIX = ".toml"


def names() -> list[str]:
    """The shipped examples' names (file names without .toml), sorted."""
    return sorted(entry.name[: -len(SUFFIX)] for entry in resources.files(__name__).iterdir()
                  if entry.name.endswith(SUFFIX))


def text(name: str) -> str:
    """The TOML text of the example ``name`` ("fig4a" or "fig4a.toml"); KeyError if no
    example has that name."""
    stem = name[: -len(SUFFIX)] if name.endswith(SUFFIX) else name
    if stem not in names():  # also refuses paths: "../x" is no example's name
        raise KeyError(name)
    return resources.files(__name__).joinpath(stem + SUFFIX).read_text(encoding="utf-8")
