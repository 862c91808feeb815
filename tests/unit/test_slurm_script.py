"""`slopetui cluster slurm`: the sbatch script's text (slopetui.ops.slurm) and the command
that writes it, in this process. The script run by a real Slurm (or by bash, against
PostgreSQL) is tests/integration/test_slurm.py."""

from __future__ import annotations

import os
import stat
import subprocess
import sys
from pathlib import Path

import pytest

from slopetui.cli import main
from slopetui.ops import slurm

PG = "postgresql+psycopg://slopes@db.cluster.example:5432/slopes"
#: Everything a shell could read as more than text: spaces, both quotes, $, backquotes,
#: a command substitution, a backslash and a newline.
NASTY = ("postgresql+psycopg://al ice:p'a\"s$HOME`id`$(id)\\x\nrm -rf ~@db.example/"
         "slopes?application_name=a b")


def job(**changes: object) -> slurm.SlurmWorkers:
    settings: dict[str, object] = {"db_url": PG, "python": "/shared/venv/bin/python",
                                   "workers_per_node": 8, "nodes": 4, "time_s": 7200}
    settings.update(changes)
    return slurm.SlurmWorkers(**settings)  # type: ignore[arg-type]


def sbatch_lines(text: str) -> list[str]:
    """The directives sbatch reads: the #SBATCH lines before the first command."""
    out = []
    for line in text.splitlines()[1:]:
        if line and not line.startswith("#"):
            break
        if line.startswith("#SBATCH "):
            out.append(line.removeprefix("#SBATCH "))
    return out


def shell_value(text: str, name: str) -> str:
    """The value bash gives ``name`` by running the script's settings: everything before
    it makes a folder (a quoted value may span lines)."""
    settings = text[:text.index("\nmkdir -p")]
    out = subprocess.run(["bash", "-c", f'{settings}\nprintf %s "${name}"'], capture_output=True,
                         text=True, check=True, timeout=10,
                         env={"PATH": os.environ["PATH"], "SLURM_ARRAY_JOB_ID": "7"})
    return out.stdout


# --- the script -------------------------------------------------------------------------

def test_the_directives_ask_for_one_node_per_task_and_the_early_signal():
    text = slurm.sbatch_script(job(partition="compute,long"))
    assert text.startswith("#!/bin/bash\n")
    assert sbatch_lines(text) == [
        "--job-name=slopetui-workers", "--array=0-3", "--nodes=1", "--ntasks=1",
        "--cpus-per-task=8", "--time=02:00:00", "--partition=compute,long",
        "--output=slopetui-worker-%A_%a.log", "--open-mode=append", "--signal=B:TERM@120"]


def test_no_partition_line_without_a_partition_and_one_task_is_array_0_0():
    directives = sbatch_lines(slurm.sbatch_script(job(nodes=1, workers_per_node=1)))
    assert "--array=0-0" in directives and "--cpus-per-task=1" in directives
    assert not any(d.startswith("--partition") for d in directives)


def test_the_pool_replaces_the_batch_shell_and_logs_where_slurm_writes():
    text = slurm.sbatch_script(job())
    exec_at = text.index('exec "$PYTHON" -P -m slopetui worker -j 8 --exit-when-idle '
                         "--another-pool")
    command = text[exec_at:].replace("\\\n", " ")
    assert command.rstrip().endswith(
        '--log "slopetui-worker-${SLURM_ARRAY_JOB_ID}_${SLURM_ARRAY_TASK_ID}.log"')
    # the database comes from the environment: a command line is readable by every user
    assert "--db" not in command and "SLOPETUI_DB" not in command
    # the comment says why B: (no srun step), next to the directive
    assert "B:" in text and "srun" in text and "exec" in text.split("#SBATCH --signal")[0]
    assert "set -euo pipefail" in text


def test_the_kernel_cache_is_node_local_private_and_warmed_once_a_node():
    text = slurm.sbatch_script(job())
    assert ('export SLOPETUI_KERNEL_CACHE="${SLURM_TMPDIR:-${TMPDIR:-/tmp}}/'
            'slopetui-kernels-$(id -u)"') in text
    cache_at, warm_at, exec_at = (text.index("export SLOPETUI_KERNEL_CACHE"),
                                  text.index('flock "$SLOPETUI_KERNEL_CACHE/warm-up.lock"'),
                                  text.index('exec "$PYTHON"'))
    assert cache_at < warm_at < exec_at
    assert '[ ! -O "$SLOPETUI_KERNEL_CACHE" ]' in text and '[ -L "$SLOPETUI_KERNEL_CACHE" ]' in text


@pytest.mark.parametrize("url", [PG, NASTY, "postgresql://u:$(reboot)@h/d", "postgresql://h/'"])
def test_the_url_reaches_the_shell_unchanged(url):
    assert shell_value(slurm.sbatch_script(job(db_url=url)), "SLOPETUI_DB") == url


