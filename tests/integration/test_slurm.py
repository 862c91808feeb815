"""The script of `slopetui cluster slurm` run by a real Slurm: a single-node cluster
(munged, slurmctld and slurmd of Debian's slurm-wlm, started here in a folder of their
own, on ports of their own) runs the job array against PostgreSQL.

* Two array tasks of one worker each drain the queue: every run done exactly once, both
  tasks completed, numba's kernels cached in the node-local folder the script names.
* The hand-back at the time limit: the stop request the script asks for 120 s before the
  limit (``--signal=B:TERM``) is what ``scancel --batch --signal=TERM`` sends, the batch
  shell alone; Slurm's kill at the limit is what a plain ``scancel`` does (SIGTERM to every
  process of the job, SIGKILL after KillWait). A real time limit cannot be waited for
  here: Slurm counts limits in whole minutes and checks them every 30 s or so.

Needs the Debian packages slurmctld, slurmd, slurm-client and munge (skipped, saying so,
when they are not installed), root (slurmd starts jobs as their user), and a PostgreSQL
server in $SLOPETUI_TEST_PG (.ci/run starts one): a node-local SQLite file is what the
command refuses.
"""

from __future__ import annotations

import os
import pwd
import re
import shutil
import signal
import socket
import subprocess
import tempfile
import time
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

import pytest
from sqlalchemy import select

from slopetui.cli import main
from slopetui.store.database import Database
from slopetui.store.models import Run
from slopetui.store.open import open_store
from tests.integration.pool_support import by_status, wait_until
from tests.support import pg_database, submit_quick

PG_URL = os.environ.get("SLOPETUI_TEST_PG")
#: The daemons and the commands the tests use.
SLURM_PROGRAMS = ("munged", "slurmctld", "slurmd", "sbatch", "squeue", "scancel", "scontrol",
                  "sinfo")
SLURM_PACKAGES = "slurmctld slurmd slurm-client munge"
#: Seconds between Slurm's SIGTERM and SIGKILL (its default): a hand-back must be over
#: well before.
KILL_WAIT_S = 30
#: RK4 to t_end = 2e7: over a minute a run, so that a run is still in its kernel when the
#: signals come.
ENDLESS = {"t_end": 2e7}


def _program(name: str) -> str | None:
    """The path of a Slurm or munge program (the daemons are in /usr/sbin)."""
    return shutil.which(name, path=f"{os.environ.get('PATH', '')}:/usr/sbin:/sbin")


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@dataclass
class Cluster:
    """A running single-node Slurm: its configuration, and the processes to stop."""

    root: Path
    node: str
    partition: str
    env: dict[str, str]
    daemons: list[tuple[str, subprocess.Popen[bytes]]] = field(default_factory=list)

    def run(self, *args: str, cwd: Path | None = None) -> str:
        """A Slurm command against this cluster; its stdout (it must succeed)."""
        done = subprocess.run([_program(args[0]) or args[0], *args[1:]], env=self.env,
                              cwd=cwd, capture_output=True, text=True, timeout=60)
        assert done.returncode == 0, f"{args}: {done.stderr}\n{self.logs()}"
        return done.stdout

    def start(self, name: str, *args: str) -> None:
        with open(self.root / "log" / f"{name}.out", "wb") as out:
            proc = subprocess.Popen([_program(name) or name, *args], stdout=out,
                                    stderr=subprocess.STDOUT, env=self.env)
        self.daemons.append((name, proc))

    def logs(self) -> str:
        """The daemons' logs, for a failure's message."""
        return "\n".join(f"--- {p.name}\n{p.read_text(errors='replace')[-3000:]}"
                         for p in sorted((self.root / "log").iterdir()))

    def queued(self, job: str) -> list[str]:
        """The array tasks of ``job`` that Slurm still holds (pending, running, completing)."""
        out = subprocess.run([_program("squeue") or "squeue", "-h", "-j", job, "-o", "%i %T"],
                             env=self.env, capture_output=True, text=True, timeout=30)
        return out.stdout.split("\n")[:-1] if out.returncode == 0 else []

    def stop(self) -> None:
        """Cancel every job left, wait for its processes, then stop the daemons."""
        subprocess.run([_program("scancel") or "scancel", "--user", pwd.getpwuid(os.getuid()).pw_name],
                       env=self.env, capture_output=True, timeout=30)
        deadline = time.monotonic() + KILL_WAIT_S + 15
        while time.monotonic() < deadline and subprocess.run(
                [_program("squeue") or "squeue", "-h"], env=self.env, capture_output=True,
                text=True, timeout=30).stdout.strip():
            time.sleep(0.5)
        for _, proc in reversed(self.daemons):  # slurmd, slurmctld, then munged
            proc.send_signal(signal.SIGTERM)
            try:
                proc.wait(timeout=20)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait()


