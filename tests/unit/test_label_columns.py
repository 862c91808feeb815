"""The store holds what the labels that follow linear theory write: the attractor unstable-fixed-point
(20 characters, where the column held 16: PostgreSQL enforces VARCHAR lengths), a regime
undetermined with its reason in a detail longer than the 64 characters the column held,
and every flag at once (migration 0010)."""

from __future__ import annotations

from sqlalchemy import text

from core.point import run_point
from core.regimes import REGIMES
from core.result_fields import ATTRACTORS, FLAGS
from slopetui.queue import jobs
from slopetui.store.migrate import current_revision, downgrade, upgrade
from slopetui.store.models import Run
from tests.support import claim_one, submit_quick

REASON = ("at rest; not departed from the unstable rest state (root +1.76e-07/t): headed for "
          "the stable cycle of the subcritical Hopf point at k = 5.97491 (period 60.67, "
          "peak-to-peak 2.4 at k = 6)")


def test_the_longest_words_fit_their_columns():
    columns = Run.__table__.c
    assert max(map(len, ATTRACTORS)) <= columns.attractor.type.length
    assert max(map(len, REGIMES)) <= columns.regime.type.length
    assert len(",".join(FLAGS)) <= columns.flags.type.length


def _store_one(db, **result) -> int:
    """Compute one queued run and complete it with ``result`` over its record."""
    submit_quick(db, 1)
    job = claim_one(db, "test")
    assert job is not None
    record = {**run_point(job.params, job.settings).as_record(), **result}
    jobs.complete(db, job, "test", record)
    return job.run_id


def test_a_run_at_an_unstable_rest_state_is_stored_whole(store):
    result = {"regime": "undetermined", "attractor": "unstable-fixed-point", "detail": REASON,
              "flags": ",".join(FLAGS)}
    run_id = _store_one(store, **result)
    with store.sessions() as s:
        run = s.get(Run, run_id)
        assert (run.regime, run.attractor, run.detail, run.flags) == tuple(result.values())


def test_the_downgrade_keeps_the_run_and_drops_what_0009_cannot_hold(db):
    run_id = _store_one(db, regime="undetermined", attractor="unstable-fixed-point",
                        detail=REASON)
    downgrade(db, "0009")
    assert current_revision(db) == "0009"
    with db.engine.connect() as conn:
        row = conn.execute(text("SELECT status, regime, attractor, detail FROM runs WHERE id = :i"),
                           {"i": run_id}).one()
    assert (row.status, row.regime, row.attractor, row.detail) == ("done", None, None, REASON[:64])
    upgrade(db)
