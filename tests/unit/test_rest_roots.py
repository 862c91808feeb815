"""core.rest_stability.rest_roots and ``slopetui roots``: the rest state's characteristic
roots, checked against the characteristic function itself and the exact Hopf point."""

from __future__ import annotations

import json
import math

import pytest

from core.params import Params
from core.rest_stability import NEUTRAL_TOL, rest_exponent, rest_roots
from core.stability import characteristic, hopf_k


@pytest.mark.parametrize("k, tau", [(4.0, 10.0), (10.0, 10.0), (12.0, 0.5), (2.0, 20.0)])
def test_noise_free_roots_solve_the_characteristic_function(k: float, tau: float) -> None:
    """At d = 0 each delay root solves h (eq. 20's delay factor) and each variance root
    the variance block's factors; they come rightmost first, none with Im < 0."""
    p = Params(k=k, tau=tau, d=0.0)
    found = rest_roots(p, 8)
    assert [r.value.real for r in found] == sorted((r.value.real for r in found), reverse=True)
    for r in found:
        assert r.value.imag >= 0.0
        lam = r.value
        if r.factor == "delay":
            assert abs(characteristic(lam, p.F1, p.k, p.tau)) < 1e-9 * max(1.0, abs(lam) ** 2)
        else:
            f = (lam + p.F1) * (lam * lam + 2 * p.F1 * lam + 4 * p.k)
            assert abs(f) < 1e-9 * max(1.0, abs(lam) ** 3)
    assert sum(r.factor == "delay" for r in found) == 8


def test_at_the_exact_hopf_point_the_leading_root_is_on_the_axis() -> None:
    """k = k_H(tau) (the closed form of core.stability): Re = 0 to round-off and
    Im = omega with omega^2 = 2k - F'^2: undecided, by the command too."""
    from slopetui.sweeps.rest_roots import verdict
    p0 = Params(tau=10.0, d=0.0)
    k = hopf_k(10.0, p0.F1)
    p = Params(k=k, tau=10.0, d=0.0)
    lead = rest_roots(p)[0].value
    assert abs(lead.real) <= NEUTRAL_TOL
    assert lead.imag == pytest.approx(math.sqrt(2 * k - p.F1 ** 2), rel=1e-9)
    assert verdict(rest_roots(p)) == "undecided"


@pytest.mark.parametrize("k", [6.1, 6.2, 10.0])
def test_with_noise_the_leading_root_is_the_rest_exponent(k: float) -> None:
    """d = 1e-4 (the default): the leading carried root is the one rest_exponent finds (the
    noisy Hopf point at tau = 10 is k = 6.14619: 6.1 stable, 6.2 unstable)."""
    p = Params(k=k, tau=10.0)
    lead = rest_roots(p)[0].value.real
    assert lead == pytest.approx(rest_exponent(p), rel=1e-9, abs=1e-15)
    assert (lead < 0) == (k < 6.14619)


def test_the_command_prints_json_and_names_a_bad_count(capsys: pytest.CaptureFixture[str]) -> None:
    from slopetui.cli import main
    assert main(["roots", "--k", "10", "--tau", "10", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["stability"] == "unstable" and out["unstable_roots"] == 4
    # 6 of h, 2 of the variance block (Im >= 0)
    assert out["params"]["k"] == 10.0 and len(out["roots"]) == len(out["factors"]) == 8
    assert main(["roots", "--count", "41"]) == 2
    assert "count" in capsys.readouterr().err
    assert main(["roots", "--k", "10", "--tau", "10", "--plot"]) == 0
    assert "Re > 0" in capsys.readouterr().out


def test_rest_exponent_is_memoised_and_rest_root_is_a_class():
    """A decorator left above the wrong definition once memoised the dataclass and not the
    function: each analysis asked linear theory afresh (106 -> 65 ms at k = 6, tau = 10)."""
    import dataclasses

    from core.params import Params
    from core.rest_stability import RestRoot, rest_exponent

    assert isinstance(RestRoot, type) and dataclasses.is_dataclass(RestRoot)
    rest_exponent.cache_clear()
    p = Params(k=6.0, tau=10.0)
    rest_exponent(p)
    rest_exponent(p)
    assert rest_exponent.cache_info().hits == 1
