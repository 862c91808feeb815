"""The stop rule from the user to the kernel and back: the spec's ``[solver] stop``, the
defaults of each entry point, the cache key, the batch key, the worker's settings, and
the outputs. These tests do not depend on a run stopping early: until the engine honours
"certified", a certified run runs to t_end too (t_stop = t_end), and nothing here asks
otherwise."""

from __future__ import annotations

import csv
import hashlib
import io
import json

import pytest
from sqlalchemy import select, update

from slopetui.cli import build_parser, main
from slopetui.cli.submit import spec_data
from slopetui.queue import jobs, run_batches
from slopetui.queue.cache import KEY_FIELDS, cache_key
from slopetui.store.models import Run
from slopetui.store.queries import runs_matching
from slopetui.sweeps.estimate import describe, expected_stop, measured_speeds, measured_stops
from slopetui.sweeps.export import write_csv
from slopetui.sweeps.export_files import write_json
from slopetui.sweeps.frames import runs_frame
from slopetui.sweeps.presets import PRESETS
from slopetui.sweeps.recompute import load_run
from slopetui.sweeps.run_rows import run_rows
from slopetui.sweeps.spec import SpecError, parse_spec, read_spec
from slopetui.sweeps.submit import submit
from slopetui.tui.screens.run_detail import summary_text
from tests.support import QUICK_SOLVER, finish_all

LINE = {"x": {"param": "k", "start": 4, "stop": 12, "num": 3}, "fixed": {"tau": 2.0}}
EULER = {"method": "euler", "dt": 1e-3, "t_end": 20.0, "window": 10.0}


def spec_with(stop: str | None = None, **solver: object):
    extra = {} if stop is None else {"stop": stop}
    return parse_spec({**LINE, "solver": {**QUICK_SOLVER, **solver, **extra}}, submitting=True)


# --- the spec --------------------------------------------------------------------------------

@pytest.mark.parametrize("value", ["sometimes", "T_END", 1, True, ["certified"]])
def test_a_bad_stop_rule_is_one_line_naming_the_field_and_the_allowed_values(value):
    with pytest.raises(SpecError) as caught:
        parse_spec({**LINE, "solver": {"stop": value}})
    assert caught.value.field == "solver.stop"
    text = str(caught.value)
    assert "\n" not in text and text.startswith("solver.stop: ")
    assert "'t_end'" in text and "'certified'" in text


def test_the_stop_rule_is_stored_with_the_sweep_and_read_back():
    spec = spec_with("certified")
    assert spec.solver.stop == "certified"
    stored = spec.to_dict()
    assert stored["solver"]["stop"] == "certified"
    assert parse_spec(json.loads(json.dumps(stored))).solver.stop == "certified"


def test_a_spec_that_does_not_say_reads_as_the_papers_protocol():
    """A sweep stored before the rule existed ran to t_end: its spec reads so."""
    assert parse_spec({**LINE, "solver": QUICK_SOLVER}).solver.stop == "t_end"


def test_each_run_row_and_stored_run_has_its_sweeps_stop_rule(db):
    rows = run_rows(spec_with("certified"), "engine")
    assert {row["stop"] for row in rows} == {"certified"}
    submit(db, spec_with("certified"))
    submit(db, spec_with("t_end", t_end=300.0))
    with db.sessions() as s:
        assert [r.stop for r in s.scalars(select(Run).order_by(Run.id))] \
            == ["certified"] * 3 + ["t_end"] * 3


# --- the defaults per entry point ------------------------------------------------------------

def submit_args(*argv: str):
    return build_parser().parse_args(["submit", *argv])


def test_submit_defaults_to_certified_and_stop_overrides_the_file(tmp_path):
    assert parse_spec(spec_data(submit_args("--x", "k=4:12:3"))).solver.stop == "certified"
    assert parse_spec(spec_data(submit_args("--x", "k=4:12:3", "--stop", "t_end"))
                      ).solver.stop == "t_end"
    path = tmp_path / "mine.toml"
    path.write_text('[x]\nparam = "k"\nstart = 4\nstop = 12\nnum = 3\n'
                    '[solver]\nstop = "t_end"\n')
    assert parse_spec(spec_data(submit_args(str(path)))).solver.stop == "t_end"
    assert parse_spec(spec_data(submit_args(str(path), "--stop", "certified"))
                      ).solver.stop == "certified"
    with pytest.raises(SpecError, match=r"^solver\.stop: "):
        parse_spec(spec_data(submit_args("--x", "k=4:12:3", "--stop", "never")))


def test_submit_stores_certified_runs_by_default(db, db_url, capsys):
    assert main(["submit", "--x", "k=4:12:3", "--tau", "2", "--t-end", "200", "--window",
                 "100", "--method", "rk4", "--dt", "0.01", "--db", db_url]) == 0
    capsys.readouterr()
    with db.sessions() as s:
        assert set(s.scalars(select(Run.stop))) == {"certified"}


