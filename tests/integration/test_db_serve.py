"""`slopetui db serve`: a PostgreSQL server of one's own, in real processes.

PostgreSQL refuses to run as root, and so does `slopetui db serve`. When these tests run
as root (CI's container), the server runs as an unprivileged user (postgres, else nobody):
Popen(user=...) drops to it, with HOME and the XDG folders in a temporary folder of its
own. That user may not be allowed to run this interpreter (a pyenv Python under /root):
then the system's Python of the same version runs this checkout with this environment's
packages (PYTHONPATH). The tests are skipped only where PostgreSQL's server programs are
not installed (`apt install postgresql`), and say so.
"""

from __future__ import annotations

import os
import pwd
import queue
import shutil
import signal
import socket
import stat
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import psycopg
import pytest
from sqlalchemy import func, select

import migrations
import slopetui
from slopetui.cli import main
from slopetui.ops import local_server as ls
from slopetui.store.database import Database
from slopetui.store.failures import StoreError
from slopetui.store.models import Run
from tests.support import slopetui_cli, submit_quick

REPO = Path(slopetui.__file__).resolve().parents[1]
#: How long a start (initdb included) or a stop may take before the test fails (s).
START_S, STOP_S = 60, 30


def _binaries() -> ls.Binaries:
    try:
        return ls.find_binaries()
    except StoreError as exc:
        pytest.skip(f"PostgreSQL's server programs are not installed: {exc}")


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("", 0))
        return int(probe.getsockname()[1])


def port_open(port: int) -> bool:
    try:
        socket.create_connection(("127.0.0.1", port), timeout=2).close()
    except OSError:
        return False
    return True


class Serve:
    """A `slopetui db serve` process, its output read line by line as it comes."""

    def __init__(self, proc: subprocess.Popen[str]) -> None:
        self.proc = proc
        self.lines: queue.Queue[str | None] = queue.Queue()
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        assert self.proc.stdout is not None
        for line in self.proc.stdout:
            self.lines.put(line.rstrip("\n"))
        self.lines.put(None)

    def ready(self, timeout: float = START_S) -> list[str]:
        """The lines up to the one that says how to stop it (the server is up then)."""
        seen: list[str] = []
        deadline = time.monotonic() + timeout
        while True:
            line = self.lines.get(timeout=max(0.1, deadline - time.monotonic()))
            if line is None:
                err = self.proc.stderr.read() if self.proc.stderr else ""
                raise AssertionError(f"serve exited {self.proc.wait()}: {seen} {err}")
            seen.append(line)
            if line.startswith("Ctrl-C"):
                return seen

    def rest(self) -> tuple[int, str, str]:
        """Its exit status, the rest of its output and its stderr, once it has exited."""
        code = self.proc.wait(timeout=STOP_S)
        out = []
        while (line := self.lines.get(timeout=5)) is not None:
            out.append(line)
        return code, "\n".join(out), self.proc.stderr.read() if self.proc.stderr else ""


@dataclass
class Runner:
    """Runs `python -m slopetui` as the server's (unprivileged) user."""

    python: str
    env: dict[str, str]
    home: Path  # a temporary folder of that user's
    user: int | None = None  # None: this process's user

    def _kwargs(self) -> dict:
        drop = {} if self.user is None else {
            "user": self.user, "group": pwd.getpwuid(self.user).pw_gid, "extra_groups": []}
        return {"env": self.env, "cwd": self.home, "text": True, **drop}

    def run(self, *args: str, timeout: float = 60) -> subprocess.CompletedProcess[str]:
        return subprocess.run([self.python, "-m", "slopetui", *args], capture_output=True,
                              timeout=timeout, **self._kwargs())

    def serve(self, *args: str) -> Serve:
        return Serve(subprocess.Popen([self.python, "-m", "slopetui", "db", "serve", *args],
                                      stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                      start_new_session=True, **self._kwargs()))

    def own(self, *paths: Path) -> None:
        """Give ``paths`` (made by this test) to the server's user."""
        if self.user is not None:
            for path in paths:
                os.chown(path, self.user, pwd.getpwuid(self.user).pw_gid, follow_symlinks=False)


def _unprivileged_user() -> int:
    for name in ("postgres", "nobody"):
        try:
            return pwd.getpwnam(name).pw_uid
        except KeyError:
            continue
    raise AssertionError("running as root, and no postgres or nobody user to serve as")


