"""The application's figure folder: $SLOPETUI_FIGURES, else figures/ in the user data
folder, beside the default store; created when missing, a clear error for a file in
the way."""

from __future__ import annotations

from pathlib import Path

import pytest

from slopetui.store.location import DB_ENV, default_url
from slopetui.tui.figure_writing import FIGURES_ENV, default_folder, ready_folder


def test_the_default_is_beside_the_default_store(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    monkeypatch.delenv(FIGURES_ENV, raising=False)
    monkeypatch.delenv(DB_ENV, raising=False)
    monkeypatch.chdir(tmp_path)
    store = Path(default_url().removeprefix("sqlite:///"))
    assert default_folder() == store.parent / "figures"
    assert tmp_path not in default_folder().parents and default_folder() != tmp_path


def test_the_environment_names_the_folder(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    monkeypatch.setenv(FIGURES_ENV, str(tmp_path / "figs"))
    assert default_folder() == tmp_path / "figs"
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv(FIGURES_ENV, "relative/figs")
    assert default_folder() == tmp_path / "relative" / "figs"  # absolute: the notice names it whole
    monkeypatch.setenv(FIGURES_ENV, "  ")
    assert default_folder().name == "figures"  # empty: the default


def test_a_missing_folder_is_created_and_a_file_in_the_way_named(tmp_path: Path) -> None:
    folder = tmp_path / "a" / "b"
    assert ready_folder(folder) == folder and folder.is_dir()
    assert ready_folder(folder) == folder  # already there: fine
    blocker = tmp_path / "file"
    blocker.write_text("")
    with pytest.raises(NotADirectoryError, match=f"{blocker} is a file, not a folder: set \\${FIGURES_ENV}"):
        ready_folder(blocker)
