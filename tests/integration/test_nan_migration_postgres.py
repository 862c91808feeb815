"""Revision 0007 on PostgreSQL: the NaN measurements an older slopetui stored become NULL
(PostgreSQL orders NaN above every number, so `lambda_max > 0` held for them), and read
back as NaN as before."""

from __future__ import annotations

import math

from sqlalchemy import select, text

from slopetui.store.database import Database
from slopetui.store.migrate import downgrade, upgrade
from slopetui.store.models import Run
from slopetui.store.open import open_store
from tests.support import finish_all, submit_quick


def test_stored_nan_becomes_null_and_reads_as_nan(pg_server):
    with pg_server.database() as url:
        db = open_store(url)
        submit_quick(db, 2)
        finish_all(db)
        downgrade(db, "0006")
        with db.transaction() as s:  # what an older slopetui wrote: NaN itself
            s.execute(text("UPDATE runs SET period = 'NaN'::float8, lambda_max = 'NaN'::float8 "
                           "WHERE id = 1"))
            assert s.execute(text("SELECT count(*) FROM runs WHERE lambda_max > 0")).scalar() >= 1
        db.dispose()
        db = Database(url)
        upgrade(db)
        with db.sessions() as s:
            assert s.execute(text("SELECT lambda_max IS NULL AND period IS NULL FROM runs "
                                  "WHERE id = 1")).scalar()
            run = s.scalars(select(Run).where(Run.id == 1)).one()
            assert math.isnan(run.lambda_max) and math.isnan(run.period)
            assert s.execute(text("SELECT count(*) FROM runs WHERE id = 1 AND "
                                  "lambda_max > 0")).scalar() == 0
        db.dispose()
