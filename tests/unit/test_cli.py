"""`slopetui run` as a user types it (in this process; the JSON contract in a fresh process:
tests/integration/test_cli_process.py)."""

from __future__ import annotations

import argparse
import json
import math

import pytest

from slopetui.cli import main


def test_text_output(capsys):
    assert main(["run", "--k", "10", "--t-end", "5e3", "--window", "500", "--method", "rk4"]) == 0
    text = capsys.readouterr().out
    for label in ("regime     oscillatory", "lambda_max", "amplitude", "period", "peaks",
                  "drift", "runtime"):
        assert label in text


def test_blow_up_is_reported(capsys):
    assert main(["run", "--a", "0.035", "--k", "12", "--t-end", "100", "--window", "10",
                 "--json"]) == 0
    captured = capsys.readouterr()
    rec = json.loads(captured.out)
    assert rec["regime"] == "unstable" and 0 < rec["t_blowup"] < 1
    assert "warning" in captured.err and "eq. 12" in captured.err


@pytest.mark.parametrize(
    "args,field",
    [(["--tau", "-1"], "tau"), (["--k", "nan"], "k"), (["--d", "-0.1"], "d"),
     (["--dt", "0"], "dt"), (["--dt", "5", "--tau", "1"], "dt"), (["--t-end", "-3"], "t_end"),
     (["--window", "2e5"], "window"), (["--a", "x"], "a")],
)
def test_bad_input_names_the_field_and_exits_nonzero(args, field, capsys):
    assert main(["run", *args]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert f"{field} = " in captured.err and "allowed" in captured.err


def test_json_has_no_nan_literals(capsys):
    main(["run", "--k", "4", "--t-end", "1e3", "--window", "100", "--no-lyap", "--json"])
    text = capsys.readouterr().out
    assert "NaN" not in text
    rec = json.loads(text)
    assert rec["lambda_max"] is None and not math.isnan(rec["amplitude"])


def one_error_line(captured, field: str) -> str:
    """The one line a refused command prints: it names the field and what is allowed."""
    lines = captured.err.splitlines()
    assert captured.out == "" and len(lines) == 1, captured.err
    assert "Traceback" not in captured.err and f"{field} = " in lines[0]
    assert "allowed" in lines[0]
    return lines[0]


@pytest.mark.parametrize(
    "args,field,cause",
    [  # before: a numba TypingError, a ValueError, MemoryErrors, or hours of steps
        (["--dt", "1e-300"], "dt", "per run"),
        (["--t-end", "1e300"], "t_end", "at most 1e10 steps per run"),
        (["--tau", "1e9"], "tau", "delay history"),
        (["--dt", "1e-12"], "dt", "per run"),
        (["--tau", "1e-300", "--dt", "1e-300"], "dt", "steps per run"),
        (["--tau", "0", "--dt", "1", "--t-end", "1e9"], "t_end", "lambda_max"),
        (["--tau", "0", "--dt", "1e300", "--t-end", "10"], "dt", "60 samples"),
        # before: "sliding (at rest)" from a window of one sample, or a traceback
        (["--t-end", "10", "--window", "1e-300"], "window", "60 samples"),
        (["--t-end", "1e-300", "--window", "1e-300"], "t_end", "60 samples"),
        (["--dt", "9", "--tau", "10", "--t-end", "10", "--window", "5"], "dt", "60 samples"),
        # siblings: every numeric option, non-numbers, infinities, huge and tiny values
        (["--k", "1e400"], "k", "finite"), (["--v", "-inf"], "v", "finite"),
        (["--delta", "nan"], "delta", "finite"), (["--d", "True"], "d", "finite"),
        (["--b", "0x10"], "b", "finite"), (["--c", ""], "c", "finite"),
        (["--tau", "-1e-3"], "tau", "tau >= 0"), (["--dt", "-1e-3"], "dt", "dt > 0"),
        (["--dt", "inf"], "dt", "finite"), (["--t-end", "0"], "t_end", "t_end > 0"),
        (["--window", "-5"], "window", "window > 0"), (["--window", "x"], "window", "finite"),
    ],
)
def test_refused_runs_print_one_line_and_nothing_else(args, field, cause, capsys):
    assert main(["run", *args]) == 2
    assert cause in one_error_line(capsys.readouterr(), field)


def test_a_short_run_takes_half_of_it_as_its_window(capsys):
    """--t-end 100 alone was refused: the default window (1000) was longer than the run."""
    assert main(["run", "--t-end", "100", "--method", "rk4", "--no-lyap"]) == 0
    assert "t_end=100, window=50" in capsys.readouterr().out


def test_negative_numbers_in_scientific_notation_are_values():
    """argparse took "-1e-3" for an option ("expected one argument")."""
    from slopetui.cli import build_parser

    args = build_parser().parse_args(["run", "--a", "-1e-3", "--v", "-2.5E4", "--delta", "-.5"])
    assert (args.a, args.v, args.delta) == ("-1e-3", "-2.5E4", "-.5")
    args = build_parser().parse_args(["submit", "--x", "a=-1:1:3", "--delta", "-1e-6"])
    assert args.fixed_delta == "-1e-6"


def test_lambda_max_says_why_it_is_missing(capsys):
    assert main(["run", "--t-end", "5", "--window", "2", "--method", "rk4"]) == 0
    assert "lambda_max not estimated (the run is too short" in capsys.readouterr().out


def test_run_says_when_it_compiles(tmp_path, monkeypatch, capsys):
    """The first run after an install compiles its kernel for seconds, silently before."""
    from core import jit_cache

    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    assert not jit_cache.compiled("euler")
    index = tmp_path / "core_0123" / "euler.euler-20.py311.nbi"
    index.parent.mkdir()
    index.touch()
    assert jit_cache.compiled("euler") and not jit_cache.compiled("rk4")
    monkeypatch.setattr(jit_cache, "compiled", lambda module: False)
    assert main(["run", "--tau", "2", "--t-end", "20"]) == 0
    assert "compiling the euler kernel" in capsys.readouterr().err


def test_export_takes_one_format(capsys):
    """--csv, --parquet or --json: one of them, required (before: --csv, the only one)."""
    with pytest.raises(SystemExit) as refused:
        main(["export", "1"])
    assert refused.value.code == 2
    assert "one of the arguments --csv --parquet --json is required" in capsys.readouterr().err
    with pytest.raises(SystemExit) as refused:
        main(["export", "1", "--csv", "--json"])
    assert refused.value.code == 2
    assert "--json: not allowed with argument --csv" in capsys.readouterr().err


def test_export_json_of_an_empty_store_names_the_sweep(tmp_path, capsys):
    url = f"sqlite:///{tmp_path / 'store.db'}"
    assert main(["export", "1", "--json", "--db", url]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err == "slopetui export: error: SWEEP: no sweep with id 1\n"


def test_every_command_has_a_handler_imported_on_dispatch_only():
    """The parser's commands and the handlers' table name the same commands; building the
    parser (what --help and shell completion do) imports no handler's module, and each
    handler is a function of the module the table names."""
    import subprocess
    import sys

    from slopetui.cli import HANDLERS, build_parser, imported

    parser = build_parser()
    (sub,) = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    assert set(sub.choices) == set(HANDLERS)
    handlers = {target.partition(":")[0] for target in HANDLERS.values()}
    probe = ("import sys; from slopetui.cli import build_parser; build_parser(); "
             f"print(sorted(m for m in {sorted(handlers)!r} if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                         check=True).stdout.strip()
    # completion: the parser's own id completers live there (a light module, stdlib only)
    assert out == "['slopetui.cli.completion']"
    assert all(callable(imported(target)) for target in HANDLERS.values())