def _python_for(uid: int | None, env: dict[str, str], home: Path) -> tuple[str, dict[str, str]]:
    """An interpreter the user ``uid`` can run this checkout with, and its environment."""
    packages = [p for p in sys.path if p.endswith("site-packages") and os.path.isdir(p)]
    system = shutil.which(f"python{sys.version_info[0]}.{sys.version_info[1]}",
                          path="/usr/bin:/usr/local/bin:/bin")
    tried = []
    for python, extra in ((sys.executable, {}),
                          (system, {"PYTHONPATH": os.pathsep.join([str(REPO), *packages])})):
        if python is None:
            continue
        probe_env = {**env, **extra}
        drop = {} if uid is None else {"user": uid, "group": pwd.getpwuid(uid).pw_gid,
                                       "extra_groups": []}
        try:
            probe = subprocess.run([python, "-c", "import slopetui.cli, psycopg"],
                                   env=probe_env, cwd=home, capture_output=True, text=True,
                                   timeout=60, **drop)
        except OSError as exc:  # not allowed to run it at all
            tried.append(f"{python}: {exc.strerror}")
            continue
        if probe.returncode == 0:
            return python, probe_env
        tried.append(f"{python}: {probe.stderr.strip().splitlines()[-1:]}")
    raise AssertionError(f"no Python that user {uid} can run slopetui with: {tried}")


@pytest.fixture
def runner() -> Iterator[Runner]:
    _binaries()
    uid = _unprivileged_user() if os.geteuid() == 0 else None
    # not under pytest's tmp_path: /tmp/pytest-of-root is closed to other users
    home = Path(tempfile.mkdtemp(prefix="slopetui-serve-"))
    env = {k: v for k, v in os.environ.items() if k not in ("SLOPETUI_DB", "PYTHONPATH")}
    env.update(HOME=str(home), XDG_DATA_HOME=str(home / "data"),
               XDG_CACHE_HOME=str(home / "cache"), XDG_STATE_HOME=str(home / "state"))
    r = Runner(sys.executable, env, home, uid)
    try:
        r.own(home)
        r.python, r.env = _python_for(uid, env, home)
        yield r
    finally:
        for data in home.glob("*/data"):  # a server a failed test left running
            if ls.postmaster_info(data.parent) is not None:
                r.run("db", "serve", "--dir", str(data.parent), "--stop")
        shutil.rmtree(home, ignore_errors=True)


def _urls(lines: list[str]) -> tuple[str, str]:
    """(the workers' URL, this machine's) from serve's output."""
    exported = [ln for ln in lines if ln.strip().startswith("export SLOPETUI_DB=")]
    here = [ln for ln in lines if ln.startswith("on this machine: ")]
    assert len(exported) == 1 and len(here) == 1, lines
    return (exported[0].split("=", 1)[1].strip().strip("'"),
            here[0].removeprefix("on this machine: ").strip())


def _runs(url: str) -> int:
    db = Database(url)
    try:
        with db.sessions() as s:
            return int(s.scalar(select(func.count()).select_from(Run)) or 0)
    finally:
        db.dispose()


def test_serve_keeps_a_password_protected_database_across_restarts(runner):
    folder, port = runner.home / "pg", free_port()
    t0 = time.monotonic()
    serve = runner.serve("--dir", str(folder), "--port", str(port))
    lines = serve.ready()
    first_start = time.monotonic() - t0
    worker_url, here = _urls(lines)
    assert "new cluster (initdb" in lines[0], lines
    password = (folder / "password").read_text().strip()
    assert len(password) >= 32
    assert worker_url.startswith(f"postgresql+psycopg://slopetui:{password}@")
    assert worker_url.endswith(f":{port}/slopetui")
    assert here == f"postgresql+psycopg://slopetui:{password}@127.0.0.1:{port}/slopetui"
    assert stat.S_IMODE(folder.stat().st_mode) == 0o700
    assert stat.S_IMODE((folder / "password").stat().st_mode) == 0o600
    assert (folder / "url").read_text().strip() == worker_url

    # the printed URL reaches a database at the current schema, over TCP, and queues runs
    db = Database(here)
    assert db.opened_revision == migrations.HEAD
    assert submit_quick(db, 3).n_runs == 3
    db.dispose()
    # over the network: only the role slopetui, only with its password
    with pytest.raises(psycopg.OperationalError, match="password authentication failed"):
        psycopg.connect(host="127.0.0.1", port=port, dbname="slopetui", user="slopetui",
                        password="not-" + password, connect_timeout=10)
    superuser = pwd.getpwuid(runner.user if runner.user is not None else os.geteuid()).pw_name
    with pytest.raises(psycopg.OperationalError, match=r"no pg_hba\.conf entry"):
        psycopg.connect(host="127.0.0.1", port=port, dbname="postgres", user=superuser,
                        password=password, connect_timeout=10)
    status = runner.run("db", "serve", "--dir", str(folder), "--status")
    assert status.returncode == 0 and "ready" in status.stdout, status

    # SIGTERM: pg_ctl stop -m fast, exit 0, nothing left running
    serve.proc.send_signal(signal.SIGTERM)
    code, out, err = serve.rest()
    assert code == 0, (out, err)
    assert "SIGTERM: stopping the server" in out and "stopped" in out
    assert not (folder / "data" / "postmaster.pid").exists() and not port_open(port)
    assert not (folder / "serve.pid").exists()

    # again, without --port: the same port, password and runs
    t0 = time.monotonic()
    serve = runner.serve("--dir", str(folder))
    lines = serve.ready()
    restart = time.monotonic() - t0
    assert "existing cluster" in lines[0], lines
    assert _urls(lines) == (worker_url, here)
    assert _runs(here) == 3
    # `--stop` from another process: the serve that runs it stops it and exits 0
    stop = runner.run("db", "serve", "--dir", str(folder), "--stop")
    assert stop.returncode == 0 and "stopped" in stop.stdout, stop
    code, out, err = serve.rest()
    assert code == 0 and not port_open(port), (out, err)

    # a server that dies on its own (kill -9): serve says so, and exits 1
    serve = runner.serve("--dir", str(folder))
    serve.ready()
    info = ls.postmaster_info(folder)
    assert info is not None
    os.kill(info.pid, signal.SIGKILL)
    code, out, err = serve.rest()
    assert code == 1 and "stopped on its own" in err, (out, err)
    print(f"\nfirst start (initdb) {first_start:.1f} s, restart {restart:.1f} s "
          f"(wall time, Python's start included)")


