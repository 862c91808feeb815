"""`slopetui show --fold`: the fold of cycles over a (k, tau) plane, computed on request."""

from __future__ import annotations

import pytest

from slopetui.cli import main
from slopetui.sweeps.spec import parse_spec
from slopetui.sweeps.submit import submit
from tests.support import QUICK_SOLVER, finish_all, submit_quick


@pytest.mark.slow
def test_show_draws_the_fold_over_a_k_tau_plane(db, db_url, capsys):
    spec = parse_spec({"x": {"param": "k", "start": 0.5, "stop": 8, "num": 4},
                       "y": {"param": "tau", "start": 5, "stop": 10, "num": 2},
                       "solver": QUICK_SOLVER})
    sweep = submit(db, spec).sweep_id
    finish_all(db)
    assert main(["show", str(sweep), "--fold", "--width", "80", "--height", "24",
                 "--color", "never", "--db", db_url]) == 0
    out = capsys.readouterr()
    assert "fold of cycles" in out.out
    # the folds measured by the report's analysis: 2.3358 at tau = 5, 1.2139 at tau = 10
    assert "tau = 5: k = 2.335" in out.err and "tau = 10: k = 1.213" in out.err


def test_fold_over_a_line_is_refused(db, db_url, capsys):
    sweep = submit_quick(db, 3).sweep_id
    finish_all(db)
    assert main(["show", str(sweep), "--fold", "--width", "80", "--height", "24",
                 "--db", db_url]) == 2
    assert "(c, tau) phase diagram only" in capsys.readouterr().err
