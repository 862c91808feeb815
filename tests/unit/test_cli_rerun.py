"""``slopetui rerun ID``: a stored run queued again with the certified stop, as the
application's certified re-run queues it; a bad id is one line naming it."""

from __future__ import annotations

import json

from slopetui.cli import main
from slopetui.store.queries import run_by_id
from slopetui.sweeps.spec import parse_spec
from tests.support import finish_all, submit_quick


def test_rerun_queues_the_run_again_with_the_certified_stop(db, db_url, capsys):
    submit_quick(db, 2, t_end=600.0)
    finish_all(db)
    assert main(["rerun", "2", "--db", db_url, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["n_runs"] == 1
    with db.sessions() as s:
        from slopetui.store.models import Sweep
        spec = parse_spec(s.get(Sweep, out["sweep_id"]).spec)
    original = run_by_id(db, 2)
    assert spec.solver.stop == "certified" and spec.x.values()[0] == original.k
    assert spec.solver.t_end == original.t_end and spec.solver.method == original.method


def test_a_bad_id_is_one_line_naming_it(db, db_url, capsys):
    assert main(["rerun", "7", "--db", db_url]) == 2
    err = capsys.readouterr().err
    assert "no run 7" in err and err.count("\n") == 1
    assert main(["rerun", "seven", "--db", db_url]) == 2
    assert "ID" in capsys.readouterr().err