#: A stand-in for the nodes' Python: records each call's arguments (NUL-separated) and the
#: $SLOPETUI_DB it was given, one pair of files per call, in $CALLS.
FAKE_PYTHON = """#!/bin/sh
n=$(ls "$CALLS" | grep -c "args$")
printf '%s\\0' "$@" > "$CALLS/$n.args"
printf '%s' "${SLOPETUI_DB-unset}" > "$CALLS/$n.db"
"""


@pytest.mark.parametrize("url", ["postgresql+psycopg://alice:s3cret-pw@db.example/slopes", NASTY])
def test_the_url_reaches_the_pool_in_its_environment_never_on_its_command_line(tmp_path, url):
    python, calls = tmp_path / "python", tmp_path / "calls"
    python.write_text(FAKE_PYTHON)
    python.chmod(0o700)
    calls.mkdir()
    script = slurm.sbatch_script(job(db_url=url, python=str(python)))
    subprocess.run(["bash", "-c", script], check=True, timeout=30, cwd=tmp_path,
                   env={"PATH": os.environ["PATH"], "SLURM_ARRAY_JOB_ID": "7",
                        "SLURM_ARRAY_TASK_ID": "1", "TMPDIR": str(tmp_path), "CALLS": str(calls)})
    warm_up, pool = (((calls / f"{n}.args").read_bytes().split(b"\0")[:-1],
                      (calls / f"{n}.db").read_text()) for n in (0, 1))
    assert pool[0][:5] == [b"-P", b"-m", b"slopetui", b"worker", b"-j"]
    assert pool[1] == url  # the pool opens the store of the script
    for args, _ in (warm_up, pool):
        assert not any(url.encode() in a or b"s3cret" in a or a == b"--db" for a in args)


def test_a_python_path_with_spaces_and_quotes_reaches_the_shell_unchanged():
    python = "/shared/my venv's/bin/python$x"
    assert shell_value(slurm.sbatch_script(job(python=python)), "PYTHON") == python


def test_outside_slurm_the_script_stops_at_once_and_says_why(tmp_path):
    out = subprocess.run(["bash", "-c", slurm.sbatch_script(job())], capture_output=True,
                         text=True, timeout=10, cwd=tmp_path, env={"PATH": os.environ["PATH"]})
    assert out.returncode != 0 and "submit this script with sbatch" in out.stderr
    assert list(tmp_path.iterdir()) == []


def test_the_script_is_valid_bash():
    text = slurm.sbatch_script(job(db_url=NASTY, partition="gpu"), "my jobs\n.sbatch")
    subprocess.run(["bash", "-n"], input=text, text=True, check=True, timeout=10)
    # a file name with a newline cannot end the comment that names it (and run a command)
    assert "# Submit it with:  sbatch THIS_FILE\n" in text and "\n.sbatch" not in text


# --- the settings' parsers --------------------------------------------------------------

@pytest.mark.parametrize("text,seconds", [
    ("5", 300), ("90", 5400), ("10:00", 600), ("5:30", 330), ("2:00:00", 7200),
    ("00:05:00", 300), ("48:00:00", 172_800), ("2-0", 172_800), ("1-2:3", 93_780),
    ("1-02:03:04", 93_784), ("365-0", 365 * 86_400), (" 1:00:00 ", 3600)])
def test_slurm_time_forms(text, seconds):
    assert slurm.parse_time_limit(text) == seconds


@pytest.mark.parametrize("seconds,shown", [(300, "00:05:00"), (7200, "02:00:00"),
                                           (93_784, "1-02:03:04"), (86_400, "1-00:00:00")])
def test_time_limits_are_written_as_slurm_writes_them(seconds, shown):
    assert slurm.format_time(seconds) == shown


@pytest.mark.parametrize("text", [
    "4", "4:59", "00:04:59", "0", "1:60:00", "1:00:60", "1-24:00:00", "366-0", "365-00:00:01",
    "abc", "", "1:2:3:4", "\u0663\u0660", "inf", "-5", "5 min", "UNLIMITED", "1-", "1e3",
    "10:00\n#SBATCH --x"])
def test_bad_time_limits_are_refused_with_the_range(text):
    with pytest.raises(slurm.SlurmScriptError) as info:
        slurm.parse_time_limit(text)
    message = str(info.value)
    assert message.startswith("--time = ") and "00:05:00" in message and "365-00:00:00" in message
    assert "120 s" in message and "\n" not in message


@pytest.mark.parametrize("name", ["compute", "gpu_a100", "long.q", "a-b", "p1,p2", "_x"])
def test_partition_names(name):
    assert slurm.check_partition(name) == name


