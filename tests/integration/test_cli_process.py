"""`slopetui run --json` in a fresh process, as a script calling it would (the rest of
`slopetui run`, in this process: tests/unit/test_cli.py)."""

from __future__ import annotations

import json

from tests.support import slopetui_cli

KEYS = {"regime", "lambda_max", "lambda_err", "amplitude", "period", "peaks", "drift",
        "t_blowup", "runtime_s"}


def test_json_has_the_contract_keys():
    out = slopetui_cli("run", "--k", "4", "--t-end", "2e4", "--method", "rk4", "--json")
    assert out.returncode == 0, out.stderr
    rec = json.loads(out.stdout)
    assert rec.keys() >= KEYS
    assert rec["regime"] == "sliding" and rec["t_blowup"] is None
    assert rec["lambda_max"] < 0 and rec["lambda_err"] > 0
