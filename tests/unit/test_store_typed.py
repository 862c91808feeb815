"""What the store-error dialog opens when a file path is typed: the URL of that very file,
whatever characters its name holds (slopetui.tui.screens.error.store_url)."""

from __future__ import annotations

from pathlib import Path

import pytest

from slopetui.store.database import parse_url, sqlite_path
from slopetui.tui.screens.error import store_url


@pytest.mark.parametrize("name", ["runs#2.db", "what?.db", "100%.db", "a b@c:d.db"])
def test_a_typed_path_names_that_file(tmp_path: Path, name: str) -> None:
    """A "#" would start the URL's fragment, a "?" its query, a "%" an escape: typed
    unescaped into the URL, they named another file (or none) than the one typed."""
    url = store_url(str(tmp_path / name))
    assert sqlite_path(parse_url(url)) == tmp_path / name