@pytest.mark.parametrize("name", ["", "a b", "a\n#SBATCH --x", "a;rm", "$(id)", "-x", ".x",
                                  "a,", ",a", "a,,b", "p'", "x" * 65, "a\tb", "caf\u00e9"])
def test_partitions_that_could_say_more_are_refused(name):
    with pytest.raises(slurm.SlurmScriptError, match=r"^--partition = .* allowed letters"):
        slurm.check_partition(name)


def test_the_dataclass_guards_its_own_ranges():
    for changes, option in [({"workers_per_node": 0}, "--workers-per-node"),
                            ({"nodes": 10_001}, "--nodes"), ({"time_s": 299}, "--time"),
                            ({"partition": "a b"}, "--partition"),
                            ({"python": "venv/bin/python"}, "--python"), ({"db_url": ""}, "--db"),
                            ({"db_url": "sqlite+pysqlite:///x.db"}, "--db: SQLite")]:
        with pytest.raises(slurm.SlurmScriptError, match=f"^{option}"):
            job(**changes)


@pytest.mark.parametrize("url,local", [
    (PG, None), ("postgresql+psycopg://u@10.1.2.3/db", None),
    ("postgresql+psycopg://postgres@127.0.0.1:54331/postgres", "127.0.0.1 is this machine"),
    ("postgresql://localhost/db", "localhost is this machine"),
    ("postgresql://[::1]:5432/db", "is this machine"),
    ("postgresql:///db", "Unix socket"),
    ("postgresql+psycopg://postgres@/postgres?host=/tmp/pg&port=5432", "Unix socket in /tmp/pg")])
def test_a_server_only_this_machine_reaches_is_named(url, local):
    found = slurm.server_database(url).local_only
    assert found == local if local is None else local in (found or "")


def test_the_password_is_hidden_from_messages_only():
    db = slurm.server_database("postgresql://alice:s3cret@db.example/slopes")
    assert db.has_password and "s3cret" not in db.display and "s3cret" in db.url


# --- the command ------------------------------------------------------------------------

@pytest.fixture
def in_tmp(tmp_path, monkeypatch) -> Path:
    monkeypatch.chdir(tmp_path)
    monkeypatch.delenv("SLOPETUI_DB", raising=False)
    return tmp_path


def cluster(*args: str) -> int:
    return main(["cluster", "slurm", *args])


GOOD = ("--workers-per-node", "4", "--nodes", "3", "--time", "1:00:00")


def test_writes_the_script_private_and_says_how_to_submit_watch_and_stop(in_tmp, capsys):
    assert cluster(*GOOD, "--partition", "compute", "--db", PG) == 0
    path = in_tmp / "slopetui-workers.sbatch"
    text = path.read_text()
    assert stat.S_IMODE(path.stat().st_mode) == 0o600  # it holds the URL (and a password)
    assert f"export SLOPETUI_DB={PG}\n" in text and "--cpus-per-task=4" in text
    assert f"PYTHON={sys.executable}\n" in text  # the Python that wrote it
    out = capsys.readouterr()
    assert out.err == ""  # a server other nodes reach: no warning
    for expected in ("sbatch slopetui-workers.sbatch", "squeue -u", "slopetui status --db " + PG,
                     "scancel --state=PENDING JOBID",
                     "scancel --batch --signal=TERM --state=RUNNING JOBID", "scancel JOBID",
                     "KillWait", "3 pools", "4 workers", "01:00:00"):
        assert expected in out.out, expected


def test_slopetui_db_is_the_default(in_tmp, monkeypatch, capsys):
    monkeypatch.setenv("SLOPETUI_DB", PG)
    assert cluster(*GOOD, "-o", "w.sh") == 0
    assert f"export SLOPETUI_DB={PG}\n" in (in_tmp / "w.sh").read_text()


def test_the_password_is_in_the_script_not_on_the_screen(in_tmp, capsys):
    assert cluster(*GOOD, "--db", "postgresql://alice:s3cret@db.example/slopes") == 0
    assert "s3cret" in (in_tmp / "slopetui-workers.sbatch").read_text()
    out = capsys.readouterr().out
    assert "s3cret" not in out and "alice:***@db.example" in out
    # the commands it suggests take the URL from $SLOPETUI_DB, not a --db with the password
    assert "slopetui status  (with $SLOPETUI_DB set to the script's URL" in out
    assert "--db" not in out


def test_a_server_on_this_machine_gets_a_warning(in_tmp, capsys):
    assert cluster(*GOOD, "--db", "postgresql://u@localhost/db") == 0
    err = capsys.readouterr().err
    assert err.startswith("warning: ") and "localhost is this machine" in err


def test_python_is_made_absolute(in_tmp):
    assert cluster(*GOOD, "--db", PG, "--python", "venv/bin/python") == 0
    text = (in_tmp / "slopetui-workers.sbatch").read_text()
    assert f"PYTHON={in_tmp / 'venv/bin/python'}\n" in text