def _configuration(root: Path, node_line: str, node: str, user: str) -> str:
    return "\n".join([
        "ClusterName=slopetest",
        f"SlurmctldHost={node}(127.0.0.1)",
        f"SlurmctldPort={_free_port()}",
        f"SlurmdPort={_free_port()}",
        f"SlurmUser={user}",
        f"SlurmdUser={user}",
        "AuthType=auth/munge",
        "CredType=cred/munge",
        f"AuthInfo=socket={root}/munge/socket",
        f"StateSaveLocation={root}/state",
        f"SlurmdSpoolDir={root}/spool",
        f"SlurmctldPidFile={root}/slurmctld.pid",
        f"SlurmdPidFile={root}/slurmd.pid",
        f"SlurmctldLogFile={root}/log/slurmctld.log",
        f"SlurmdLogFile={root}/log/slurmd.log",
        "MailProg=/bin/true",
        # no cgroups in a container: processes tracked by their parentage, no binding
        "ProctrackType=proctrack/linuxproc",
        "TaskPlugin=task/none",
        "JobAcctGatherType=jobacct_gather/none",
        "AccountingStorageType=accounting_storage/none",
        "SelectType=select/cons_tres",
        "SelectTypeParameters=CR_CPU",
        "MpiDefault=none",
        "SchedulerType=sched/builtin",
        "ReturnToService=2",
        f"KillWait={KILL_WAIT_S}",
        f"{node_line} NodeAddr=127.0.0.1 State=UNKNOWN",
        f"PartitionName=workers Nodes={node} Default=YES MaxTime=INFINITE State=UP",
        "",
    ])


@pytest.fixture(scope="module")
def cluster() -> Iterator[Cluster]:
    missing = [name for name in SLURM_PROGRAMS if _program(name) is None]
    if missing:
        pytest.skip(f"Slurm is not installed (no {', '.join(missing)}): apt-get install "
                    f"{SLURM_PACKAGES}")
    # a short path: munge's socket must fit a Unix socket's 108 bytes
    root = Path(tempfile.mkdtemp(prefix="slopetui-slurm-"))
    for sub in ("munge", "state", "spool", "log", "jobs", "tmp"):
        (root / sub).mkdir(mode=0o700)
    key = root / "munge" / "key"
    key.write_bytes(os.urandom(1024))
    key.chmod(0o600)
    hardware = subprocess.run([_program("slurmd") or "slurmd", "-C"], capture_output=True,
                              text=True, timeout=30, check=True).stdout.splitlines()[0]
    node = hardware.split()[0].removeprefix("NodeName=")
    user = pwd.getpwuid(os.getuid()).pw_name
    conf = root / "slurm.conf"
    conf.write_text(_configuration(root, hardware, node, user))
    # the jobs inherit this environment (sbatch's default --export=ALL): the node-local
    # folder of the script and the pool files go in the test's folder
    env = {**os.environ, "SLURM_CONF": str(conf), "SLURM_TMPDIR": str(root / "tmp"),
           "XDG_STATE_HOME": str(root / "state-home")}
    env.pop("SLOPETUI_DB", None)
    cl = Cluster(root, node, "workers", env)
    try:
        cl.start("munged", "--foreground", "--force", f"--key-file={key}",
                 f"--socket={root}/munge/socket", f"--pid-file={root}/munge/pid",
                 f"--log-file={root}/log/munged.log", f"--seed-file={root}/munge/seed")
        wait_until("munged's socket", lambda: (root / "munge" / "socket").exists(), 20)
        cl.start("slurmctld", "-D", "-c", "-f", str(conf))
        cl.start("slurmd", "-D", "-f", str(conf))
        try:
            wait_until("the node to be idle", lambda: subprocess.run(
                [_program("sinfo") or "sinfo", "-h", "-n", node, "-o", "%T"], env=env,
                capture_output=True, text=True, timeout=30).stdout.strip() == "idle", 30)
        except AssertionError as exc:
            raise AssertionError(f"{exc}\n{cl.logs()}") from None
        yield cl
    finally:
        cl.stop()
        shutil.rmtree(root, ignore_errors=True)


@pytest.fixture
def pg_url() -> Iterator[str]:
    if not PG_URL:
        pytest.skip("no PostgreSQL server: set SLOPETUI_TEST_PG (.ci/run starts one)")
    with pg_database(PG_URL, f"slopetui_slurm_{os.getpid()}") as url:
        yield url


def kernel_cache(cl: Cluster) -> Path:
    """The folder of this engine's kernels in the node-local folder the script names."""
    from core.jit_cache import source_digest
    return cl.root / "tmp" / f"slopetui-kernels-{os.getuid()}" / source_digest()


