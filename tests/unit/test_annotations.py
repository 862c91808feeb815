"""What a tracker keeps, on SQLite and PostgreSQL: a sweep's name, note and tags
(slopetui.sweeps.annotations and the store's statements), the marked runs
(slopetui.store.runs.marks), runs and sweeps filtered by tag (`runs --tag`, `sweeps
--tag`, open_store().runs(tag=)), two sweeps' specs side by side (`compare`), and
migration 0014 (up with the rows kept, down naming what it drops)."""

from __future__ import annotations

import json
import threading
import time

import pytest
from alembic import command
from sqlalchemy import insert, inspect, text

import slopetui
from slopetui.cli import main
from slopetui.store.database import Database
from slopetui.store.migrate import alembic_config, downgrade, plan_downgrade, upgrade
from slopetui.store.models import Mark
from slopetui.store.open import open_store
from slopetui.store.runs.marks import clear_marks, marked_runs, set_mark
from slopetui.store.sweeps.annotations import sweep_list
from slopetui.sweeps import annotations, control, spec
from slopetui.sweeps.annotations import LabelError
from slopetui.sweeps.control import UnknownSweep
from slopetui.sweeps.spec_compare import compare_specs
from tests.support import submit_quick


def cli(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str, str]:
    code = main(list(args))
    out = capsys.readouterr()
    return code, out.out, out.err


def run_ids(db: Database, sweep: int) -> list[int]:
    with db.engine.begin() as conn:
        return [r[0] for r in conn.exec_driver_sql(
            f"SELECT id FROM runs WHERE sweep_id = {sweep} ORDER BY id")]


def test_names_notes_and_tags_are_stored_and_checked(store: Database) -> None:
    sweep = submit_quick(store, 2).sweep_id
    assert annotations.rename(store, sweep, "  the k axis  ") == "the k axis"
    assert annotations.set_note(store, sweep, "first try\nτ = 2 only") == "first try\nτ = 2 only"
    assert annotations.add_tags(store, sweep, ["Fig4", "paper", "fig4"]) == ("fig4", "paper")
    assert annotations.change_tags(store, sweep, ["v2"], ["paper", "absent"]) == ("fig4", "v2")
    got = annotations.labels(store, sweep)
    assert (got.name, got.note, got.tags) == ("the k axis", "first try\nτ = 2 only", ("fig4", "v2"))
    assert annotations.set_note(store, sweep, "  ") is None
    assert annotations.labels(store, sweep).note is None

    for bad, field in (("two words", "tag"), ("-x", "tag"), ("", "tag"), ("x" * 33, "tag")):
        with pytest.raises(LabelError, match=f"^{field}: .* is not a tag: allowed 1 to 32 letters"):
            annotations.add_tags(store, sweep, ["ok", bad])
    with pytest.raises(LabelError, match=r"^name: control characters are not allowed \(\\x1b\)"):
        annotations.rename(store, sweep, "red\x1b[31m")
    with pytest.raises(LabelError, match=r"^name: expected 1 to 200 characters, got 0"):
        annotations.rename(store, sweep, " ")
    with pytest.raises(LabelError, match=r"^note: expected at most 2000 characters"):
        annotations.set_note(store, sweep, "x" * 2001)
    assert annotations.labels(store, sweep).tags == ("fig4", "v2")  # nothing of "ok" written
    for change in (lambda: annotations.rename(store, 99, "x"),
                   lambda: annotations.set_note(store, 99, "x"),
                   lambda: annotations.add_tags(store, 99, ["x"]),
                   lambda: annotations.labels(store, 99)):
        with pytest.raises(UnknownSweep):
            change()
    assert annotations.MAX_NAME == spec.MAX_NAME


def test_marks_survive_the_session_and_go_with_their_runs(store: Database) -> None:
    first, second = submit_quick(store, 3).sweep_id, submit_quick(store, 2, tau=3.0).sweep_id
    a, b, c = run_ids(store, first)
    d, _ = run_ids(store, second)
    for run in (c, a, d):
        set_mark(store, run, True)
    assert set_mark(store, b, True) == (c, a, d, b)
    assert set_mark(store, c, True) == (c, a, d, b)  # as it is: nothing moves
    assert set_mark(store, a, False) == set_mark(store, a, False) == (c, d, b)
    assert set_mark(store, 10_000, True) == (c, d, b)  # no such run
    assert marked_runs(store) == (c, d, b)  # read back as a restarted application reads them
    control.delete(store, first)
    assert marked_runs(store) == (d,)
    assert clear_marks(store) == 1 and marked_runs(store) == ()


