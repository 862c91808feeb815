"""Control characters in names: refused at submission, shown escaped wherever stored text
is shown (a store written by an older slopetui or another tool may hold anything)."""

from __future__ import annotations

import io
import sys

import pytest

from slopetui.cli import main
from slopetui.display_text import terminal_safe, terminal_safe_lines, unsafe_characters
from slopetui.store.models import Run

#: The evil_sweep fixture's name (tests.support.EVIL) as the terminal shows it.
SHOWN = "\\x1b[2J\\x1b[31mevil\\u202eabc"


@pytest.mark.parametrize("char", ["\x1b", "\x9b", "\x07", "\x08", "\r", "\n", "\t", "\x7f",
                                  "\x00", "\u202a", "\u202e", "\u2066", "\u2069", "\u200e",
                                  "\u200f", "\u061c", "\u2028"])
def test_terminal_safe_escapes_controls_and_bidi(char):
    assert unsafe_characters(f"a{char}b") == [terminal_safe(char)]
    shown = terminal_safe(f"a{char}b")
    assert shown.startswith("a\\") and shown.endswith("b") and char not in shown
    assert shown.isprintable()


def test_the_scan_and_the_definition_agree():
    """terminal_safe's one-pass regex (UNSAFE) finds exactly is_unsafe's characters (Cc
    lies below U+00A0; the other unsafe ones below U+3000)."""
    from slopetui.display_text import UNSAFE, is_unsafe
    for code in range(0x3000):
        assert (UNSAFE.match(chr(code)) is not None) == is_unsafe(chr(code)), hex(code)


def test_plain_text_is_left_as_it_is():
    for text in ("Fig. 4A: bifurcation in k", "τ = 10, δ = 0.1 — k ∈ [3, 24]", "[bold]x", ""):
        assert terminal_safe(text) == text and unsafe_characters(text) == []
    assert terminal_safe(None) == ""
    assert terminal_safe_lines("a,\x1b\nb,c\n") == "a,\\x1b\nb,c\n"


@pytest.mark.parametrize("char", ["\x1b", "\u202e", "\u2066", "\t", "\n", "\u200f", "\u061c",
                                  "\x9b", "\x7f"])
def test_a_name_with_control_characters_is_refused(tmp_path, capsys, char):
    store = tmp_path / "store.db"
    code = main(["submit", "--x", "k=1:2:2", "--name", f"ab{char}c", "--db", f"sqlite:///{store}"])
    assert code == 2
    captured = capsys.readouterr()
    lines = captured.err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("slopetui submit: error: name: ")
    assert terminal_safe(char) in lines[0] and char not in lines[0]
    assert "Traceback" not in captured.err and captured.out == "" and not store.exists()


def test_a_spec_files_name_is_checked_too(tmp_path, capsys):
    spec = tmp_path / "spec.toml"
    spec.write_text('name = "\\u001b]0;owned\\u0007"\n[x]\nparam = "k"\nstart = 1\nstop = 2\n'
                    'num = 2\n', encoding="utf-8")
    store = tmp_path / "store.db"
    assert main(["submit", str(spec), "--db", f"sqlite:///{store}"]) == 2
    err = capsys.readouterr().err
    assert "name: control characters are not allowed (\\x1b, \\x07)" in err
    assert not store.exists()


def test_unicode_names_are_welcome(tmp_path, capsys):
    store = f"sqlite:///{tmp_path / 'store.db'}"
    name = "τ = 10, δ = 0.1 — k ∈ [3, 24]"
    assert main(["submit", "--x", "k=1:2:2", "--t-end", "200", "--name", name, "--db", store]) == 0
    capsys.readouterr()
    assert main(["status", "--db", store]) == 0
    assert name in capsys.readouterr().out


@pytest.fixture
def evil_regime(db, evil_sweep):
    """The same, with a run whose regime (free text in the store) is an escape."""
    with db.transaction() as s:
        run = s.get(Run, 1)
        run.status, run.regime = "done", "\x1b[2Jx"
    return evil_sweep


def test_status_and_show_print_stored_names_escaped(db, db_url, evil_sweep, capsys):
    assert main(["status", "--db", db_url]) == 0
    out = capsys.readouterr().out
    assert SHOWN in out and "\x1b" not in out and "\u202e" not in out
    assert main(["status", "--json", "--db", db_url]) == 0   # JSON escapes as \u001b
    out = capsys.readouterr().out
    assert "\x1b" not in out and "\\u001b[2J" in out
    assert main(["show", str(evil_sweep), "--width", "80", "--height", "20", "--color", "never",
                 "--db", db_url]) == 0
    out = capsys.readouterr().out
    assert "\x1b" not in out and "\u202e" not in out and "\\x1b[31mevil" in out


def test_runs_prints_a_stored_regime_escaped(db, db_url, evil_regime, capsys):
    assert main(["runs", "--db", db_url]) == 0
    out = capsys.readouterr().out
    assert "\\x1b[2Jx" in out and "\x1b" not in out


class Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_csv_is_raw_into_a_file_and_escaped_on_a_terminal(db, db_url, evil_regime, capsys,
                                                          monkeypatch, tmp_path):
    out = tmp_path / "runs.csv"
    assert main(["export", str(evil_regime), "--csv", "-o", str(out), "--db", db_url]) == 0
    assert "\x1b[2Jx" in out.read_text(encoding="utf-8")   # data: exactly what is stored
    terminal = Terminal()
    monkeypatch.setattr(sys, "stdout", terminal)
    assert main(["export", str(evil_regime), "--csv", "--db", db_url]) == 0
    assert main(["runs", "--csv", "--db", db_url]) == 0
    text = terminal.getvalue()
    assert "\x1b" not in text and text.count("\\x1b[2Jx") == 2 and text.count("\n") == 8
