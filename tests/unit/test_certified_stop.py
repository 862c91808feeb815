"""The certified stop of one run (SolverSettings.stop = "certified", core.certified_stop):
a run stops at the first chunk whose attractor is certified, with the t_end run's regime
and attractor; one that cannot be certified is the t_end run, bit for bit; lambda_max of a
stopped run is the certificate's, checked against linear theory and the long run."""

from __future__ import annotations

import math
from itertools import pairwise

import numpy as np
import pytest

from core.certified_stop import (
    FIRST_CHUNK,
    LINEAR_SHARE,
    attempt,
    chunk_ends,
    near_linear,
    simulate_to_certificate,
)
from core.params import ParameterError, Params
from core.point import run_batch, run_point
from core.solve import SolverSettings, make_grid, simulate
from core.stability import leading_exponent

#: Long enough that a certified stop is a small part of it, short for the unit tier.
T_END = 1e4


def _pair(p: Params, **kw: object) -> tuple[dict[str, object], dict[str, object]]:
    base = SolverSettings(t_end=T_END, **kw)  # type: ignore[arg-type]
    return (run_point(p, base).as_record(),
            run_point(p, SolverSettings(t_end=T_END, stop="certified", **kw)).as_record())  # type: ignore[arg-type]


def test_stop_is_validated_and_defaults_to_the_papers_protocol():
    assert SolverSettings().stop == "t_end"
    with pytest.raises(ParameterError, match=r"stop = 'soon' is out of range: allowed one of "
                                             r"t_end, certified"):
        SolverSettings(stop="soon")


def test_chunks_halve_back_from_t_end_and_the_first_holds_a_window():
    p, s = Params(tau=10.0), SolverSettings(t_end=1e5)
    g = make_grid(p, s)
    ends = [n for n, _ in chunk_ends(p, s, g)]
    assert ends == [1562500, 3125000, 6250000, 12500000, 25000000, 50000000, 100000000]
    assert ends[0] * g.dt >= max(FIRST_CHUNK, s.window)
    # each chunk's middle window is the previous chunk's end window
    for (prev, prev_part), (n, part) in pairwise(chunk_ends(p, s, g)):
        assert n // 2 == prev and part.n_mid and part.mid_start == prev_part.win_start


def test_a_stable_fixed_point_stops_early_with_the_leading_root_as_lambda_max():
    """k = 4, tau = 10: the rest state is stable (root -3.944e-3): the certified run stops
    at the first chunk (1250 of 1e4), with the t_end run's label; its lambda_max is the
    leading root of linear theory (core.stability, independent of the run), and the long
    run's Euler-map estimate agrees within its error and Euler's O(dt) bias (0.2-1.7 %,
    core.lyapunov_bias: 2 % allowed)."""
    p = Params(k=4.0, tau=10.0)
    long, short = _pair(p)
    assert short["t_stop"] == 1250.0 and long["t_stop"] == T_END
    for key in ("regime", "attractor", "certified"):
        assert short[key] == long[key], key
    assert short["certified"] is True and short["stop"] == "certified" and long["stop"] == "t_end"
    root = leading_exponent(p)
    assert short["lambda_max"] == pytest.approx(root, rel=1e-6)
    assert type(short["lambda_max"]) is float  # not numpy's: the JSON encoders' input
    assert abs(float(long["lambda_max"]) - root) <= max(3 * float(long["lambda_err"]), 0.02 * abs(root))
    assert "the leading root" in str(short["certificate"])


def test_a_stable_cycle_stops_early_on_its_orbit_with_lambda_max_0_and_the_next_exponent():
    """k = tau = 10: the orbit (period 10.5146, |mu_2| = 0.6429) is certified after a few
    chunks; period, amplitude and maxima agree with the t_end run's; lambda_max is 0 along
    the flow, as the long run's estimate is within its error."""
    p = Params(k=10.0, tau=10.0)
    long, short = _pair(p)
    assert short["certified"] is True and float(short["t_stop"]) <= T_END / 2
    for key in ("regime", "attractor", "maxima_per_period", "slips"):
        assert short[key] == long[key], key
    assert short["period"] == pytest.approx(long["period"], rel=1e-6)
    assert short["amplitude"] == pytest.approx(long["amplitude"], rel=1e-4)
    assert short["lambda_max"] == 0.0
    assert abs(float(long["lambda_max"])) <= 3 * float(long["lambda_err"])
    mu2 = max(math.hypot(*m) for m in short["multipliers"])  # type: ignore[union-attr]
    nxt = math.log(mu2) / float(short["period"])
    assert f"log|mu_2|/T = {nxt:+.6g}/t" in str(short["certificate"])


@pytest.mark.parametrize("method", ["euler", "rk4"])
def test_a_run_that_cannot_be_certified_is_the_t_end_run_bit_for_bit(method):
    """k = 20, tau = 10: a long transient toward a two-slip state, which Newton does not
    reach within its budget: the certified run goes on to t_end, and its windows, trace,
    logs and final state are those of the paper's run (each kernel's), so its record is
    too (but the runtime and the stop rule)."""
    p = Params(k=20.0, tau=10.0)
    s = SolverSettings(method=method, t_end=T_END, stop="certified")
    stopped = simulate_to_certificate(p, s)
    plain = simulate(p, SolverSettings(method=method, t_end=T_END))
    tr = stopped.trajectory
    assert stopped.certificate is None and stopped.chunks == len(chunk_ends(p, s, plain.grid))
    for a, b in ((tr.window, plain.window), (tr.mid, plain.mid), (tr.trace, plain.trace),
                 (tr.lyap_logs, plain.lyap_logs), (tr.window_t, plain.window_t),
                 (tr.mid_t, plain.mid_t), (tr.final.m_x, plain.final.m_x),  # type: ignore[union-attr]
                 (tr.final.now, plain.final.now)):  # type: ignore[union-attr]
        assert np.array_equal(a, b)
    long, short = _pair(p, method=method)
    assert short["t_stop"] == long["t_stop"] == T_END and short["certified"] is False
    for key in long:
        if key not in ("runtime_s", "stop"):
            assert short[key] == long[key] or (isinstance(long[key], float)
                                               and math.isnan(long[key]) and math.isnan(short[key])), key  # type: ignore[arg-type]


