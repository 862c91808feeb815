"""A PostgreSQL server of one's own, for researchers without a database administrator:
the service behind ``slopetui db serve`` (initdb and pg_ctl as the user, no root).

The server lives in one folder, DIR (default ``default_folder()``,
~/.local/share/slopetui/postgres), mode 700:

    data/          the cluster (initdb), with this module's pg_hba.conf and its settings
                   in data/slopetui.conf (rewritten at each start from the options)
    password       the password of the role ``slopetui`` (mode 600, made once)
    url            the URL for the workers, written at each start (mode 600)
    read-password  the password of the role ``slopetui_read`` (mode 600, made once)
    read-url       the URL for reading only (SLOPETUI_READ_DB), written at each start
    server.log     the server's log (pg_ctl -l)
    serve.lock     flock()ed by the ``slopetui db serve`` process that runs the server
    serve.pid      that process's pid, so that ``--stop`` can ask it to stop
    server.host    the machine the server was last started on (DIR may be on a shared
                   file system: PostgreSQL's own postmaster.pid is checked on one host)
    .s.PGSQL.PORT  the server's Unix socket (the folder's mode keeps other users out)

Security. The server listens on the network so that workers on other nodes reach it, so
nothing is trusted over TCP: the only role allowed there is ``slopetui`` (no superuser,
cannot create roles or databases), on the database ``slopetui`` only, with a random
password (``secrets``, 192 bits) checked by scram-sha-256 (a challenge-response: the
password never crosses the network). The server stores only a SCRAM verifier, computed
here by libpq, so the password is never sent to the server in clear either. The
superuser is the folder's owner, on the Unix socket only (peer authentication). TCP is
not encrypted (no TLS): someone on the network between the workers and the server can
read the queries and the results, not the password.

Reading only. ``slopetui sql`` and the application's console refuse writes (a READ ONLY
transaction), but a READ ONLY transaction still lets a role cancel or terminate the
backends of its own role and take advisory locks, and the workers' role is everyone's.
So the server has a second role, ``slopetui_read``: SELECT on the tables of ``slopetui``
(default privileges cover the tables that later migrations add), no other privilege, not
a member of ``slopetui`` (so ``pg_terminate_backend`` and ``pg_cancel_backend`` refuse
the workers' backends), and no EXECUTE on the advisory lock functions, which are revoked
from PUBLIC and granted to ``slopetui`` alone. Its URL is in DIR/read-url: the commands
that only read use it when ``SLOPETUI_READ_DB`` names it (slopetui.store.database), and a
colleague who should only read gets that URL, not the workers'.

Nothing here prints: the functions return what happened and raise ``StoreError`` with a
one-line message naming the option (--dir, --port...) for what the user can fix.
"""

from __future__ import annotations

import contextlib
import errno
import fcntl
import ipaddress
import os
import pwd
import re
import secrets
import select
import shutil
import signal
import socket
import subprocess
import time
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

from platformdirs import user_data_path

from slopetui.store.failures import StoreError
from slopetui.store.pg_programs import distribution_folders

#: The port when none is given and none is stored in DIR. Not PostgreSQL's 5432: that is
#: where a system server runs (Debian's `apt install postgresql` starts one there).
DEFAULT_PORT = 54320
#: Listen on every interface: the workers are on other nodes.
DEFAULT_LISTEN = "*"
#: PostgreSQL's own default. A worker pool holds 2 connections by default whatever its
#: size (slopetui.ops.connection_slots), so 100 serve some 45 pools with room to spare.
DEFAULT_MAX_CONNECTIONS = 100
#: The role and the database the workers use.
ROLE = DATABASE = "slopetui"
#: The role that only reads (module docstring).
READ_ROLE = "slopetui_read"
#: Oldest PostgreSQL accepted: scram-sha-256 (password_encryption, initdb --auth-host)
#: appeared in 10.
MIN_MAJOR = 10
#: pg_ctl waits this long for a start, and for a stop (s). A start after a crash replays
#: the WAL; a fast stop writes a checkpoint.
START_TIMEOUT_S = 120
STOP_TIMEOUT_S = 120
#: initdb of an empty cluster takes ~1 s; a slow shared file system may need far more (s).
INITDB_TIMEOUT_S = 600
#: How often the foreground waits check on the server when pidfd is not available (s).
POLL_S = 1.0
#: The longest Unix socket path (sun_path is 108 bytes with its NUL, on Linux).
MAX_SOCKET_PATH = 107
#: Characters refused in DIR: pg_ctl passes the log's and the data's paths through
#: `/bin/sh -c "..."` in double quotes, where these are special.
SHELL_SPECIAL = set('"$`\\\'')
#: What a --listen may hold: host names, IPv4 and IPv6 addresses, '*', commas.
LISTEN_CHARS = re.compile(r"[A-Za-z0-9.:*_, -]+")
#: The names this module writes in DIR (a folder holding anything else is not its own).
OWN_NAMES = frozenset({"data", "data.init", "password", "url", "read-password", "read-url",
                       "server.log", "serve.lock",
                       "serve.pid", "server.host"})
TOOLS = ("initdb", "pg_ctl", "postgres")
INSTALL_HINT = ("install them (Debian/Ubuntu: sudo apt install postgresql; without root: "
                "conda install -c conda-forge postgresql; on a cluster: module load "
                "postgresql), or name their folder with --pg-bin")


