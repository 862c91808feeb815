"""Every Hopf branch of the fixed point: the n-th root crossing in closed form
(core.stability), the n-th Hopf point of the noisy rest state (core.hopf_start), checked
against the rest state's roots computed independently (the Chebyshev generator of
core.stability.roots, carried to the noise by core.rest_stability), and
``slopetui continue --from-hopf N``'s input checks."""

from __future__ import annotations

import json
import math

import pytest

from core.hopf_start import hopf_point
from core.orbit import OrbitError
from core.params import Params
from core.rest_stability import NEUTRAL_TOL, rest_roots
from core.stability import characteristic, hopf_friction, hopf_k, hopf_omega, hopf_tau, roots
from slopetui.cli import main
from slopetui.store import open_store
from slopetui.store.jobs import continuations
from slopetui.tui.screens.branches import start_text

F1 = Params().F1


@pytest.mark.parametrize("tau", [2.0, 10.0, 60.0])
@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_the_nth_branch_solves_h_on_the_axis(tau: float, n: int) -> None:
    """At k_n(tau), lam = i omega_n solves h, and omega_n tau lies in ((2n - 1) pi, 2n pi)."""
    k, w = hopf_k(tau, F1, n), hopf_omega(tau, F1, n)
    assert w == pytest.approx(math.sqrt(2 * k - F1 ** 2), rel=1e-12)
    assert abs(characteristic(1j * w, F1, k, tau)) < 1e-9 * max(1.0, w * w)
    assert (2 * n - 1) * math.pi < w * tau < 2 * n * math.pi
    assert hopf_tau(w, F1, branch=n) == pytest.approx(tau, rel=1e-12)


@pytest.mark.parametrize("tau", [2.0, 10.0, 60.0])
def test_the_branches_follow_each_other_and_the_first_is_unchanged(tau: float) -> None:
    ks = [hopf_k(tau, F1, n) for n in (1, 2, 3, 4, 5)]
    assert ks == sorted(ks) and len(set(ks)) == 5
    assert hopf_k(tau, F1) == ks[0]


@pytest.mark.parametrize("n", [2, 3, 4])
def test_at_the_nth_crossing_n_minus_1_pairs_are_already_unstable(n: int) -> None:
    """The generator's roots (independent of the closed form) at k_n(tau = 10), d = 0:
    n - 1 pairs to the right of the axis, one on it at omega_n, the rest to the left."""
    k = hopf_k(10.0, F1, n)
    r = roots(F1, k, 10.0, count=n + 3)
    r = r[abs(r) > 1e-9]
    on_axis = [x for x in r if abs(x.real) < 1e-10]
    assert len(on_axis) == 1 and on_axis[0].imag == pytest.approx(hopf_omega(10.0, F1, n), rel=1e-9)
    assert sum(x.real > 1e-10 for x in r) == n - 1


@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_the_noisy_nth_hopf_point_puts_the_nth_pair_on_the_axis(n: int) -> None:
    """d = 1e-4, tau = 10: at hopf_point(..., n) the carried roots (core.rest_stability)
    have one pair on the axis at the point's omega and n - 1 pairs to the right; the noise
    moves the point by less than 0.05 % from the closed form (measured: k_2 = 6.678483
    against 6.680374, k_3 = 7.571612 against 7.572951, k_4 = 8.832405 against 8.833236)."""
    p = Params(tau=10.0, d=1e-4)
    h = hopf_point(p, "k", n)
    assert h.branch == n
    assert abs(h.value / hopf_k(10.0, F1, n) - 1) < 5e-4
    found = [r.value for r in rest_roots(p.with_(k=h.value), n + 3)]
    on_axis = [x for x in found if abs(x.real) <= NEUTRAL_TOL]
    assert len(on_axis) == 1 and on_axis[0].imag == pytest.approx(h.omega, rel=1e-8)
    assert sum(x.real > NEUTRAL_TOL for x in found) == n - 1


def test_the_second_hopf_point_in_tau_and_in_b() -> None:
    """In tau at k = 8 and in b at k = 8, tau = 10: the second pair is on the axis."""
    p = Params(k=8.0, tau=10.0, d=1e-4)
    for name in ("tau", "b"):
        h = hopf_point(p, name, 2)
        q = p.with_(**{name: h.value})
        found = [r.value for r in rest_roots(q, 6)]
        assert sum(abs(x.real) <= NEUTRAL_TOL for x in found) == 1
        assert sum(x.real > NEUTRAL_TOL for x in found) == 1
    assert hopf_friction(p.with_(d=0.0), "b", 2)[0] != hopf_friction(p.with_(d=0.0), "b", 1)[0]


@pytest.mark.parametrize("bad", [0, -1, 1.5, True])
def test_a_bad_branch_index_is_refused(bad: object) -> None:
    with pytest.raises(ValueError, match="branch index"):
        hopf_k(10.0, F1, bad)  # type: ignore[arg-type]


def test_later_branches_in_other_parameters_say_so() -> None:
    with pytest.raises(OrbitError, match="branch 2"):
        hopf_point(Params(tau=10.0), "v", 2)


@pytest.mark.parametrize("value", ["0", "x", "51"])
def test_continue_names_a_bad_branch_index(value: str, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["continue", "--param", "k", "--from-hopf", value]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and "from-hopf = " in captured.err and "allowed" in captured.err


def test_continue_queues_a_later_branch_with_its_index(tmp_path, capsys: pytest.CaptureFixture[str]
                                                        ) -> None:
    """Before, the continuations table had no place for the index: --submit refused N > 1.
    The branch is computed through a worker in tests/integration/test_branch_worker.py."""
    url = f"sqlite:///{tmp_path}/store.db"
    assert main(["continue", "--param", "k", "--from-hopf", "2", "--tau", "10", "--submit",
                 "--db", url]) == 0
    capsys.readouterr()
    row = continuations.continuation(open_store(url), 1)
    assert (row.start, row.hopf_branch, row.status) == ("hopf", 2, "queued")
    assert start_text(row) == "hopf2 τ=10"  # the Branches screen's start column
    assert main(["branch", "--db", url]) == 0
    assert capsys.readouterr().out.splitlines()[1].split()[:5] == \
        ["1", "k", "hopf2", "tau=10", "queued"]
    assert main(["branch", "1", "--db", url]) == 0
    assert "continuation 1 in k from Hopf point 2: queued" in capsys.readouterr().out
    assert main(["branch", "1", "--db", url, "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["hopf_branch"] == 2
