"""The store speaks in errors of its own: a driver's error met in a session, a read, a
transaction or a connection becomes a DatabaseFailure (a StoreError) naming the store,
with SQLAlchemy's error as its cause; the command line catches it by type."""

from __future__ import annotations

import inspect

import pytest
from sqlalchemy import text
from sqlalchemy.exc import SQLAlchemyError

import slopetui.cli
from slopetui.store.database import Database
from slopetui.store.failures import DatabaseFailure, StoreError


@pytest.mark.parametrize("how", ["sessions", "read", "transaction", "connection"])
def test_every_way_into_the_database_translates_its_failures(tmp_path, how):
    db = Database(f"sqlite:///{tmp_path / 's.db'}")
    with pytest.raises(DatabaseFailure) as caught, getattr(db, how)() as s:
        s.execute(text("SELECT * FROM nowhere"))
    assert isinstance(caught.value, StoreError)
    assert isinstance(caught.value.__cause__, SQLAlchemyError)
    assert "no such table: nowhere" in str(caught.value) and str(db.path) in str(caught.value)
    db.dispose()


def test_other_errors_pass_unchanged(tmp_path):
    db = Database(f"sqlite:///{tmp_path / 's.db'}")
    with pytest.raises(KeyError), db.transaction():
        raise KeyError("not the database's")
    db.dispose()


def test_the_command_line_knows_no_sqlalchemy():
    source = inspect.getsource(slopetui.cli)
    assert "sqlalchemy" not in source.lower() and "except DatabaseFailure" in source