def default_folder() -> Path:
    """~/.local/share/slopetui/postgres on Linux (the platform's user data folder)."""
    return user_data_path("slopetui") / "postgres"


# --- what is needed before anything is written ---------------------------------------


def check_not_root() -> None:
    """PostgreSQL refuses to run as root (initdb and postgres exit at once): say so first."""
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        raise StoreError("PostgreSQL refuses to run as root: run `slopetui db serve` as "
                         "your own (unprivileged) user; nothing was created")


def check_driver() -> None:
    """The server is useless to slopetui without the PostgreSQL driver."""
    try:
        import psycopg  # noqa: F401
    except ImportError:
        raise StoreError("the PostgreSQL driver is not installed: pip install "
                         "'slopetui[postgres]' (psycopg), here and where the workers run"
                         ) from None


@dataclass(frozen=True)
class Binaries:
    """PostgreSQL's server programs: their folder and version ("15.6")."""

    folder: Path
    version: str

    @property
    def major(self) -> int:
        return int(self.version.split(".")[0])

    def tool(self, name: str) -> str:
        return str(self.folder / name)


def _version(folder: Path) -> str | None:
    """The version of the programs in ``folder`` ("15.6"), None if pg_ctl does not run."""
    try:
        out = subprocess.run([str(folder / "pg_ctl"), "--version"], capture_output=True,
                             text=True, timeout=30, check=True).stdout
    except (OSError, subprocess.SubprocessError):
        return None
    match = re.search(r"\(PostgreSQL\)\s+(\d+(?:\.\d+)?)", out)
    return match.group(1) if match else None


def _has_tools(folder: Path) -> bool:
    return all(os.access(folder / name, os.X_OK) for name in TOOLS)


def _candidates() -> list[Path]:
    """Folders that may hold the server programs, in the order they are tried: PATH's
    pg_ctl (a symlink is followed: initdb and postgres sit beside the real one), then the
    distributions' folders, newest version first."""
    found: list[Path] = []
    on_path = shutil.which("pg_ctl")
    if on_path:
        found.append(Path(on_path).resolve().parent)
    return found + distribution_folders()


def find_binaries(pg_bin: Path | None = None) -> Binaries:
    """The server programs (initdb, pg_ctl, postgres): in ``pg_bin`` if given, else
    PATH's, else the newest of /usr/lib/postgresql/*/bin and the like."""
    if pg_bin is not None:
        missing = [name for name in TOOLS if not os.access(pg_bin / name, os.X_OK)]
        if missing:
            raise StoreError(f"--pg-bin: {pg_bin} holds no {', '.join(missing)} "
                             "(PostgreSQL's server programs)")
        folders = [pg_bin]
    else:
        folders = [f for f in _candidates() if _has_tools(f)]
    for folder in folders:
        version = _version(folder)
        if version is None:
            continue
        if int(version.split(".")[0]) < MIN_MAJOR:
            raise StoreError(f"PostgreSQL {version} in {folder} is too old: {MIN_MAJOR} or "
                             f"newer is needed; {INSTALL_HINT}")
        return Binaries(folder, version)
    raise StoreError("no PostgreSQL server programs (initdb, pg_ctl, postgres) on PATH or "
                     f"in /usr/lib/postgresql/*/bin: {INSTALL_HINT}")


@dataclass(frozen=True)
class Settings:
    """The server's settings. None: the value stored in DIR by the last start, else the
    default (so that a later `slopetui db serve` gives the workers the same URL)."""

    port: int | None = None  # TCP port (default DEFAULT_PORT, 54320)
    listen: str | None = None  # listen_addresses: '*', or addresses/names, comma-separated
    max_connections: int | None = None  # default DEFAULT_MAX_CONNECTIONS, 100


def check_folder_name(folder: Path) -> None:
    """Refuse a DIR that pg_ctl's shell or the socket's path cannot carry."""
    text = str(folder)
    bad = sorted(SHELL_SPECIAL.intersection(text)) + [c for c in text if ord(c) < 32]
    if bad:
        raise StoreError(f"--dir: {text!r} holds {' '.join(map(repr, bad))}, which pg_ctl "
                         "cannot pass to its shell: choose another folder")
    socket_path = len(os.fsencode(folder / ".s.PGSQL.65535"))
    if socket_path > MAX_SOCKET_PATH:
        raise StoreError(f"--dir: {folder} is too long for the server's Unix socket in it "
                         f"({socket_path} > {MAX_SOCKET_PATH} bytes): choose a shorter path")


def _foreign_entries(folder: Path) -> list[str]:
    """What ``folder`` holds beyond this module's files: its own names, the server's
    socket, and the temporary files of ``_write_private`` a killed start left."""
    own = OWN_NAMES | {f".{name}.tmp" for name in OWN_NAMES}
    return sorted(name for name in os.listdir(folder)
                  if name not in own and not name.startswith(".s.PGSQL."))


