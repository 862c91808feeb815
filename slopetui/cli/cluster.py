"""``slopetui cluster slurm``: write the sbatch script of a job array of worker pools, one
per node, and say how to submit, watch and stop it.

The script is built by slopetui.ops.slurm (which says how the pools stop); here are the
options, the checks of the command line, the file and the instructions.
"""

from __future__ import annotations

import argparse
import os
import shlex
import sys
import tempfile
from pathlib import Path

from slopetui.cli.options import UsageError, int_arg
from slopetui.display_text import terminal_safe
from slopetui.ops import slurm
from slopetui.store.location import DB_ENV


def _python(given: str | None) -> str:
    """The absolute path of the Python of the script: --python, else this process's own
    (the virtual environment's path as it was started, symlink kept: resolving it would
    leave the environment)."""
    path = given if given is not None else sys.executable
    if not path:
        raise UsageError("--python: this Python does not know its own path; give --python "
                         "PATH of the Python that runs slopetui on the nodes")
    if "\0" in path or not path.strip():
        raise UsageError(f"--python = {path!r}: allowed the path of a Python executable")
    return os.path.abspath(path)


def _job(args: argparse.Namespace) -> tuple[slurm.SlurmWorkers, slurm.ServerDatabase]:
    """The checked settings, every option's error named (UsageError)."""
    workers = int_arg("--workers-per-node", args.workers_per_node, 1,
                      slurm.MAX_WORKERS_PER_NODE)
    nodes = int_arg("--nodes", args.nodes, 1, slurm.MAX_NODES,
                    note=" (array tasks, one node each)")
    try:
        time_s = slurm.parse_time_limit(args.time)
        partition = None if args.partition is None else slurm.check_partition(args.partition)
        db = slurm.server_database(args.db if args.db is not None else os.environ.get(DB_ENV))
        job = slurm.SlurmWorkers(db_url=db.url, python=_python(args.python),
                                 workers_per_node=workers, nodes=nodes, time_s=time_s,
                                 partition=partition)
    except slurm.SlurmScriptError as exc:
        raise UsageError(str(exc)) from None
    return job, db


def _write(path: Path, text: str, force: bool) -> None:
    """Write the script, mode 600 (it holds the database's URL). Without ``force`` an
    existing file is refused; with it, the new file replaces the old one whole (a
    temporary file renamed over it). A failed write leaves nothing behind."""
    shown = terminal_safe(str(path))
    if path.is_dir():
        raise UsageError(f"--output = {shown} is a folder: allowed a file name")
    if not path.parent.is_dir():
        raise UsageError(f"--output = {shown}: the folder {terminal_safe(str(path.parent))} "
                         "does not exist")
    exists = UsageError(f"--output = {shown} exists: pass --force to overwrite it, or choose "
                        "another name with -o FILE")
    if path.is_symlink() and not force:
        raise exists
    data = text.encode()
    try:
        if force:
            fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.")
            try:
                with os.fdopen(fd, "wb") as f:
                    f.write(data)
                os.replace(tmp, path)
            except BaseException:
                os.unlink(tmp)
                raise
            return
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
        try:
            with os.fdopen(fd, "wb") as f:
                f.write(data)
        except BaseException:
            path.unlink()
            raise
    except FileExistsError:
        raise exists from None
    except OSError as exc:
        raise UsageError(f"--output = {shown}: cannot write it ({exc.strerror})") from None


def _instructions(path: Path, job: slurm.SlurmWorkers, db: slurm.ServerDatabase) -> str:
    """What to do with the script: submit, watch, stop (the file's name and the URL made
    safe for the terminal)."""
    script = terminal_safe(shlex.quote(str(path)))
    if db.has_password:  # not --db URL: every user of the machine reads a command line
        db_arg = ""
        note = ("  (with $SLOPETUI_DB set to the script's URL: a password is not given on "
                "a command line)")
    else:
        db_arg, note = f" --db {terminal_safe(shlex.quote(db.url))}", ""
    tasks = f"{job.nodes} pool{'s' if job.nodes > 1 else ''}"
    return "\n".join([
        f"wrote {script}: a job array of {tasks} (one per node) of {job.workers_per_node} "
        f"worker{'s' if job.workers_per_node > 1 else ''}, time limit "
        f"{slurm.format_time(job.time_s)}, database {terminal_safe(db.display)}",
        "queue the runs first: a pool exits once nothing is queued or running",
        f"submit:  sbatch {script}        (prints JOBID)",
        f"watch:   squeue -u \"$USER\" -n {slurm.JOB_NAME}",
        f"         slopetui status{db_arg}{note}",
        f"         slopetui workers{db_arg}",
        "logs:    slopetui-worker-JOBID_TASK.log, one per task, in the folder you submit from",
        "stop:    scancel --state=PENDING JOBID; scancel --batch --signal=TERM "
        "--state=RUNNING JOBID",
        "           the tasks not started are cancelled, the pools finish the runs they "
        "compute, then exit;",
        "           the second command once more gives those runs back to the queue at once",
        "         scancel JOBID",
        "           Slurm's kill: SIGTERM to every process, SIGKILL after KillWait (30 s by "
        "default): a run",
        "           not finished by then goes back to the queue when its lease expires "
        "(60 s), its attempt counted",
    ])


def handle(args: argparse.Namespace) -> int:
    job, db = _job(args)
    path = Path(args.output)
    _write(path, slurm.sbatch_script(job, path.name), args.force)
    print(_instructions(path, job, db))
    if db.local_only is not None:
        print(f"warning: only this machine reaches the database "
              f"({terminal_safe(db.local_only)}): pools "
              "on other nodes will fail to connect; give a host name the nodes resolve",
              file=sys.stderr)
    return 0
