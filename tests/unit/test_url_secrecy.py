"""A URL's password is hidden wherever slopetui shows the URL: here the
message that refuses a URL SQLAlchemy cannot parse, which quotes it. The detached pool's
command line and log are tests/integration/test_pool_secrets.py's; the Slurm script's exec
line tests/unit/test_slurm_script.py's."""

from __future__ import annotations

import pytest

from slopetui.cli import main
from slopetui.store.url_text import password_hidden


@pytest.mark.parametrize("text, shown", [
    ("postgresql+psycopg://alice:s3cret@db.example/slopes",
     "postgresql+psycopg://alice:***@db.example/slopes"),
    ("postgresql//alice:s3cret@db.example/x", "postgresql//alice:***@db.example/x"),  # no ':'
    ("alice:s3cret@db.example/x", "alice:***@db.example/x"),                          # no scheme
    ("postgresql://alice:s3c@r:e/t@db.example:5432/x", "postgresql://alice:***@db.example:5432/x"),
    ("postgresql://alice:@db.example/x", "postgresql://alice:***@db.example/x"),
    ("postgresql://alice@db.example:5432/x", "postgresql://alice@db.example:5432/x"),
    ("postgresql://db.example:5432/x", "postgresql://db.example:5432/x"),
    ("sqlite:////tmp/runs.db", "sqlite:////tmp/runs.db"),
    ("", ""),
    # found in review: libpq and psycopg take the password in the query too
    ("postgresql+psycopg://alice@db.example/slopes?password=s3cret",
     "postgresql+psycopg://alice@db.example/slopes?password=***"),
    ("postgresql://alice@h/x?sslmode=require&PASSWORD=s3cret&connect_timeout=5",
     "postgresql://alice@h/x?sslmode=require&PASSWORD=***&connect_timeout=5"),
])
def test_the_password_is_hidden_even_in_a_typo(text, shown):
    assert password_hidden(text) == shown


@pytest.mark.parametrize("url", ["postgresql//alice:s3cret@db.example/slopes",
                                 "alice:s3cret@db.example/slopes"])
def test_a_url_that_does_not_parse_is_refused_without_its_password(url, capsys):
    assert main(["status", "--db", url]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "is not a SQLAlchemy database URL" in err
    assert "s3cret" not in err and "alice:***@db.example/slopes" in err


def test_a_pool_started_with_a_password_on_its_command_line_warns_of_ps(monkeypatch, capsys):
    """slopetui hands its own pools the URL in their environment; a user who types the
    password into `slopetui worker --db` is told that ps shows it, and how to avoid it.
    (The warning comes before the store opens: this one cannot, and the command fails.)"""
    url = "postgresql+psycopg://alice:s3cret@127.0.0.1:1/slopes"
    main(["worker", "--db", url, "--exit-when-idle"])
    err = capsys.readouterr().err
    assert "warning: the password in --db is on this command line" in err
    assert "SLOPETUI_DB" in err and "s3cret" not in err
    main(["worker", "--db", "postgresql+psycopg://alice@127.0.0.1:1/slopes", "--exit-when-idle"])
    assert "warning" not in capsys.readouterr().err


def test_a_password_in_the_query_is_hidden_from_the_store_url_shown_and_warned_of(capsys):
    """Database.display_url (the pool's log lines, `workers`, messages) hid the userinfo's
    password only: SQLAlchemy's hide_password leaves ?password= as it is."""
    from types import SimpleNamespace

    from sqlalchemy.engine import make_url

    from slopetui.store.database import Database
    url = "postgresql+psycopg://alice@127.0.0.1:1/slopes?password=s3cret"
    # the property on the parsed URL alone: a Database connects when it is made
    shown = Database.display_url.fget(SimpleNamespace(url=make_url(url)))  # type: ignore[attr-defined]
    assert "s3cret" not in shown and "password=***" in shown
    main(["worker", "--db", url, "--exit-when-idle"])
    err = capsys.readouterr().err
    assert "warning: the password in --db" in err and "s3cret" not in err
