"""The history before t = 0 as a choice (core.history): the consistent history agrees
with an independent Radau solution and has no kink; a carried final state continues the
run it came from; bad choices are refused naming the field."""

from __future__ import annotations

import numpy as np
import pytest

from core.batch import simulate_batch
from core.history import CarriedState, half_steps
from core.params import ParameterError, Params
from core.solve import SolverSettings, simulate
from tests.radau_reference import radau


def _rk4(p: Params, t_end: float, history: str = "constant", dt: float = 0.01,
         carried: CarriedState | None = None, points: int = 2):
    return simulate(p, SolverSettings(method="rk4", dt=dt, t_end=t_end, window=dt,
                                      lyap=False, trace_points=points, history=history),
                    carried)


def test_the_consistent_history_agrees_with_radau():
    """RK4 (dt = 0.01) from m_x(t) = delta (1 + t) against Radau by the method of steps
    from the same history, over ten delays: the kernels read the history where Radau's
    first interval evaluates it."""
    p = Params(k=10.0, tau=2.0, delta=0.1)
    ref = radau(k=10.0, tau=2.0, delta=0.1, t_end=20.0,
                history=lambda t: 0.1 * (1.0 + np.asarray(t, dtype=float)))
    got = _rk4(p, 20.0, "consistent").final
    assert got is not None
    want = ref(20.0)[:, 0]
    np.testing.assert_allclose(got.now, want, rtol=1e-6, atol=1e-8)
    # and it is another trajectory than the constant history's
    other = _rk4(p, 20.0).final
    assert other is not None and abs(other.now[1] - got.now[1]) > 1e-3


def test_the_consistent_history_has_no_kink():
    """With the constant history the delayed m_x has a corner at t = tau (slope 0 before,
    delta after), so m_y's second derivative jumps there by k delta; with the consistent
    one it does not (second differences of m_y just before and after tau)."""
    p = Params(k=10.0, tau=1.0, delta=0.1)
    dt = 1e-3
    jumps = {}
    for history in ("constant", "consistent"):
        tr = _rk4(p, 2.0, history, dt=dt, points=2001)
        t, y = tr.trace_t, tr.trace[1]
        i = int(np.argmin(np.abs(t - p.tau)))
        curv, t_c = np.diff(y, 2) / dt ** 2, t[1:-1]  # second differences, at their centres
        # lines through the curvature just before and just after tau (stencils that do
        # not straddle it), extrapolated to tau: the jump without the smooth trend
        before = np.polyfit(t_c[i - 8:i - 2], curv[i - 8:i - 2], 1)
        after = np.polyfit(t_c[i + 1:i + 7], curv[i + 1:i + 7], 1)
        jumps[history] = abs(np.polyval(after, p.tau) - np.polyval(before, p.tau))
    assert jumps["constant"] == pytest.approx(p.k * p.delta, rel=0.05)
    assert jumps["consistent"] < 0.01 * jumps["constant"]


def test_a_carried_state_continues_the_run_it_came_from():
    """Euler hands over its ring as it is: from A's state at T, B to T' ends where A to
    T + T' ends, to the bit. RK4 reads half steps between the carried values by cubic
    Lagrange instead of its Hermite interpolant: within 1e-7 after ten delays (2e-8
    measured)."""
    p = Params(k=12.0, tau=2.0, delta=0.1)
    for method, dt, tol in (("euler", 1e-3, 0.0), ("rk4", 0.01, 1e-7)):
        def run(t_end, history="constant", carried=None, method=method, dt=dt):
            return simulate(p, SolverSettings(method=method, dt=dt, t_end=t_end, window=dt,
                                              lyap=False, trace_points=2, history=history),
                            carried)
        first = run(30.0).final
        assert first is not None
        second = run(20.0, first.name, first).final
        whole = run(50.0).final
        assert second is not None and whole is not None
        np.testing.assert_allclose(second.now, whole.now, rtol=0, atol=tol)
        np.testing.assert_allclose(second.m_x, whole.m_x, rtol=0, atol=tol)


def test_a_carried_state_round_trips_through_bytes():
    tr = _rk4(Params(tau=1.0), 5.0)
    assert tr.final is not None
    back = CarriedState.from_bytes(tr.final.to_bytes())
    assert back.name == tr.final.name
    np.testing.assert_array_equal(back.m_x, tr.final.m_x)


def test_half_steps_are_exact_for_cubics():
    x = np.linspace(-2.0, 0.0, 9)
    f = lambda t: 1 + t - 0.5 * t ** 2 + 0.25 * t ** 3  # noqa: E731
    fine = np.linspace(-2.0, 0.0, 17)
    # the end midpoints are quadratic (3 points): off by f''' h^3 / 16 = 1.5e-3 at h = 0.25
    np.testing.assert_allclose(half_steps(f(x))[1:-1], f(fine)[1:-1], atol=2e-3)
    np.testing.assert_allclose(half_steps(f(x))[3:-3], f(fine)[3:-3], atol=1e-12)


def test_bad_histories_are_refused_naming_the_field():
    with pytest.raises(ParameterError, match="history"):
        SolverSettings(history="linear")
    tr = _rk4(Params(tau=1.0), 5.0)
    assert tr.final is not None
    with pytest.raises(ParameterError, match=r"history.*tau = 2"):
        _rk4(Params(tau=2.0), 5.0, tr.final.name, carried=tr.final)
    with pytest.raises(ParameterError, match="history"):
        _rk4(Params(tau=1.0), 5.0, "state:0123456789abcdef")  # named, not given
    with pytest.raises(ValueError, match="constant history"):
        simulate_batch([Params()], SolverSettings(history="consistent", t_end=10.0))


def test_run_from_the_final_state_of_a_stored_run(db, db_url, capsys):
    """`slopetui run --history run:ID` recomputes the stored run and starts from its end:
    the same as continuing that run (RK4: within 1e-7, the half steps being Lagrange's);
    a run with another tau is refused naming the field, and so is an unknown id."""
    import json

    from slopetui.cli import main
    from tests.support import finish_all, submit_quick
    submit_quick(db, 2, tau=2.0)  # k = 4 and 12, rk4, dt 0.01, t_end 200
    finish_all(db)
    assert main(["run", "--k", "12", "--tau", "2", "--method", "rk4", "--dt", "0.01",
                 "--t-end", "100", "--no-lyap", "--history", "run:2", "--db", db_url,
                 "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["history_given"] == "run:2" and out["history"].startswith("state:")
    p = Params(k=12.0, tau=2.0)
    whole = simulate(p, SolverSettings(method="rk4", dt=0.01, t_end=300.0, lyap=False))
    # the window of the continued run is the last 50 (t_end 100 -> window 50) of 300
    late = whole.window[1][whole.window_t >= 250.0]
    assert out["amplitude"] == pytest.approx(float(np.ptp(late)), rel=1e-6)
    assert main(["run", "--tau", "3", "--method", "rk4", "--dt", "0.01", "--t-end", "10",
                 "--history", "run:2", "--db", db_url]) == 2
    assert "history" in capsys.readouterr().err
    assert main(["run", "--history", "run:99", "--db", db_url, "--t-end", "10"]) == 2
    assert "run:ID of a run in this store" in capsys.readouterr().err
    assert main(["run", "--history", "sideways", "--t-end", "10"]) == 2
    assert "history = " in capsys.readouterr().err
