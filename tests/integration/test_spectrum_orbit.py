"""The spectrum on the periodic orbit at k = tau = 10 against its Floquet multipliers (an
independent method: Newton-Krylov shooting and Arnoldi on the monodromy, core.floquet),
and run --spectrum end to end. Seconds each: the orbit's search and the kernels'."""

from __future__ import annotations

import json

import numpy as np

from core.params import Params
from core.periodic_orbit import find_orbit
from core.solve import SolverSettings
from core.spectrum import spectrum
from slopetui.cli import main

ORBIT = Params(k=10.0, tau=10.0)


def test_exponents_on_the_orbit_are_the_flows_zero_then_log_multipliers_over_the_period():
    """Top: the flow's 0. Next: log|mu| / T of the leading nontrivial multipliers, -0.0421
    (real), -0.0541 (a pair: twice), -0.0806 (a pair), to their errors (RK4, dt = 0.01 on
    both sides; the run's second half, 5000 time units, measures)."""
    orbit = find_orbit(ORBIT)
    mu = orbit.multipliers.nontrivial
    floquet = np.log(np.abs(mu)) / orbit.period
    sp = spectrum(ORBIT, SolverSettings(method="rk4", t_end=1e4), 5)
    assert sp is not None
    assert abs(sp.values[0]) <= 3.0 * sp.errors[0] + 1e-4, sp.format()
    for v, e, x in zip(sp.values[1:], sp.errors[1:], floquet[:4], strict=True):
        assert abs(v - x) <= 4.0 * e + 2e-4, (sp.format(), floquet[:4])


def test_run_spectrum_prints_and_stores_the_exponents(capsys):
    assert main(["run", "--k", "10", "--tau", "10", "--method", "rk4", "--t-end", "4000",
                 "--spectrum", "3", "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)
    assert len(rec["spectrum"]) == 3 and len(rec["spectrum_err"]) == 3
    assert abs(rec["spectrum"][0]) < 3.0 * rec["spectrum_err"][0] + 1e-4
    assert rec["spectrum"][1] < -0.03 and rec["attractor"] == "periodic"
    assert main(["run", "--k", "10", "--tau", "10", "--method", "rk4", "--t-end", "4000",
                 "--spectrum", "2"]) == 0
    assert "spectrum   -0.0000(6), -0.0421(7)  (top 2, the m_x shift quotiented out" \
        in capsys.readouterr().out


def test_run_spectrum_refuses_a_bad_count(capsys):
    assert main(["run", "--t-end", "100", "--spectrum", "17"]) == 2
    err = capsys.readouterr().err
    assert err.strip() == ("slopetui run: error: spectrum = '17' is out of range: allowed an "
                           "integer 1 <= N <= 16")