def test_a_busy_port_or_a_foreign_folder_is_refused_before_anything_is_written(runner):
    folder = runner.home / "pg"
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        out = runner.run("db", "serve", "--dir", str(folder), "--port", str(port))
    assert out.returncode == 2, out
    assert f"--port: {port} is already in use" in out.stderr and len(out.stderr.splitlines()) == 1
    assert not folder.exists()

    thesis = runner.home / "thesis"
    thesis.mkdir()
    (thesis / "thesis.tex").write_text("\\documentclass{article}\n")
    runner.own(thesis, thesis / "thesis.tex")
    out = runner.run("db", "serve", "--dir", str(thesis), "--port", str(free_port()))
    assert out.returncode == 2 and "--dir" in out.stderr and "not empty" in out.stderr, out
    assert os.listdir(thesis) == ["thesis.tex"]

    # on a shared file system: a server another node started and did not stop may still
    # run there, and PostgreSQL checks its postmaster.pid on this node only
    shared = runner.home / "shared"
    (shared / "data").mkdir(parents=True)
    (shared / "data" / "PG_VERSION").write_text(f"{_binaries().major}\n")
    (shared / "data" / "postmaster.pid").write_text("4242\n")
    (shared / "server.host").write_text("node-17\n")
    runner.own(shared, *shared.rglob("*"))
    out = runner.run("db", "serve", "--dir", str(shared), "--port", str(free_port()))
    assert out.returncode == 2 and "was started on node-17" in out.stderr, out
    assert sorted(p.name for p in shared.rglob("*")) == [
        "PG_VERSION", "data", "postmaster.pid", "server.host"]


def test_an_initdb_that_fails_midway_leaves_nothing_behind(runner):
    real = _binaries().folder
    fake = runner.home / "bin"
    fake.mkdir()
    for tool in ("pg_ctl", "postgres"):
        (fake / tool).symlink_to(real / tool)
    # an initdb that has written part of a cluster (-D DIR comes first) when it fails
    (fake / "initdb").write_text('#!/bin/sh\nmkdir -p "$2/base/1" && echo 15 > "$2/PG_VERSION"\n'
                                 'echo "initdb: error: disk quota exceeded (simulated)" >&2\n'
                                 "exit 1\n")
    (fake / "initdb").chmod(0o755)
    runner.own(fake, *fake.iterdir())
    folder = runner.home / "pg"
    out = runner.run("db", "serve", "--dir", str(folder), "--port", str(free_port()),
                     "--pg-bin", str(fake))
    assert out.returncode == 2, out
    assert "initdb failed" in out.stderr and "simulated" in out.stderr
    assert not folder.exists()


def test_serve_as_root_is_refused_and_creates_nothing(tmp_path, monkeypatch, capsys):
    folder = tmp_path / "pg"
    if os.geteuid() == 0:
        out = slopetui_cli("db", "serve", "--dir", str(folder), timeout=60)
        code, err = out.returncode, out.stderr
    else:  # the same check, as root would meet it
        monkeypatch.setattr(os, "geteuid", lambda: 0)
        code, err = main(["db", "serve", "--dir", str(folder)]), capsys.readouterr().err
    assert code == 2
    assert "refuses to run as root" in err and len(err.splitlines()) == 1, err
    assert not folder.exists()


def test_a_read_only_file_system_is_named(tmp_path, monkeypatch):
    real = os.statvfs

    def read_only(path: os.PathLike[str] | str) -> os.statvfs_result:
        values = list(real(path))
        values[8] |= os.ST_RDONLY  # f_flag
        return os.statvfs_result(values)

    monkeypatch.setattr(os, "statvfs", read_only)
    with pytest.raises(StoreError, match=r"--dir: .* is on a read-only file system"):
        ls.check_folder(tmp_path / "pg", make_parents=False)
    assert not (tmp_path / "pg").exists()