def test_the_papers_presets_and_the_shipped_examples_keep_t_end():
    for preset in PRESETS:
        assert parse_spec(preset.spec).solver.stop == "t_end", preset.key
        assert parse_spec(preset.at_resolution(4, 1e3)).solver.stop == "t_end", preset.key
    for name in ("fig4a", "k-tau-plane"):  # `slopetui submit fig4a` too
        assert parse_spec(read_spec(name)).solver.stop == "t_end", name
        assert parse_spec(spec_data(submit_args(name))).solver.stop == "t_end", name


def test_reproduce_keeps_t_end():
    from slopetui.cli.reproduce import preset_specs  # the report's sweeps

    assert {spec.solver.stop for spec in preset_specs(["fig4a", "fig5a"], 4, 1e3)} == {"t_end"}


def test_run_defaults_to_t_end_and_takes_stop():
    from slopetui.cli.run import parse_inputs

    run = ["run", "--t-end", "100", "--window", "50"]
    assert parse_inputs(build_parser().parse_args(run))[1].stop == "t_end"
    assert parse_inputs(build_parser().parse_args([*run, "--stop", "certified"]))[1].stop \
        == "certified"


def test_run_refuses_a_bad_stop_rule_in_one_line(capsys):
    assert main(["run", "--t-end", "100", "--window", "50", "--stop", "early"]) == 2
    captured = capsys.readouterr()
    lines = captured.err.splitlines()
    assert captured.out == "" and len(lines) == 1 and "stop = " in lines[0]
    assert "t_end" in lines[0] and "certified" in lines[0]


def test_help_says_the_defaults_and_why(capsys):
    texts = {}
    for command in ("submit", "run"):
        with pytest.raises(SystemExit):
            build_parser().parse_args([command, "--help"])
        texts[command] = " ".join(capsys.readouterr().out.split())
    assert "certified (default for a spec that does not say" in texts["submit"]
    assert "paper's protocol" in texts["submit"]
    assert "t_end (default: the paper's protocol" in texts["run"]


# --- the result cache ------------------------------------------------------------------------

def test_the_cache_key_differs_by_stop_rule_and_keeps_t_ends_old_key():
    row = run_rows(spec_with("t_end"), "engine")[0]
    old = hashlib.sha256(";".join(f"{n}={row[n]!r}" for n in KEY_FIELDS).encode()
                         ).hexdigest()[:32]  # the key before the stop rule existed
    assert cache_key(row) == old
    assert cache_key({**row, "stop": "certified"}) != old
    assert cache_key({n: row[n] for n in KEY_FIELDS}) == old  # no stop: the paper's


def test_a_finished_run_answers_only_runs_of_its_stop_rule(db):
    submit(db, spec_with("t_end"))
    finish_all(db)
    certified = submit(db, spec_with("certified"))
    assert certified.n_cached == 0
    again = submit(db, spec_with("t_end"))
    assert again.n_cached == 3


# --- the batch and the worker ----------------------------------------------------------------

def test_a_batch_never_mixes_stop_rules(db):
    """Two sweeps alike in every setting and tau but the stop rule, queued interleaved:
    every batch holds one rule."""
    for stop in ("t_end", "certified", "t_end"):
        submit(db, parse_spec({**LINE, "solver": {**EULER, "stop": stop}}))
    batches = []
    while batch := jobs.claim_batch(db, "w", 64, run_batches.BATCHED_METHODS):
        batches.append(batch)
    assert sum(len(b) for b in batches) == 9
    assert all(len({job.settings.stop for job in b}) == 1 for b in batches)
    assert [b[0].settings.stop for b in batches] == ["t_end", "certified"]


def test_the_worker_computes_a_queued_certified_run_with_its_stop_rule(db):
    """The claim builds the job's settings with the row's stop, and the record of both
    kernels' paths (a batch, a run alone) names it."""
    submit(db, parse_spec({**LINE, "solver": {**EULER, "stop": "certified"}}))
    batch = jobs.begin(db, jobs.claim_batch(db, "w", 64, run_batches.BATCHED_METHODS), "w")
    assert len(batch) == 3 and {job.settings.stop for job in batch} == {"certified"}
    together = run_batches._compute_together(batch)
    alone = run_batches._compute_one(batch[0])
    assert {record["stop"] for record in [*together, *alone]} == {"certified"}
    for job, record in zip(batch, together, strict=True):
        assert jobs.complete(db, job, "w", record)
    with db.sessions() as s:
        stored = s.scalars(select(Run)).all()
    assert {(r.stop, r.status) for r in stored} == {("certified", "done")}
    assert all(r.t_stop is not None and 0 < r.t_stop <= r.t_end + r.dt for r in stored)


# --- the outputs -----------------------------------------------------------------------------

