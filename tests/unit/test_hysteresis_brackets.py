"""Hysteresis transitions as brackets, then refined: each branch's
transition comes with its grid bracket (the last value on the old attractor, the first on
the new) and is bisected inside it, from the carried state, to a relative tolerance. Up
from rest it lands on the Hopf point (the exact formula, core.stability.hopf_k); down from
the cycle on the fold of cycles (continuation, an independent method). The grid alone
cannot say more than its bracket: on the default 40 points its first values on the new
attractor, 6.269 and 1.077, are one step beyond both, and 1.077 is on the wrong side of
the fold."""

from __future__ import annotations

import math

import pytest
from alembic import command

from core.hysteresis import TOL, WarmPoint, hysteresis, initial_state, refine, settle
from core.orbit import Grid
from core.params import Params
from core.stability import hopf_k
from slopetui.cli import main
from slopetui.queue import hysteresis_jobs
from slopetui.store.database import Database
from slopetui.store.jobs import hysteresis_sweeps
from slopetui.store.migrate import alembic_config, plan_downgrade, upgrade
from slopetui.tui.screens.branches import change_text
from tests.unit.test_hysteresis import FOLD_TAU10
from tests.unit.test_hysteresis_jobs import SPEC, _compute

#: The Hopf point at tau = 10 with the default noise d = 1e-4, as the referee confirmed it
#: (core.rest_stability: 6.14619; the noise-free formula gives 6.14854).
HOPF_TAU10 = 6.1462
#: A short point for the unit tier: at tau = 10 the decisions near k_H are linear
#: theory's, and near the fold the cycle is lost well within 2000 units.
SHORT, WINDOW = 2000.0, 1000.0


def _rest(k: float) -> WarmPoint:
    return WarmPoint(k, "sliding", "at rest", 0.0, -1e-5)


def _cycle(k: float) -> WarmPoint:
    return WarmPoint(k, "oscillatory", "period-1", 1.5, math.nan)


def test_the_onset_is_the_exact_hopf_point_to_the_tolerance():
    """Up from rest at tau = 10 without noise (d = 0, where core.stability's closed form is
    the rest state's Hopf point): the bracket (5.9, 6.4) refined to 1e-5 relative from the
    rest state of k = 5.9 lands on k_H = 6.148541 (the grid's answer was 6.4)."""
    base = Params(tau=10.0, d=0.0)
    g = Grid.of(base, 0.01)
    # at rest, as the sweep hands it over (from delta = 1e-6: no transient left to decay)
    state, _, _, _ = settle(base.with_(k=5.9), g, initial_state(base.with_(delta=1e-6), g),
                            SHORT, WINDOW)
    points = [_rest(5.5), _rest(5.9), WarmPoint(6.4, "oscillatory", "", 2.3, 1e-4, True)]
    found = refine(base, "k", points, [state, state, state], g, SHORT, WINDOW, 1e-5)
    k_h = hopf_k(10.0, base.F1)
    assert found is not None and (found.before, found.after) == (5.9, 6.4)
    assert abs(found.value - k_h) <= 1e-5 * k_h
    assert found.by_theory == found.settles > 0  # every middle value still at rest


def test_the_offset_is_the_fold_of_cycles_to_the_tolerance():
    """Down from the cycle at tau = 10: the bracket (1.3, 1.1) refined to the default 1e-3
    from the cycle carried down from k = 8 lands on the fold of cycles continuation finds
    (1.2139); the grid's first point past it was 1.1 (or 1.077 on the default grid)."""
    base = Params(tau=10.0)
    g = Grid.of(base, 0.01)
    state = initial_state(base.with_(k=8.0), g)
    for k in (8.0, 3.0, 1.3):
        state, _, _, _ = settle(base.with_(k=k), g, state, SHORT, WINDOW)
    points = [_cycle(1.5), _cycle(1.3), WarmPoint(1.1, "sliding", "at rest", 0.0, -1e-3)]
    found = refine(base, "k", points, [state, state, state], g, SHORT, WINDOW)
    assert found is not None and (found.before, found.after) == (1.3, 1.1)
    assert abs(found.value - FOLD_TAU10) <= TOL * FOLD_TAU10
    assert found.by_theory == 0 and found.settles == 7


def test_a_branch_that_keeps_its_attractor_has_no_transition():
    g = Grid.of(Params(tau=2.0), 0.01)
    assert refine(Params(tau=2.0), "k", [_rest(8.0), _rest(8.5)], [], g, SHORT, WINDOW) is None


@pytest.mark.slow
def test_the_default_sweep_at_tau_10_gives_the_hopf_point_and_the_fold():
    """The acceptance test: tau = 10, k from 0.5 to 8 at the default 40 points and default
    settling (~17 s). Brackets: the grid's; refined: within 1e-3 of the Hopf point (the
    exact formula, and the referee's value with the noise) and of the fold (continuation)."""
    h = hysteresis(Params(tau=10.0), "k", 0.5, 8.0, 40)
    step = 7.5 / 39
    assert h.onset is not None and h.offset is not None
    assert h.onset.before == pytest.approx(6.0769, abs=1e-4)
    assert h.onset.after == pytest.approx(6.2692, abs=1e-4)  # the grid's end of the bracket, not the transition
    assert h.offset.before == pytest.approx(1.2692, abs=1e-4)
    assert h.offset.after == pytest.approx(1.0769, abs=1e-4)  # the grid's end, beyond the fold
    assert abs(h.onset.before - h.onset.after) == pytest.approx(step)
    for k_h in (HOPF_TAU10, hopf_k(10.0, Params().F1)):
        assert h.onset_up is not None and abs(h.onset_up - k_h) <= TOL * k_h
    assert h.offset_down is not None and abs(h.offset_down - FOLD_TAU10) <= TOL * FOLD_TAU10