def test_runs_and_sweeps_by_tag(store: Database, capsys: pytest.CaptureFixture[str],
                                monkeypatch: pytest.MonkeyPatch) -> None:
    url = store.url.render_as_string(hide_password=False)
    first, second = submit_quick(store, 3).sweep_id, submit_quick(store, 2, tau=3.0).sweep_id
    annotations.add_tags(store, first, ["paper"])
    annotations.add_tags(store, second, ["paper", "tau3"])
    code, out, _ = cli(capsys, "runs", "--tag", "tau3", "--db", url)
    assert code == 0 and [int(line.split()[1]) for line in out.splitlines()[1:]] == [second] * 2
    code, out, _ = cli(capsys, "runs", "--tag", "Paper", "--limit", "0", "--db", url)
    assert len(out.splitlines()) == 1 + 5
    code, out, _ = cli(capsys, "runs", "--tag", "nothing", "--db", url)
    assert (code, out) == (0, "no runs match\n")
    code, _, err = cli(capsys, "runs", "--tag", "a b", "--db", url)
    assert code == 2 and err.startswith("slopetui runs: error: --tag: 'a b' is not a tag")

    code, out, _ = cli(capsys, "sweeps", "--tag", "tau3", "--json", "--db", url)
    assert [s["id"] for s in json.loads(out)] == [second]
    assert [s.id for s in sweep_list(store, "paper")] == [second, first]

    with slopetui.open_store(url) as notebook:
        assert set(notebook.runs(tag="TAU3")["sweep_id"]) == {second}
        assert len(notebook.runs(tag="paper")) == 5 and notebook.runs(tag="none").empty
        assert len(notebook.runs(first, tag="tau3")) == 0

    control.delete(store, second)  # its tags go with it
    assert [s.id for s in sweep_list(store, "paper")] == [first]
    assert sweep_list(store, "tau3") == []


def test_the_cli_renames_notes_tags_and_escapes_stored_text(
        store: Database, capsys: pytest.CaptureFixture[str]) -> None:
    url = store.url.render_as_string(hide_password=False)
    sweep = submit_quick(store, 2).sweep_id
    assert cli(capsys, "rename", str(sweep), "k sweep", "--db", url)[1] == \
        f"sweep {sweep} renamed 'k sweep'\n"
    assert cli(capsys, "tag", str(sweep), "a", "B", "--db", url)[1] == f"sweep {sweep} tags: a, b\n"
    assert cli(capsys, "tag", str(sweep), "c", "--remove", "a", "--db", url)[1] == \
        f"sweep {sweep} tags: b, c\n"
    code, _, err = cli(capsys, "tag", str(sweep), "ok", "no way", "--db", url)
    assert code == 2 and err == ("slopetui tag: error: TAG: 'no way' is not a tag: allowed 1 to "
                                 "32 letters, digits, '.', '_' or '-', starting with a letter "
                                 "or a digit (e.g. fig4, paper-v2)\n")
    assert cli(capsys, "tag", str(sweep), "--db", url)[1] == f"sweep {sweep} tags: b, c\n"
    assert cli(capsys, "note", str(sweep), "why:\nto see", "--db", url)[1] == \
        f"sweep {sweep}: note saved\n"
    assert cli(capsys, "note", str(sweep), "--db", url)[1] == "why:\nto see\n"
    code, _, err = cli(capsys, "tag", "99", "x", "--db", url)
    assert code == 2 and "no sweep with id 99" in err

    # text another tool wrote straight into the store reaches the terminal escaped
    with store.engine.begin() as conn:
        conn.exec_driver_sql(f"UPDATE sweeps SET name = 'x' || chr(27) || '[2J', "
                             f"note = 'n' || chr(27) || ']0;t' || chr(7) WHERE id = {sweep}"
                             .replace("chr(", "char(" if store.url.get_backend_name() == "sqlite"
                                      else "chr("))
    out = cli(capsys, "sweeps", "--db", url)[1]
    assert "\x1b" not in out and "\x07" not in out and "x\\x1b[2J" in out and "n\\x1b]0;t\\x07" in out
    assert "\x1b" not in cli(capsys, "note", str(sweep), "--db", url)[1]
    assert json.loads(cli(capsys, "sweeps", "--json", "--db", url)[1])[0]["name"] == "x\x1b[2J"