def test_a_blow_up_stops_the_chunks_where_the_t_end_run_stops():
    """k = 12, tau = 1, a = 0.035: Euler leaves its stability region on the fast branch
    (core.point's docstring); both rules re-integrate with the stiff scheme and agree."""
    p = Params(a=0.035, k=12.0, tau=1.0)
    long, short = _pair(p)
    assert long["t_blowup"] is not None and short["t_blowup"] == long["t_blowup"]
    assert short["regime"] == long["regime"] and short["attractor"] == long["attractor"]


def test_the_result_says_where_a_stopped_runs_lambda_max_comes_from():
    """The certificate's lambda_max is the continuous model's, not the run's Euler map's:
    the result says so (lambda_note), where the t_end run's leaves it to the bias note.
    Without lambda_max (lyap off) the stop still works, and none is given, as at t_end."""
    p = Params(k=4.0, tau=10.0)
    stopped = run_point(p, SolverSettings(t_end=T_END, stop="certified"))
    assert stopped.lambda_note.startswith("lambda_max -0.00394") and "leading root" in stopped.lambda_note
    assert run_point(p, SolverSettings(t_end=2000.0)).lambda_note == ""
    bare = run_point(p, SolverSettings(t_end=T_END, stop="certified", lyap=False)).as_record()
    assert bare["t_stop"] == 1250.0 and bare["certified"] is True
    assert math.isnan(float(bare["lambda_max"]))  # type: ignore[arg-type]  # not asked for


def test_a_fixed_point_stops_only_once_the_window_ends_near_linear():
    """k = 5.5, tau = 10, delta = 0.1 (bistable: from delta = 0.5 the run reaches the
    cycle), at the paper's t_end: at the first chunk's end (1562.5) the window already
    decays at the root's rate and is certified, but its end still has a peak-to-peak of m_y
    above 0.011 (eq. 6b's quadratic term over 1 % of the linear one: LINEAR_SHARE); the run
    stops at the next chunk, 3125."""
    p = Params(k=5.5, tau=10.0)
    s = SolverSettings(t_end=1e5, stop="certified")
    early = simulate(p, SolverSettings(t_end=1562.5, window=1000.0))
    summary, cert = attempt(early)
    assert cert is not None and cert.certified and not near_linear(early, summary)
    tail = early.window[1, -early.window.shape[1] // 10:]
    assert float(np.ptp(tail)) > 2 * LINEAR_SHARE * p.F1 / abs(p.q)
    stopped = simulate_to_certificate(p, s)
    assert stopped.trajectory.t_done == 3125.0 and stopped.tries == 2
    assert stopped.certificate is not None and stopped.certificate.certified


def test_run_says_where_a_certified_run_stopped_and_whence_its_lambda_max(capsys):
    """`run --stop certified` names the stop and its time on the solver line, and a
    lambda_max taken from the certificate says so instead of calling it the run's map."""
    from slopetui.cli import main

    assert main(["run", "--k", "4", "--tau", "10", "--stop", "certified", "--t-end", "1e4"]) == 0
    out = capsys.readouterr().out
    solver = next(line for line in out.splitlines() if line.startswith("solver"))
    t_stop = float(solver.split("stopped at t = ")[1].rstrip(")"))
    assert t_stop < T_END
    lam = next(line for line in out.splitlines() if line.startswith("lambda_max"))
    assert "the leading root" in lam and "euler map at dt" not in lam
    assert float(lam.split()[1]) == pytest.approx(leading_exponent(Params(k=4.0, tau=10.0)),
                                                  rel=1e-3)


def test_a_certified_batch_stops_each_run_at_its_certificate():
    """run_batch under stop = certified gives each point its own run_point result (the
    single kernel, in chunks), so that a queued sweep's runs stop early too: a fixed point
    (k = 4) and a cycle (k = tau = 10) stop before t_end, as run alone."""
    points = [Params(k=4.0, tau=10.0), Params(k=10.0, tau=10.0)]
    s = SolverSettings(t_end=T_END, stop="certified")
    batch = [r.as_record() | {"runtime_s": 0} for r in run_batch(points, s)]
    alone = [run_point(p, s).as_record() | {"runtime_s": 0} for p in points]
    assert [r["t_stop"] < T_END for r in batch] == [True, True]
    for got, want in zip(batch, alone, strict=True):
        assert got.keys() == want.keys()
        for key in got:
            assert got[key] == want[key] or (got[key] != got[key] and want[key] != want[key]), key


def test_run_refuses_a_spectrum_under_the_certified_stop(capsys):
    """The tangents of --spectrum integrate to t_end whatever the run's stop: asked
    together, one line naming the field, exit 2, nothing computed."""
    from slopetui.cli import main

    assert main(["run", "--k", "4", "--tau", "10", "--stop", "certified", "--spectrum", "2"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "spectrum" in err and "--stop certified" in err
