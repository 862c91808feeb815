"""A sweep's diagram: what a read returns (``result``), its SQL (``statements``), read through
SQLAlchemy (``reads``) or, for ``slopetui show`` on a SQLite file, through the standard
library's sqlite3 (``sqlite_reads``). Light: this package imports nothing, so that the
sqlite3 reader loads no SQLAlchemy.
"""