def refused(capsys, folder: Path, *args: str) -> str:
    """Run the command; it must exit 2 with one error line and write nothing."""
    before = sorted(folder.iterdir())
    assert cluster(*args) == 2
    captured = capsys.readouterr()
    lines = captured.err.splitlines()
    assert captured.out == "" and len(lines) == 1, captured.err
    assert lines[0].startswith("slopetui cluster: error: ") and "Traceback" not in captured.err
    assert sorted(folder.iterdir()) == before
    return lines[0]


@pytest.mark.parametrize("option,value,allowed", [
    ("--workers-per-node", "0", "from 1 to 512"), ("--workers-per-node", "513", "from 1 to 512"),
    ("--workers-per-node", "two", "from 1 to 512"), ("--workers-per-node", "1.5", "from 1 to 512"),
    ("--nodes", "0", "from 1 to 10000"), ("--nodes", "10001", "from 1 to 10000"),
    ("--nodes", "-1", "from 1 to 10000"),
    ("--time", "4:59", "from 00:05:00 to 365-00:00:00"), ("--time", "1:2:3:4", "D-HH:MM:SS"),
    ("--time", "forever", "from 00:05:00"),
    ("--partition", "a b", "letters, digits"), ("--partition", "x\n#SBATCH --mem=1", "letters"),
    ("--partition", "", "letters")])
def test_bad_input_names_the_option_and_its_range(in_tmp, capsys, option, value, allowed):
    args = dict(zip(GOOD[::2], GOOD[1::2], strict=True))
    args[option] = value
    line = refused(capsys, in_tmp, *[w for kv in args.items() for w in kv], "--db", PG)
    assert f"{option} = " in line and allowed in line


@pytest.mark.parametrize("db", ["sqlite:///runs.db", "sqlite://", "sqlite+pysqlite:////tmp/x.db"])
def test_sqlite_is_refused(in_tmp, capsys, db):
    line = refused(capsys, in_tmp, *GOOD, "--db", db)
    assert "--db = " in line and "SQLite" in line and "cannot be shared between nodes" in line
    assert "PostgreSQL" in line and "slopetui db serve" in line


def test_no_database_at_all_is_refused_too(in_tmp, capsys):
    line = refused(capsys, in_tmp, *GOOD)
    assert "$SLOPETUI_DB is not set" in line and "slopetui db serve" in line


def test_a_sqlite_slopetui_db_is_refused(in_tmp, capsys, monkeypatch):
    monkeypatch.setenv("SLOPETUI_DB", f"sqlite:///{in_tmp / 'runs.db'}")
    assert "SQLite" in refused(capsys, in_tmp, *GOOD)


def test_not_a_url_is_refused(in_tmp, capsys):
    assert "--db" in refused(capsys, in_tmp, *GOOD, "--db", "db.example:5432")


def test_an_existing_script_is_kept_unless_force(in_tmp, capsys):
    path = in_tmp / "slopetui-workers.sbatch"
    path.write_text("mine\n")
    line = refused(capsys, in_tmp, *GOOD, "--db", PG)
    assert "--output = slopetui-workers.sbatch exists" in line and "--force" in line
    assert path.read_text() == "mine\n"
    assert cluster(*GOOD, "--db", PG, "--force") == 0
    assert "#SBATCH --array=0-2" in path.read_text()
    assert stat.S_IMODE(path.stat().st_mode) == 0o600
    assert sorted(p.name for p in in_tmp.iterdir()) == ["slopetui-workers.sbatch"]


def test_a_symlink_is_not_followed_without_force(in_tmp, capsys):
    target = in_tmp / "elsewhere"
    target.write_text("keep\n")
    (in_tmp / "s.sbatch").symlink_to(target)
    assert "exists" in refused(capsys, in_tmp, *GOOD, "--db", PG, "-o", "s.sbatch")
    assert target.read_text() == "keep\n"


def test_an_output_in_a_missing_folder_or_a_folder_is_refused(in_tmp, capsys):
    assert "does not exist" in refused(capsys, in_tmp, *GOOD, "--db", PG, "-o", "no/x.sbatch")
    (in_tmp / "d").mkdir()
    assert "is a folder" in refused(capsys, in_tmp, *GOOD, "--db", PG, "-o", "d")


@pytest.mark.parametrize("force", [False, True])
def test_a_folder_no_one_may_write_in_is_one_line(in_tmp, capsys, force):
    # /proc refuses new files even to root (whom permission bits would not stop)
    path = Path("/proc/slopetui-workers.sbatch")
    assert cluster(*GOOD, "--db", PG, "-o", str(path), *(["--force"] if force else [])) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and len(captured.err.splitlines()) == 1
    assert "--output = /proc/slopetui-workers.sbatch: cannot write it" in captured.err
    assert not path.exists()