def check_folder(folder: Path, *, make_parents: bool) -> None:
    """Refuse a DIR that cannot be this server's, before anything is written.

    make_parents : the folder's parents may be created (the default DIR). An explicit
                   --dir whose parent does not exist is more likely a typo.
    """
    check_folder_name(folder)
    if folder.exists():
        if not folder.is_dir():
            raise StoreError(f"--dir: {folder} is not a folder")
        if folder.stat().st_uid != os.geteuid():
            raise StoreError(f"--dir: {folder} belongs to another user: give a folder of "
                             "your own")
        if (folder / "PG_VERSION").exists():
            raise StoreError(f"--dir: {folder} is a PostgreSQL data folder made without "
                             "slopetui: give `slopetui db serve` a new or empty folder (it "
                             "keeps its cluster in DIR/data)")
        foreign = _foreign_entries(folder)
        if foreign:
            shown = ", ".join(foreign[:5]) + (", ..." if len(foreign) > 5 else "")
            raise StoreError(f"--dir: {folder} is not empty and not a slopetui server "
                             f"folder (it holds {shown}): give a new or empty folder")
        where = folder
    else:
        where = folder.parent
        while make_parents and not where.exists() and where != where.parent:
            where = where.parent
        if not where.is_dir():
            raise StoreError(f"--dir: the folder {folder.parent} does not exist (create it "
                             "first)")
    if os.statvfs(where).f_flag & os.ST_RDONLY:
        raise StoreError(f"--dir: {where} is on a read-only file system")
    if not os.access(where, os.W_OK | os.X_OK):
        raise StoreError(f"--dir: no permission to write in {where}")


def _bind_error(host: str | None, port: int) -> OSError | None:
    """The error binding ``host``:``port`` gives (as PostgreSQL binds it: SO_REUSEADDR,
    so a port in TIME_WAIT is free and one with a listener is not), None if it is free."""
    try:
        infos = socket.getaddrinfo(host, port, type=socket.SOCK_STREAM,
                                   flags=socket.AI_PASSIVE)
    except socket.gaierror as exc:
        return OSError(errno.EADDRNOTAVAIL, str(exc))
    for family, kind, proto, _name, address in infos:
        try:
            with socket.socket(family, kind, proto) as probe:
                probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
                probe.bind(address)
        except OSError as exc:
            if exc.errno in (errno.EAFNOSUPPORT, errno.EPROTONOSUPPORT):
                continue  # no IPv6 on this machine: PostgreSQL skips it as well
            return exc
    return None


def _listen_hosts(listen: str) -> list[str | None]:
    """The hosts of a listen_addresses value to bind (None: every interface)."""
    hosts = [h.strip() for h in listen.split(",") if h.strip()]
    return [None if h in ("*", "0.0.0.0", "::") else h for h in hosts]


def check_port(port: int, listen: str) -> None:
    """Refuse a --port that another program already listens on, and a --listen that is
    not this machine's, before anything is written (PostgreSQL's own message would come
    after an initdb)."""
    if not LISTEN_CHARS.fullmatch(listen):
        raise StoreError(f"--listen: {listen!r} is not a list of addresses ('*', or "
                         "names and IP addresses separated by commas)")
    for host in _listen_hosts(listen):
        exc = _bind_error(host, port)
        if exc is None:
            continue
        if exc.errno == errno.EADDRINUSE:
            raise StoreError(f"--port: {port} is already in use on this machine (another "
                             "server?): choose another --port")
        if exc.errno == errno.EACCES:
            raise StoreError(f"--port: {port} needs root here: choose one from 1024 up")
        if exc.errno == errno.EADDRNOTAVAIL:
            raise StoreError(f"--listen: {host} is not an address of this machine")
        raise StoreError(f"--port: cannot listen on {host or '*'}:{port}: {exc.strerror}")


# --- the folder, its lock and its files ----------------------------------------------


def _owner() -> str:
    """The user running this: initdb's superuser, reached by peer authentication (the
    effective user's name, not $USER, which `su` and `runuser` may leave behind)."""
    return pwd.getpwuid(os.geteuid()).pw_name


def _write_private(path: Path, text: str) -> None:
    """Write ``path`` readable by its owner only, whole or not at all (a temporary file
    renamed over it)."""
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.unlink(missing_ok=True)
    fd = os.open(tmp, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o600)
    with os.fdopen(fd, "w") as out:
        out.write(text)
        out.flush()
        os.fsync(out.fileno())
    os.replace(tmp, path)


def _try_lock(folder: Path) -> int | None:
    """flock DIR/serve.lock: its descriptor, or None if another process holds it. The
    kernel drops the lock when its holder dies, kill -9 included."""
    fd = os.open(folder / "serve.lock", os.O_RDWR | os.O_CREAT, 0o600)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        os.close(fd)
        return None
    return fd


def _serve_pid(folder: Path) -> int | None:
    try:
        return int((folder / "serve.pid").read_text().strip())
    except (OSError, ValueError):
        return None


def read_password(folder: Path, name: str = "password") -> str | None:
    """The role's password stored in DIR/password (``name``: DIR/read-password, the
    reading role's), None if there is none yet."""
    try:
        text = (folder / name).read_text().strip()
    except FileNotFoundError:
        return None
    return text or None


def _password(folder: Path, name: str = "password") -> str:
    """The role's password (``name``: read-password, the reading role's): the stored one,
    else a new one, stored (mode 600). Deleting the file and starting again gives the
    role a new password."""
    stored = read_password(folder, name)
    if stored is not None:
        os.chmod(folder / name, 0o600)  # in case someone loosened it
        return stored
    password = secrets.token_urlsafe(24)  # 192 bits; URL-safe: no escaping in the URL
    _write_private(folder / name, password + "\n")
    return password


def _conf_string(text: str) -> str:
    """A string value of postgresql.conf."""
    return "'" + text.replace("\\", "\\\\").replace("'", "''") + "'"