def test_compare_sets_two_specs_side_by_side(store: Database,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    url = store.url.render_as_string(hide_password=False)
    a, b = submit_quick(store, 3).sweep_id, submit_quick(store, 4, tau=3.0).sweep_id
    found = compare_specs(store, a, b)
    assert [(s.key, s.a, s.b) for s in found.differences] == [("fixed.tau", "2", "3"),
                                                             ("x.num", "3", "4")]
    assert ("solver.method", "rk4", "rk4", False) in [
        (s.key, s.a, s.b, s.differs) for s in found.settings]
    code, out, _ = cli(capsys, "compare", str(a), str(b), "--differences", "--db", url)
    lines = out.splitlines()
    assert code == 0 and lines[0].split() == ["setting", "sweep", str(a), "sweep", str(b)]
    assert lines[2].split() == ["*", "fixed.tau", "2", "3"] and lines[3].split() == ["*", "x.num", "3", "4"]
    assert lines[-1] == f"(2 of {len(found.settings)} settings differ)"
    code, _, err = cli(capsys, "compare", str(a), "99", "--db", url)
    assert code == 2 and err.endswith("error: SWEEP_B: no sweep with id 99\n")
    code, _, err = cli(capsys, "compare", "98", str(b), "--db", url)
    assert code == 2 and err.endswith("error: SWEEP_A: no sweep with id 98\n")


def test_compare_decides_on_the_stored_values_not_their_text(
        store: Database, capsys: pytest.CaptureFixture[str]) -> None:
    url = store.url.render_as_string(hide_password=False)
    a = submit_quick(store, 3, tau=10.000001).sweep_id
    b = submit_quick(store, 3, tau=10.000004).sweep_id
    c = submit_quick(store, 3, tau=2).sweep_id
    d = submit_quick(store, 3, tau=2.0).sweep_id
    differs = {s.key: (s.a, s.b) for s in compare_specs(store, a, b).differences}
    assert differs == {"fixed.tau": ("10.000001", "10.000004")}
    assert compare_specs(store, c, d).differences == ()  # 2 and 2.0: one number
    code, out, _ = cli(capsys, "compare", str(a), str(b), "--json", "--db", url)
    tau = next(s for s in json.loads(out)["settings"] if s["key"] == "fixed.tau")
    assert code == 0 and tau == {"key": "fixed.tau", "a": 10.000001, "b": 10.000004,
                                 "differs": True}
    assert "(1 of " in cli(capsys, "compare", str(a), str(b), "--db", url)[1]


def hostile_key(db: Database, sweep: int) -> None:
    """A spec key with a terminal's control sequences, as another tool could write it."""
    with db.engine.begin() as conn:
        spec = conn.execute(text("SELECT spec FROM sweeps WHERE id = :i"), {"i": sweep}).scalar()
        spec = spec if isinstance(spec, dict) else json.loads(spec)
        spec.setdefault("fixed", {})["\x1b]0;owned\x07\u202etau"] = 1
        conn.execute(text("UPDATE sweeps SET spec = :s WHERE id = :i"),
                     {"s": json.dumps(spec), "i": sweep})


def test_compare_escapes_a_spec_key_and_measures_it_escaped(
        store: Database, capsys: pytest.CaptureFixture[str]) -> None:
    url = store.url.render_as_string(hide_password=False)
    a, b = submit_quick(store, 3).sweep_id, submit_quick(store, 4).sweep_id
    hostile_key(store, a)
    code, out, _ = cli(capsys, "compare", str(a), str(b), "--db", url)
    assert code == 0 and not any(ch in out for ch in ("\x1b", "\x07", "\u202e"))
    lines = out.splitlines()
    column = lines[0].index("sweep")  # every row's first value starts under its title
    assert all(line[column - 2:column] == "  " and line[column] != " " for line in lines[1:-1])
    key = json.loads(cli(capsys, "compare", str(a), str(b), "--json", "--db", url)[1])
    assert "fixed.\x1b]0;owned\x07\u202etau" in {s["key"] for s in key["settings"]}


def test_two_applications_marking_one_run_at_once_on_postgresql(pg_server) -> None:
    """The second mark of a run waits on the first's unique index entry, then finds it
    taken: the run is marked, and nothing is raised (it raised the unique violation)."""
    db = open_store(pg_server.emptied_shared())
    run = run_ids(db, submit_quick(db, 2).sweep_id)[0]
    got: list[object] = []
    try:
        with db.engine.connect() as other:  # another application's mark, not yet committed
            other.begin()
            other.execute(insert(Mark).values(run_id=run))

            def mark() -> None:
                try:
                    got.append(set_mark(db, run, True))
                except Exception as exc:
                    got.append(exc)

            thread = threading.Thread(target=mark)
            thread.start()
            for _ in range(400):  # until set_mark's insert waits on the other's row lock
                with db.engine.connect() as probe:
                    if probe.exec_driver_sql("SELECT count(*) FROM pg_locks "
                                             "WHERE NOT granted").scalar():
                        break
                time.sleep(0.025)
            else:
                raise AssertionError("set_mark never waited on the other mark")
            other.commit()
            thread.join(10)
        assert got == [(run,)] and marked_runs(db) == (run,)
    finally:
        db.dispose()


def test_0014_keeps_the_rows_and_its_downgrade_names_what_goes(new_store_url, backend) -> None:
    db = Database(new_store_url)
    upgrade(db)
    sweep = submit_quick(db, 2).sweep_id
    downgrade(db, "0013")
    assert "note" not in {c["name"] for c in inspect(db.engine).get_columns("sweeps")}
    assert not {"marks", "sweep_tags"} & set(inspect(db.engine).get_table_names())
    command.upgrade(alembic_config(db), "0014")
    assert [s.id for s in sweep_list(db)] == [sweep] and marked_runs(db) == ()
    assert plan_downgrade(db, "0013").dropped == "no stored data"
    annotations.set_note(db, sweep, "kept?")
    annotations.add_tags(db, sweep, ["a", "b"])
    set_mark(db, run_ids(db, sweep)[0], True)
    assert plan_downgrade(db, "0013").dropped == \
        "the note of 1 sweep, 2 sweep tags and 1 marked run"
    command.downgrade(alembic_config(db), "0013")
    assert not {"marks", "sweep_tags"} & set(inspect(db.engine).get_table_names())
    db.dispose()