def test_the_stored_sweep_keeps_the_brackets_and_its_tolerance(store):
    """A queued sweep refines to its own tol, and --show prints the bracket."""
    sid = hysteresis_jobs.submit(store, hysteresis_jobs.HysteresisSpec(
        SPEC.params, SPEC.name, SPEC.start, SPEC.stop, SPEC.n_points, SPEC.dt, SPEC.t_settle,
        SPEC.window, 1e-2))
    _compute(store, "w1")
    row = hysteresis_sweeps.hysteresis_sweep(store, sid)
    assert row.status == "done" and row.tol == 1e-2
    before, after = row.onset_up_before, row.onset_up_after
    assert (before, after) == pytest.approx((8.0, 8.0 + 4.0 / 3.0))
    assert before < row.onset_up < after
    k_h = hopf_k(2.0, Params().F1)  # 9.129: the Hopf point at tau = 2
    assert abs(row.onset_up - k_h) <= 1e-2 * k_h


def test_hysteresis_tol_is_checked_and_printed(capsys):
    for bad in ("0", "0.5", "-1", "x"):
        assert main(["hysteresis", "--param", "k", "--from", "1", "--to", "8", "--tol", bad]) == 2
        captured = capsys.readouterr()
        assert captured.out == "" and "tol = " in captured.err
    assert main(["hysteresis", "--param", "k", "--from", "8", "--to", "12", "--points", "3",
                 "--tau", "2", "--t-settle", "300", "--window", "100", "--tol", "1e-2"]) == 0
    text = capsys.readouterr().out
    assert "refined to 0.01 relative; bracket: last on the old attractor 8, first on the new 10)" \
        in text


def test_the_branches_screen_names_the_bracket():
    up = [{"value": 1.0, "regime": "sliding", "growth": -1e-3, "jumped": False}]
    assert change_text("k", "up", up, 6.1431, (6.0769, 6.2692)) == \
        "up leaves rest at k = 6.1431 [6.0769, 6.2692]"
    assert change_text("k", "up", up, 6.2692) == "up leaves rest at k = 6.2692"  # before 0011


def test_0011_keeps_the_sweeps_and_gives_them_no_bracket(new_store_url, backend):
    """A sweep finished before 0011 keeps its grid value, reads no bracket and the default
    tol; the downgrade names the brackets it drops and keeps the refined values."""
    db = Database(new_store_url)
    config = alembic_config(db)
    command.upgrade(config, "0010")
    with db.engine.begin() as conn:
        conn.exec_driver_sql(
            "INSERT INTO hysteresis_sweeps (param, start, stop, n_points, a, b, c, d, k, v, tau, "
            "delta, dt, t_settle, \"window\", engine, status, onset_up, offset_down, n_done, "
            "runtime_s, attempts) VALUES ('k', 0.5, 8, 40, 0.035, 0.7, 6.8, 1e-4, 6, 1, 10, "
            "0.1, 0.01, 6000, 1000, 'x', 'done', 6.269, 1.077, 80, 1.0, 1)")
    upgrade(db)
    row = hysteresis_sweeps.hysteresis_sweep(db, 1)
    assert row is not None and (row.onset_up, row.offset_down, row.tol) == (6.269, 1.077, 1e-3)
    assert row.onset_up_before is None and row.offset_down_after is None
    with db.engine.begin() as conn:
        conn.exec_driver_sql("UPDATE hysteresis_sweeps SET onset_up_before = 6.0769, "
                             "onset_up_after = 6.2692, onset_up = 6.143")
    assert plan_downgrade(db, "0010").dropped == "the transition brackets of 1 hysteresis sweep"
    command.downgrade(config, "0010")
    with db.engine.begin() as conn:
        kept = conn.exec_driver_sql("SELECT onset_up, offset_down FROM hysteresis_sweeps").all()
    assert [tuple(r) for r in kept] == [(6.143, 1.077)]
    db.dispose()


def test_the_spec_default_is_the_engines():
    """The queue's spec names core.hysteresis.TOL's value without importing it (numpy)."""
    assert hysteresis_jobs.HysteresisSpec.tol == TOL


@pytest.mark.parametrize("tol", [0.0, 0.5])
def test_a_stored_tol_out_of_range_fails_the_sweep_at_its_claim(store, tol):
    """A hand-edited tol is refused with its name and range, not bisected forever."""
    sid = hysteresis_jobs.submit(store, SPEC)
    with store.engine.begin() as conn:
        conn.exec_driver_sql(f"UPDATE hysteresis_sweeps SET tol = {tol}")
    assert hysteresis_jobs.claim(store, "w1") is None
    row = hysteresis_sweeps.hysteresis_sweep(store, sid)
    assert row is not None and row.status == "failed" and "tol = " in row.error