def _pg_hba(owner: str) -> str:
    return f"""\
# Written by `slopetui db serve`: who may connect, and how (first match wins).
# TYPE  DATABASE  USER      ADDRESS    METHOD
# the owner of this folder, as the superuser, on the Unix socket only (in a folder of mode 700)
local   all       "{owner}"            peer
# the workers: the role {ROLE} (no superuser), on its database, with its password
local   {DATABASE}  {ROLE}               scram-sha-256
host    {DATABASE}  {ROLE}  0.0.0.0/0  scram-sha-256
host    {DATABASE}  {ROLE}  ::/0       scram-sha-256
# readers: the role {READ_ROLE} (SELECT only), on the same database, with its own password
local   {DATABASE}  {READ_ROLE}               scram-sha-256
host    {DATABASE}  {READ_ROLE}  0.0.0.0/0  scram-sha-256
host    {DATABASE}  {READ_ROLE}  ::/0       scram-sha-256
"""


def _settings_conf(folder: Path, port: int, listen: str, max_connections: int) -> str:
    socket_dir = '"' + str(folder) + '"'  # one element of a list: commas and spaces stay
    return f"""\
# Written by `slopetui db serve` at each start, from its options (--port, --listen,
# --max-connections): edit those, not this file. Other settings: postgresql.conf, or
# ALTER SYSTEM (postgresql.auto.conf is read after this file).
listen_addresses = {_conf_string(listen)}
port = {port}
max_connections = {max_connections}
unix_socket_directories = {_conf_string(socket_dir)}
unix_socket_permissions = 0700
password_encryption = 'scram-sha-256'
# A worker node that vanished (power, network) leaves its connections open; keepalives
# close them within ~2 minutes, so that they stop counting against max_connections.
tcp_keepalives_idle = 60
tcp_keepalives_interval = 10
tcp_keepalives_count = 6
# fsync, full_page_writes and synchronous_commit keep PostgreSQL's defaults (on): this is
# the experiment's data, and claims and results are small transactions.
"""


def stored_settings(folder: Path) -> dict[str, str]:
    """The settings the last start wrote in DIR/data/slopetui.conf, as text ({} if none)."""
    try:
        lines = (folder / "data" / "slopetui.conf").read_text().splitlines()
    except FileNotFoundError:
        return {}
    found: dict[str, str] = {}
    for line in lines:
        match = re.fullmatch(r"(\w+) = (.*)", line.strip())
        if match:
            value = match.group(2)
            if value.startswith("'") and value.endswith("'"):
                value = value[1:-1].replace("''", "'").replace("\\\\", "\\")
            found[match.group(1)] = value
    return found


def resolve_settings(folder: Path, settings: Settings) -> tuple[int, str, int]:
    """(port, listen_addresses, max_connections): the options, else what DIR stores, else
    the defaults."""
    stored = stored_settings(folder)

    def stored_int(key: str, default: int) -> int:
        try:
            return int(stored.get(key, default))
        except ValueError:  # edited by hand despite its header: the default then
            return default

    port = settings.port or stored_int("port", DEFAULT_PORT)
    listen = settings.listen or stored.get("listen_addresses", DEFAULT_LISTEN)
    max_connections = settings.max_connections or stored_int("max_connections",
                                                             DEFAULT_MAX_CONNECTIONS)
    return port, listen, max_connections


def _started_on(folder: Path) -> str | None:
    """The machine that last started the server of DIR (DIR/server.host), if known."""
    try:
        return (folder / "server.host").read_text().strip() or None
    except FileNotFoundError:
        return None


def elsewhere(folder: Path) -> str | None:
    """The other machine the server of DIR may still run on, else None: the one that
    started it last, if that is not this one and the server did not stop cleanly (its
    postmaster.pid is still there). PostgreSQL checks that pid on the host it starts on
    only, so a second server on a shared folder would start, and the two would destroy
    the cluster."""
    host = _started_on(folder)
    if host is None or host == socket.gethostname():
        return None
    return host if (folder / "data" / "postmaster.pid").exists() else None


def _refuse_elsewhere(folder: Path) -> None:
    host = elsewhere(folder)
    if host is not None:
        raise StoreError(f"--dir: the server of {folder} was started on {host} and did not "
                         f"stop cleanly there: if it still runs, stop it on {host} "
                         f"(`slopetui db serve --stop`); if {host} is down, delete "
                         f"{folder / 'data' / 'postmaster.pid'} and start again (two "
                         "servers on one folder would destroy it)")


def _cluster_major(folder: Path) -> int | None:
    """The PostgreSQL major version of DIR/data, None if there is no cluster yet."""
    try:
        return int((folder / "data" / "PG_VERSION").read_text().strip().split(".")[0])
    except FileNotFoundError:
        return None


def _command_error(what: str, result: subprocess.CompletedProcess[str]) -> str:
    """The last lines a failed initdb or pg_ctl wrote, on one line."""
    lines = [ln.strip() for ln in (result.stderr + result.stdout).splitlines() if ln.strip()]
    return f"{what} failed (exit {result.returncode}): {' / '.join(lines[-3:]) or 'no message'}"


