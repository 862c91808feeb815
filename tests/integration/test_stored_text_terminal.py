"""`slopetui sql --csv` in a fresh process: into a pipe the stored bytes come out exactly
(data); on a real terminal (a pseudo-terminal) they come out escaped (the rest of the
rule, in one process: tests/unit/test_stored_text_escaped.py)."""

from __future__ import annotations

import os
import pty
import sqlite3
import subprocess
import sys

from slopetui.store.open import open_store
from tests.support import submit_quick

HOSTILE = "\x1b]0;owned\x07\x1b[2J\x9b1m\u202eabc"


def hostile_store(db_url: str) -> None:
    db = open_store(db_url)
    submit_quick(db, 2)
    db.dispose()
    with sqlite3.connect(db_url.removeprefix("sqlite:///")) as conn:
        conn.execute("UPDATE sweeps SET name = ?", (HOSTILE,))
    conn.close()


def test_a_pipe_gets_the_stored_bytes(db_url: str) -> None:
    hostile_store(db_url)
    done = subprocess.run([sys.executable, "-m", "slopetui", "sql", "SELECT id, name FROM sweeps",
                           "--csv", "--db", db_url], capture_output=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout == f"id,name\n1,{HOSTILE}\n".encode()


def test_a_terminal_gets_them_escaped(db_url: str) -> None:
    hostile_store(db_url)
    for fmt in (["--csv"], []):
        leader, follower = pty.openpty()
        try:
            proc = subprocess.Popen([sys.executable, "-m", "slopetui", "sql",
                                     "SELECT id, name FROM sweeps", *fmt, "--db", db_url],
                                    stdout=follower, stderr=subprocess.PIPE)
            os.close(follower)
            out = b""
            while True:
                try:
                    chunk = os.read(leader, 4096)
                except OSError:  # EIO: the process closed the terminal
                    break
                if not chunk:
                    break
                out += chunk
            assert proc.wait(timeout=120) == 0
        finally:
            os.close(leader)
        text = out.decode().replace("\r\n", "\n")  # the terminal's own line ends
        assert "\\x1b]0;owned\\x07\\x1b[2J\\x9b1m\\u202eabc" in text, (fmt, text)
        assert not any(ch in text for ch in ("\x1b", "\x07", "\x9b", "\u202e")), (fmt, text)