def test_runs_and_export_show_stop_and_t_stop(db):
    sweep = submit(db, spec_with("certified")).sweep_id
    finish_all(db)
    out = io.StringIO()
    write_csv(runs_matching(db, sweep=sweep, limit=0), out)
    rows = list(csv.DictReader(io.StringIO(out.getvalue())))
    assert {r["stop"] for r in rows} == {"certified"}
    assert all(0 < float(r["t_stop"]) <= 200.0 + 0.01 for r in rows)
    frame = runs_frame(db, sweep)
    assert list(frame["stop"]) == ["certified"] * 3 and frame["t_stop"].notna().all()
    text = io.StringIO()
    write_json(frame, text)
    records = json.loads(text.getvalue())
    assert {r["stop"] for r in records} == {"certified"}
    assert all(isinstance(r["t_stop"], float) for r in records)


def test_the_run_detail_shows_stop_and_t_stop(db):
    submit(db, spec_with("certified"))
    finish_all(db)
    run = load_run(db, 1)
    assert run is not None and run.inputs()[1].stop == "certified"  # recomputed alike
    text = summary_text(run)
    assert "stop certified: t_stop 200 of t_end 200" in text  # as stored: this one ran to t_end


# --- the estimate ----------------------------------------------------------------------------

def test_the_estimate_of_a_certified_sweep_assumes_t_end_until_certified_runs_are_stored(db):
    spec = spec_with("certified")
    assert "assumes t_end: no certified run on this store yet" in describe(spec, 2, {}, [])
    assert "every run to t_end" in describe(spec_with("t_end"), 2, {}, [])


def test_the_estimate_takes_the_stores_stopping_times_and_speed_per_step(db):
    """Three certified runs, stored as if they had stopped at t = 50, 100 and at t_end
    (200): a new sweep to t_end = 200 expects (50 + 100 + 200) / 3; one to t_end = 80,
    (50 + 80 + 80) / 3. The speed is the runs' runtime over their steps to t_stop, summed
    (a median of each run's ratio priced a run stopped early by its analysis alone), so
    that at the runs' own mean steps it gives their mean runtime."""
    submit(db, spec_with("certified"))
    finish_all(db)
    with db.transaction() as s:
        for run_id, t_stop in ((1, 50.0), (2, 100.0)):
            s.execute(update(Run).where(Run.id == run_id).values(t_stop=t_stop))
        runs = {r.id: (r.runtime_s, r.t_stop, r.dt) for r in s.scalars(select(Run))}
    stops = measured_stops(db)
    assert sorted(t for t, _, _ in stops) == [50.0, 100.0, pytest.approx(200.0, abs=0.01)]
    assert expected_stop(200.0, stops) == pytest.approx(350.0 / 3, abs=0.01)
    assert expected_stop(80.0, stops) == pytest.approx(210.0 / 3)
    speeds = measured_speeds(db)
    runtimes = [runtime for runtime, _, _ in runs.values()]
    steps = [t_stop / dt for _, t_stop, dt in runs.values()]
    assert speeds[("rk4", True, "certified")] == pytest.approx(sum(runtimes) / sum(steps))
    mean_steps = sum(steps) / len(steps)
    assert speeds[("rk4", True, "certified")] * mean_steps == pytest.approx(sum(runtimes) / 3)
    line = describe(spec_with("certified"), 1, speeds, stops)
    assert "certified stop at 58 % of t_end on average, from 3 certified runs here" in line
    assert "(measured speed;" in line
    # a sweep to t_end charges every step
    assert "every run to t_end" in describe(spec_with("t_end"), 1, speeds, stops)


def test_the_runs_table_shows_stop_and_t_stop(db, db_url, capsys):
    submit(db, spec_with("certified"))
    finish_all(db)
    assert main(["runs", "--limit", "0", "--db", db_url]) == 0
    header, *lines = capsys.readouterr().out.splitlines()
    assert header.split()[-2:] == ["stop", "t_stop"]
    assert len(lines) == 3 and all(line.split()[-2] == "certified" for line in lines)
    assert all(0 < float(line.split()[-1]) <= 200.01 for line in lines)


def test_a_t_end_sweep_is_not_priced_by_certified_runs_speed():
    """A certified run's steps carry its analysis and certification over few steps: a
    sweep to t_end with only certified speeds measured takes the reference speed."""
    from slopetui.sweeps.estimate import OVERHEAD_S, REFERENCE_S_PER_STEP, seconds_per_run

    spec = spec_with("t_end")
    s = spec.solver
    assert s.dt is not None
    reference = s.t_end / s.dt * REFERENCE_S_PER_STEP[(s.method, s.lyap)] + OVERHEAD_S
    assert seconds_per_run(spec, {(s.method, s.lyap, "certified"): 1e-6}) == pytest.approx(reference)