def _run(argv: list[str], timeout: float) -> subprocess.CompletedProcess[str]:
    """Run a PostgreSQL program in a session of its own (a Ctrl-C on the terminal reaches
    `slopetui db serve`, which acts on it, not its initdb halfway), without the PG*
    variables of the caller's environment (a PGDATA or PGPORT must not redirect it)."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("PG")}
    try:
        return subprocess.run(argv, capture_output=True, text=True, timeout=timeout,
                              env=env, start_new_session=True, check=False)
    except subprocess.TimeoutExpired as exc:
        raise StoreError(f"{Path(argv[0]).name} did not finish within {timeout:g} s") from exc


def _initdb(folder: Path, binaries: Binaries) -> None:
    """Make the cluster in DIR/data.init, write its pg_hba.conf and the include of the
    settings, then rename it to DIR/data: DIR/data exists whole or not at all, so an
    initdb that failed or was killed leaves nothing that stops a retry."""
    staging = folder / "data.init"
    shutil.rmtree(staging, ignore_errors=True)  # a killed attempt's (the lock is ours)
    try:
        result = _run([binaries.tool("initdb"), "-D", str(staging), "-U", _owner(),
                       "--no-locale", "--encoding=UTF8", "--data-checksums",
                       "--auth-local=peer", "--auth-host=scram-sha-256"],
                      timeout=INITDB_TIMEOUT_S)
        if result.returncode != 0:
            raise StoreError(f"--dir: {_command_error('initdb', result)}")
        (staging / "pg_hba.conf").write_text(_pg_hba(_owner()))
        with open(staging / "postgresql.conf", "a") as conf:
            conf.write("\n# slopetui db serve: its settings (port, listen_addresses...)\n"
                       "include = 'slopetui.conf'\n")
        # written now too, so that the cluster can start even before the first serve
        # writes it (and a pg_ctl start by hand finds it)
        _write_private(staging / "slopetui.conf",
                       _settings_conf(folder, DEFAULT_PORT, DEFAULT_LISTEN,
                                      DEFAULT_MAX_CONNECTIONS))
        os.rename(staging, folder / "data")
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise


# --- the running server ----------------------------------------------------------------


@dataclass(frozen=True)
class PostmasterInfo:
    """What DIR/data/postmaster.pid says of a server (PostgreSQL writes it at start)."""

    pid: int
    started: float  # time.time() of its start
    port: int
    status: str  # "starting", "ready", "stopping"


def postmaster_info(folder: Path) -> PostmasterInfo | None:
    """The server of DIR if it runs, else None (no postmaster.pid, or a stale one)."""
    try:
        lines = (folder / "data" / "postmaster.pid").read_text().splitlines()
        info = PostmasterInfo(int(lines[0]), float(lines[2]), int(lines[3]),
                              lines[7].strip() if len(lines) > 7 else "")
    except (OSError, ValueError, IndexError):
        return None
    return info if _alive(info.pid) else None


def _alive(pid: int) -> bool:
    """Is ``pid`` a live process of this user (not a zombie)?"""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's: the pid was reused, ours is gone
        return False
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return True  # no /proc (macOS): kill(0) has to do
    return stat.rsplit(")", 1)[-1].split()[0] != "Z"


def log_reason(log: Path, offset: int = 0, *, silent: str | None = None) -> str:
    """The lines of the server's log since ``offset`` (bytes) that say why it did not
    start or why it stopped, on one line.

    silent : what to say if no line of the log tells (default: its last line)
    """
    try:
        with open(log, errors="replace") as f:
            f.seek(offset)
            lines = f.read().splitlines()
    except OSError:
        return "no log"
    wanted = [ln.strip() for ln in lines
              if any(w in ln for w in ("FATAL", "PANIC", "could not", "terminated by",
                                           "shutdown request"))]
    if wanted:
        return " / ".join(wanted[-3:])
    return silent or (lines[-1].strip() if lines else "no log")


def _pg_ctl_start(folder: Path, binaries: Binaries, offset: int) -> PostmasterInfo:
    """Start the server (pg_ctl start -w: it returns once the server accepts
    connections). pg_ctl starts it in a session of its own: it is no child of this
    process, and no Ctrl-C on the terminal reaches it. ``offset``: the log's size before
    (its lines after it are this start's)."""
    log = folder / "server.log"
    result = _run([binaries.tool("pg_ctl"), "start", "-D", str(folder / "data"), "-l",
                   str(log), "-w", "-t", str(START_TIMEOUT_S), "-s"],
                  timeout=START_TIMEOUT_S + 30)
    info = postmaster_info(folder)
    if result.returncode != 0 or info is None:
        raise StoreError(f"the server did not start: {log_reason(log, offset)} (log: {log})")
    return info


def pg_ctl_stop(folder: Path, binaries: Binaries) -> None:
    """Stop the server of DIR: pg_ctl stop -m fast (open transactions are rolled back, the
    clients disconnected, a checkpoint written) and wait until it has exited."""
    result = _run([binaries.tool("pg_ctl"), "stop", "-D", str(folder / "data"), "-m",
                   "fast", "-w", "-t", str(STOP_TIMEOUT_S), "-s"],
                  timeout=STOP_TIMEOUT_S + 30)
    if result.returncode != 0 and postmaster_info(folder) is not None:
        raise StoreError(_command_error("pg_ctl stop", result))


def _provision(folder: Path, port: int, password: str, reader_password: str) -> None:
    """Make (or repair) the roles and their database, as the superuser on the Unix socket.
    Run at every start, so that a start interrupted after initdb is completed by the next
    one, and a new DIR/password or DIR/read-password takes effect."""
    import psycopg
    from psycopg import sql

    with psycopg.connect(host=str(folder), port=port, user=_owner(), dbname="postgres",
                         autocommit=True, connect_timeout=30) as conn:
        role = sql.Identifier(ROLE)
        for name, secret in ((ROLE, password), (READ_ROLE, reader_password)):
            if conn.execute("SELECT 1 FROM pg_roles WHERE rolname = %s",
                            (name,)).fetchone() is None:
                conn.execute(sql.SQL("CREATE ROLE {} LOGIN").format(sql.Identifier(name)))
            # the SCRAM verifier, made by libpq: the password itself never reaches the
            # server (nor its log, should a statement fail)
            verifier = conn.pgconn.encrypt_password(secret.encode(), name.encode(),
                                                    b"scram-sha-256").decode()
            conn.execute(sql.SQL("ALTER ROLE {} WITH LOGIN NOSUPERUSER NOCREATEDB "
                                 "NOCREATEROLE NOREPLICATION PASSWORD {}").format(
                sql.Identifier(name), sql.Literal(verifier)))
        if conn.execute("SELECT 1 FROM pg_database WHERE datname = %s",
                        (DATABASE,)).fetchone() is None:
            conn.execute(sql.SQL("CREATE DATABASE {} OWNER {}").format(
                sql.Identifier(DATABASE), role))
    with psycopg.connect(host=str(folder), port=port, user=_owner(), dbname=DATABASE,
                         autocommit=True, connect_timeout=30) as conn:
        for statement in reader_grants(ROLE, READ_ROLE, DATABASE):
            conn.execute(statement)


def reader_grants(owner: str, reader: str, database: str) -> list[str]:
    """The statements, for a superuser connected to ``database``, that make ``reader`` a
    role that only reads the tables that ``owner`` (the workers' role) makes, and keep the
    advisory locks to ``owner``. Idempotent. docs/store.md prints them for other servers.
    (``reader`` must not be a member of ``owner``: that is CREATE ROLE's default.)"""
    o, r, d = (f'"{name}"' for name in (owner, reader, database))
    owner_literal = "'" + owner.replace("'", "''") + "'"
    # no % in the text: a client that takes parameters (SQLAlchemy, psql -v) reads it whole
    advisory = ("SELECT p.oid::regprocedure FROM pg_proc p JOIN pg_namespace n "
                "ON n.oid = p.pronamespace WHERE n.nspname = 'pg_catalog' "
                "AND p.proname ~ '^pg_(try_)?advisory_'")
    return [
        f"GRANT CONNECT ON DATABASE {d} TO {r}",
        # PostgreSQL < 15 lets PUBLIC create in the schema public: only the owner may
        "REVOKE CREATE ON SCHEMA public FROM PUBLIC",
        f"GRANT USAGE, CREATE ON SCHEMA public TO {o}",
        f"GRANT USAGE ON SCHEMA public TO {r}",
        f"GRANT SELECT ON ALL TABLES IN SCHEMA public TO {r}",
        f"ALTER DEFAULT PRIVILEGES FOR ROLE {o} IN SCHEMA public GRANT SELECT ON TABLES TO {r}",
        # every pg_advisory_* and pg_try_advisory_*: revoked from PUBLIC, for the owner only
        "DO $$DECLARE f regprocedure; BEGIN FOR f IN " + advisory + " LOOP "
        "EXECUTE 'REVOKE EXECUTE ON FUNCTION ' || f || ' FROM PUBLIC'; "
        f"EXECUTE 'GRANT EXECUTE ON FUNCTION ' || f || ' TO ' || quote_ident({owner_literal}); "
        "END LOOP; END$$",
    ]


def local_url(folder: Path, port: int, password: str) -> str:
    """The URL of the database on the Unix socket in DIR (this machine, this user)."""
    from sqlalchemy.engine import URL

    return URL.create("postgresql+psycopg", username=ROLE, password=password,
                      database=DATABASE, query={"host": str(folder), "port": str(port)}
                      ).render_as_string(hide_password=False)


def tcp_url(host: str, port: int, password: str, role: str = ROLE) -> str:
    """postgresql+psycopg://slopetui:PASSWORD@HOST:PORT/slopetui (an IPv6 address in [];
    ``role``: READ_ROLE for the reading role's URL)."""
    shown = f"[{host}]" if ":" in host else host
    return f"postgresql+psycopg://{role}:{password}@{shown}:{port}/{DATABASE}"


def _loopback_only(host: str) -> bool:
    """Does ``host`` resolve, here, to loopback addresses only (or not at all)?"""
    try:
        infos = socket.getaddrinfo(host, None, type=socket.SOCK_STREAM)
    except socket.gaierror:
        return True
    return all(ipaddress.ip_address(str(info[4][0]).split("%")[0]).is_loopback
               for info in infos)


def worker_host(listen: str) -> tuple[str, str | None]:
    """The name by which workers on other nodes reach this machine, and a warning when it
    may not work. A --listen of one address gives that address; else the fully
    qualified name (socket.getfqdn()), or the host name where that is only "localhost"."""
    specific = [h for h in _listen_hosts(listen) if h is not None]
    if specific and len(specific) == len(_listen_hosts(listen)):
        named = [h for h in specific if not _loopback_only(h)]
        if named:
            return named[0], None
        return specific[0], (f"--listen {listen} is this machine's loopback only: workers on "
                             "other machines cannot reach the server")
    host = socket.getfqdn()
    if host.startswith("localhost") or host in ("", "ip6-localhost"):
        host = socket.gethostname()
    if _loopback_only(host):
        return host, (f"{host} resolves to a loopback address on this machine: if the "
                      "workers cannot reach it by that name, put this machine's address "
                      "on their network in the URL (`hostname -I` lists them)")
    return host, None


def _serves_loopback(listen: str) -> bool:
    return any(h in (None, "localhost", "127.0.0.1") for h in _listen_hosts(listen))


@dataclass
class Server:
    """A server of DIR started by ``start()``: stop it with ``stop()``, which also lets go
    of DIR's lock."""

    folder: Path
    binaries: Binaries
    port: int
    listen: str
    max_connections: int
    pid: int  # the postmaster's
    created: bool  # initdb ran now
    password: str = field(repr=False)
    worker_url: str = field(repr=False)  # postgresql+psycopg://slopetui:...@HOST:PORT/slopetui
    this_machine_url: str = field(repr=False)  # 127.0.0.1, or the socket if not listened on
    host_note: str | None  # why worker_url's host may not reach this machine
    timings: dict[str, float]  # "initdb" (a new cluster only), "start", "setup" (s)
    log_offset: int  # bytes of DIR/server.log before this start
    lock_fd: int | None = field(default=None, repr=False)

    @property
    def log(self) -> Path:
        return self.folder / "server.log"

    def running(self) -> bool:
        info = postmaster_info(self.folder)
        return info is not None and info.pid == self.pid

    def wait(self, wake_fd: int) -> bool:
        """Block until ``wake_fd`` is readable (a signal's byte: returns False) or the
        server has exited on its own (True). On Linux a pidfd wakes it at once; elsewhere
        the server is checked every POLL_S seconds."""
        pidfd: int | None = None
        with contextlib.suppress(AttributeError, OSError):
            pidfd = os.pidfd_open(self.pid)
        try:
            while True:
                watched = [wake_fd] if pidfd is None else [wake_fd, pidfd]
                ready, _, _ = select.select(watched, [], [], POLL_S)
                if wake_fd in ready:
                    return False
                if not self.running():
                    return True
        finally:
            if pidfd is not None:
                os.close(pidfd)

    def stop(self) -> None:
        """pg_ctl stop -m fast, then let go of DIR (its lock and serve.pid). Idempotent."""
        try:
            if postmaster_info(self.folder) is not None:
                pg_ctl_stop(self.folder, self.binaries)
        finally:
            self.release()

    def release(self) -> None:
        if self.lock_fd is not None:
            (self.folder / "serve.pid").unlink(missing_ok=True)
            os.close(self.lock_fd)  # closing the descriptor drops the flock
            self.lock_fd = None


@contextlib.contextmanager
def _claimed(folder: Path) -> Iterator[int]:
    """DIR made (mode 700) if it is new, and locked for this process: the lock's
    descriptor, which stays open (locked) after the block. On an error, DIR is left as it
    was found:
    removed if it was made now, else without the files made now (a cluster made whole
    stays: a retry uses it)."""
    made = not folder.exists()
    if made:
        folder.mkdir(mode=0o700, parents=True)
    else:
        os.chmod(folder, 0o700)  # the socket is in it: keep other users out
    before = set(os.listdir(folder))
    try:
        fd = _try_lock(folder)
    except OSError as exc:
        if made:
            shutil.rmtree(folder, ignore_errors=True)
        raise StoreError(f"--dir: cannot lock {folder / 'serve.lock'}: {exc.strerror}") from None
    if fd is None:
        pid = _serve_pid(folder)
        raise StoreError(f"--dir: another `slopetui db serve`{f' (pid {pid})' if pid else ''} "
                         f"runs the server of {folder}: `slopetui db serve --url` prints its "
                         "URL, `--stop` stops it")
    try:
        _write_private(folder / "serve.pid", f"{os.getpid()}\n")
        yield fd
    except BaseException:
        has_cluster = (folder / "data").exists()
        if made and not has_cluster:
            shutil.rmtree(folder, ignore_errors=True)
        elif not has_cluster:
            for name in set(os.listdir(folder)) - before:
                with contextlib.suppress(OSError):
                    os.unlink(folder / name)
        with contextlib.suppress(OSError):
            (folder / "serve.pid").unlink(missing_ok=True)
        os.close(fd)
        raise


def start(folder: Path, settings: Settings, binaries: Binaries, *,
          make_parents: bool = False) -> Server:
    """Start the server of DIR ``folder``: make the cluster the first time (initdb), write
    the settings, start it, make the role and database ``slopetui``, and migrate that to
    the current schema. Returns the running server, with DIR locked for this process
    until ``Server.stop()``.

    make_parents : create DIR's missing parents (the default DIR); an explicit --dir
                   needs its parent to exist.
    """
    check_not_root()
    check_driver()
    folder = folder.expanduser().absolute()
    check_folder(folder, make_parents=make_parents)
    major = _cluster_major(folder)
    if major is not None and major != binaries.major:
        raise StoreError(f"--dir: the cluster in {folder / 'data'} was made by PostgreSQL "
                         f"{major}, and these programs are {binaries.version} "
                         f"({binaries.folder}): --pg-bin the {major} ones, or upgrade the "
                         "cluster with pg_upgrade")
    if _owner() == ROLE:
        raise StoreError(f"run `slopetui db serve` as a user not named {ROLE}: the workers' "
                         "role has that name, and it must not be the superuser")
    _refuse_elsewhere(folder)
    port, listen, max_connections = resolve_settings(folder, settings)
    if postmaster_info(folder) is None:  # else the checks below say who runs it
        check_port(port, listen)
    timings: dict[str, float] = {}
    with _claimed(folder) as lock_fd:
        # DIR is ours now: a server that runs is not another serve's
        running = postmaster_info(folder)
        if running is not None:
            raise StoreError(f"--dir: a server already runs on {folder} (pid {running.pid}, "
                             f"port {running.port}), started by hand or by a `slopetui db "
                             "serve` that was killed: `slopetui db serve --stop` stops it")
        created = not (folder / "data").exists()
        if created:
            t0 = time.monotonic()
            _initdb(folder, binaries)
            timings["initdb"] = time.monotonic() - t0
        password = _password(folder)
        reader_password = _password(folder, "read-password")
        # rewritten at each start: a cluster made before the reading role gets its lines
        _write_private(folder / "data" / "pg_hba.conf", _pg_hba(_owner()))
        _write_private(folder / "data" / "slopetui.conf",
                       _settings_conf(folder, port, listen, max_connections))
        log = folder / "server.log"
        log_offset = log.stat().st_size if log.exists() else 0
        _write_private(folder / "server.host", socket.gethostname() + "\n")
        t0 = time.monotonic()
        info = _pg_ctl_start(folder, binaries, log_offset)
        timings["start"] = time.monotonic() - t0
        try:
            t0 = time.monotonic()
            _provision(folder, port, password, reader_password)
            # here: `slopetui db --help` reads this module's defaults, and the store
            # imports SQLAlchemy (slopetui.cli.arguments.db)
            from slopetui.store.open import open_store
            open_store(local_url(folder, port, password)).dispose()  # migrates
            timings["setup"] = time.monotonic() - t0
            host, note = worker_host(listen)
            worker_url = tcp_url(host, port, password)
            _write_private(folder / "url", worker_url + "\n")
            _write_private(folder / "read-url",
                           tcp_url(host, port, reader_password, READ_ROLE) + "\n")
        except BaseException:
            with contextlib.suppress(StoreError):
                pg_ctl_stop(folder, binaries)
            raise
    here = (tcp_url("127.0.0.1", port, password) if _serves_loopback(listen)
            else local_url(folder, port, password))
    return Server(folder, binaries, port, listen, max_connections, info.pid, created,
                  password, worker_url, here, note, timings, log_offset, lock_fd)


# --- the other actions: status, URL, stop ----------------------------------------------


@dataclass(frozen=True)
class Status:
    """What runs in DIR."""

    folder: Path
    initialised: bool  # DIR/data holds a cluster
    server: PostmasterInfo | None  # the running server, None if none (on this machine)
    serve_pid: int | None  # the `slopetui db serve` process that runs it, if any
    elsewhere: str | None  # another machine it may run on (see elsewhere())


def status(folder: Path) -> Status:
    """The state of DIR, read from its files (no PostgreSQL program needed)."""
    folder = folder.expanduser().absolute()
    serve_pid = None
    if (folder / "serve.lock").exists():
        fd = _try_lock(folder)
        if fd is None:
            serve_pid = _serve_pid(folder)
        else:
            os.close(fd)
    return Status(folder, (folder / "data" / "PG_VERSION").exists(), postmaster_info(folder),
                  serve_pid, elsewhere(folder))


def stored_url(folder: Path) -> str:
    """The URL for the workers that the last start wrote in DIR/url."""
    folder = folder.expanduser().absolute()
    try:
        return (folder / "url").read_text().strip()
    except FileNotFoundError:
        raise StoreError(f"--dir: {folder} holds no server URL yet: start the server first "
                         "(`slopetui db serve`)") from None


def stop_folder(folder: Path, pg_bin: Path | None = None) -> str:
    """Stop the server of DIR: ask the `slopetui db serve` that runs it to stop (SIGTERM)
    and wait until it has let go of DIR, or, if none does (it was killed), stop the server
    with pg_ctl. Returns what was done, in words: "serve", "server" or "none"."""
    folder = folder.expanduser().absolute()
    if not (folder / "data" / "PG_VERSION").exists():
        raise StoreError(f"--dir: {folder} holds no slopetui server")
    _refuse_elsewhere(folder)
    fd = _try_lock(folder)
    if fd is None:
        pid = _serve_pid(folder)
        if pid is None:
            raise StoreError(f"--dir: the `slopetui db serve` of {folder} wrote no pid")
        with contextlib.suppress(ProcessLookupError):  # it is exiting already
            os.kill(pid, signal.SIGTERM)
        deadline = time.monotonic() + STOP_TIMEOUT_S + 30
        while (fd := _try_lock(folder)) is None:
            if time.monotonic() > deadline:
                raise StoreError(f"`slopetui db serve` (pid {pid}) did not stop within "
                                 f"{STOP_TIMEOUT_S + 30} s")
            time.sleep(0.1)
        os.close(fd)
        return "serve"
    try:
        if postmaster_info(folder) is None:
            return "none"
        pg_ctl_stop(folder, find_binaries(pg_bin))
        return "server"
    finally:
        os.close(fd)