def share_warm_kernels(cl: Cluster) -> None:
    """Copy this process's compiled kernels (if any: the suite's pools made them) into the
    node-local folder: a compilation costs 30 s to 2 min on two busy cores, and what is
    tested is the script, not numba. Without them the jobs compile, and take longer."""
    from core.jit_cache import cache_dir
    target = kernel_cache(cl)
    if cache_dir().is_dir() and not target.exists():
        target.parent.mkdir(mode=0o700, exist_ok=True)
        shutil.copytree(cache_dir(), target)


def write_script(cl: Cluster, url: str, capsys: pytest.CaptureFixture[str], *,
                 nodes: int, workers: int) -> Path:
    script = cl.root / "jobs" / f"workers-{nodes}x{workers}.sbatch"
    assert main(["cluster", "slurm", "--workers-per-node", str(workers), "--nodes", str(nodes),
                 "--time", "00:05:00", "--partition", cl.partition, "--db", url,
                 "-o", str(script), "--force"]) == 0
    out = capsys.readouterr()
    assert f"sbatch {script}" in out.out
    assert "only this machine reaches the database" in out.err  # true: one node here
    return script


def submit(cl: Cluster, script: Path) -> str:
    return cl.run("sbatch", "--parsable", str(script), cwd=script.parent).strip().split(";")[0]


def job_states(cl: Cluster, job: str) -> list[tuple[str, str]]:
    """(JobState, ExitCode) of every array task, from slurmctld's memory (MinJobAge)."""
    text = cl.run("scontrol", "show", "job", job)
    return re.findall(r"JobState=(\S+).*?ExitCode=(\S+)", text, flags=re.S)


def runs(db: Database) -> list[Run]:
    with db.sessions() as s:
        return list(s.scalars(select(Run).order_by(Run.id)))


def test_a_job_array_drains_the_queue_each_run_once(cluster, pg_url, capsys):
    db = open_store(pg_url)
    try:
        submit_quick(db, 8)
        script = write_script(cluster, pg_url, capsys, nodes=2, workers=1)
        share_warm_kernels(cluster)
        job = submit(cluster, script)
        try:
            wait_until("the array to leave the queue", lambda: not cluster.queued(job), 240)
        except AssertionError as exc:
            raise AssertionError(f"{exc}: {cluster.queued(job)}\n{cluster.logs()}") from None
        logs = [script.parent / f"slopetui-worker-{job}_{task}.log" for task in (0, 1)]
        text = "\n".join(log.read_text() for log in logs)
        assert job_states(cluster, job) == [("COMPLETED", "0:0")] * 2, text
        done = runs(db)
        assert [(r.status, r.attempts) for r in done] == [("done", 1)] * 8, text
        assert all(r.worker_id and r.worker_id.startswith(f"{cluster.node}:") for r in done)
        for log in logs:  # each task ran its pool to the end, Slurm's output in its log
            assert "pool of 1 workers" in log.read_text() and "pool stopped" in log.read_text()
        assert sum(text.count(f"run {r.id} done") for r in done) == 8  # once each
        # numba's kernels went to the node-local folder, private
        assert any(kernel_cache(cluster).rglob("*.nbi"))
        assert kernel_cache(cluster).parent.stat().st_mode & 0o777 == 0o700
    finally:
        db.dispose()


def test_the_stop_request_then_slurms_kill_give_the_runs_back(cluster, pg_url, capsys):
    db = open_store(pg_url)
    try:
        submit_quick(db, 2, **ENDLESS)
        script = write_script(cluster, pg_url, capsys, nodes=1, workers=2)
        share_warm_kernels(cluster)
        job = submit(cluster, script)
        log = script.parent / f"slopetui-worker-{job}_0.log"

        def both_in_kernels() -> bool:
            return [(r.status, r.started_at is not None) for r in runs(db)] == [("running", True)] * 2

        wait_until("both runs in their kernels", both_in_kernels, 240)
        # 120 s before the limit (#SBATCH --signal=B:TERM@120): the batch shell, the pool
        cluster.run("scancel", "--batch", "--signal=TERM", "--state=RUNNING", job)
        wait_until("the pool to stop claiming", lambda: "workers finish the runs they are "
                   "computing" in log.read_text(), 30)
        assert both_in_kernels()  # they finish what they compute (over a minute here)
        # the time limit: Slurm's SIGTERM to every process of the job, the pool's second
        killed_at = time.monotonic()
        cluster.run("scancel", job)
        wait_until("the job to end", lambda: not cluster.queued(job), KILL_WAIT_S + 30)
        took = time.monotonic() - killed_at
        text = log.read_text()
        assert "again: workers give their runs back" in text, text
        assert took < KILL_WAIT_S - 10, (took, text)  # given back, not killed by SIGKILL
        assert by_status(db) == {"queued": 2}
        assert [(r.attempts, r.worker_id) for r in runs(db)] == [(0, None)] * 2  # not counted
    finally:
        db.dispose()
