"""The sbatch script of ``slopetui cluster slurm``: a Slurm job array of worker pools.

Each array task is one node's pool (``slopetui worker -j N --exit-when-idle``) on a server
database that every node reaches; the tasks end when nothing is left to compute. This
module only builds text: ``SlurmWorkers`` holds the checked settings, ``sbatch_script``
turns them into the script, and the parsers below turn the command line's words into
settings, raising ``SlurmScriptError`` with one line that names the option and what it
allows (``slopetui cluster slurm`` is the one face that builds these scripts). No I/O, and
nothing heavy at import: ``slopetui --help`` builds the parser that reads the constants.

How the pools stop (see slopetui.queue.pool): a first SIGTERM to a pool lets its workers
finish the runs they are computing, a second one gives those runs back to the queue at
once, their attempt not counted. The script replaces its batch shell with the pool
(``exec``) and asks Slurm (``--signal=B:TERM@120``) for the first SIGTERM
SIGNAL_MARGIN_S before the time limit; Slurm's own SIGTERM at the limit is the second.

The database's URL, password included, is in the script (written 0600) and reaches the
pool in the environment ($SLOPETUI_DB), never on a command line, which every user of a
node can read (``ps``).
"""

from __future__ import annotations

import ipaddress
import os
import re
import shlex
from dataclasses import dataclass

from slopetui import __version__
from slopetui.store.url_text import holds_password, password_hidden

#: As ``slopetui worker -j``: more processes than this on a node is a typo, not a machine.
MAX_WORKERS_PER_NODE = 512
#: Array tasks (nodes). Slurm's own MaxArraySize (1001 by default) may allow fewer.
MAX_NODES = 10_000
#: The first SIGTERM (finish the runs in progress) comes this long before the time limit
#: (s). A run still in its kernel at the limit is given back, and a later task computes
#: it again from the start.
SIGNAL_MARGIN_S = 120
#: Slurm checks the limits about every 30 s and may send the signal up to 60 s early
#: (sbatch(1), --signal) (s).
SIGNAL_EARLY_S = 60
#: The shortest time limit (s): even when the signal comes at its earliest
#: (SIGNAL_MARGIN_S + SIGNAL_EARLY_S before the limit), a pool has two minutes after its
#: start.
MIN_TIME_S = 300
#: The longest time limit (s): 365 days; beyond that it is a typo.
MAX_TIME_S = 365 * 86_400
#: The Slurm job name: ``squeue -n slopetui-workers`` finds the pools.
JOB_NAME = "slopetui-workers"
#: The script's default file name, in the current folder.
DEFAULT_SCRIPT = "slopetui-workers.sbatch"
#: One log per pool (array task), in the folder sbatch runs in; ``%A`` (the array's job id)
#: and ``%a`` (the task) are Slurm's, and the script spells the same name out for --log.
LOG_PATTERN = "slopetui-worker-%A_%a.log"
#: Slurm's time limit formats, for the messages.
TIME_FORMS = "MM, MM:SS, HH:MM:SS, D-HH, D-HH:MM or D-HH:MM:SS"

# ASCII digits only: \d also matches other scripts' digits, which Slurm does not read.
_TIME = re.compile(r"(?:(?P<days>[0-9]{1,6})-(?P<dh>[0-9]{1,2})(?::(?P<dm>[0-9]{1,2})"
                   r"(?::(?P<ds>[0-9]{1,2}))?)?"
                   r"|(?P<a>[0-9]{1,9})(?::(?P<b>[0-9]{1,2})(?::(?P<c>[0-9]{1,2}))?)?)")
# A partition, or a comma-separated list (the job runs in the first that can start it):
# written into an #SBATCH line, so nothing a shell or Slurm would read as more.
_PARTITION = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.-]{0,63}(?:,[A-Za-z0-9_][A-Za-z0-9_.-]{0,63})*")
_LOCAL_NAMES = {"localhost", "localhost.localdomain", "ip6-localhost", "ip6-loopback"}


class SlurmScriptError(ValueError):
    """A setting the script cannot have: one line naming the option and what it allows."""


def format_time(seconds: int) -> str:
    """A time limit as Slurm writes it: ``HH:MM:SS``, or ``D-HH:MM:SS`` from a day on."""
    days, rest = divmod(seconds, 86_400)
    clock = f"{rest // 3600:02d}:{rest % 3600 // 60:02d}:{rest % 60:02d}"
    return f"{days}-{clock}" if days else clock


def _time_range() -> str:
    return (f"allowed a Slurm time limit ({TIME_FORMS}) from {format_time(MIN_TIME_S)} to "
            f"{format_time(MAX_TIME_S)}: the pools are asked to stop {SIGNAL_MARGIN_S} s "
            f"before it, and Slurm may ask up to {SIGNAL_EARLY_S} s earlier")


def parse_time_limit(text: str) -> int:
    """``--time`` in seconds, from any of Slurm's forms (TIME_FORMS; a lone number is
    minutes, as for sbatch). A field right of a larger unit must be below 60 (hours below
    24); the total must lie from MIN_TIME_S to MAX_TIME_S."""
    m = _TIME.fullmatch(text.strip())
    if m is None:
        raise SlurmScriptError(f"--time = {text!r} is not a time limit: {_time_range()}")
    g = {k: int(v) for k, v in m.groupdict().items() if v is not None}
    if "days" in g:
        fields = [(g["dh"], 24), (g.get("dm", 0), 60), (g.get("ds", 0), 60)]
        seconds = g["days"] * 86_400 + g["dh"] * 3600 + g.get("dm", 0) * 60 + g.get("ds", 0)
    elif "c" in g:  # H:M:S
        fields = [(g["b"], 60), (g["c"], 60)]
        seconds = g["a"] * 3600 + g["b"] * 60 + g["c"]
    else:  # M or M:S
        fields = [(g.get("b", 0), 60)]
        seconds = g["a"] * 60 + g.get("b", 0)
    if any(value >= limit for value, limit in fields):
        raise SlurmScriptError(f"--time = {text!r} is not a time limit (a field is out of "
                               f"its range): {_time_range()}")
    if not MIN_TIME_S <= seconds <= MAX_TIME_S:
        raise SlurmScriptError(f"--time = {text!r} is out of range: {_time_range()}")
    return seconds


def check_partition(text: str) -> str:
    """``--partition``: a name, or names separated by commas, of letters, digits, ``_``,
    ``.`` and ``-`` (up to 64 characters each). It is written into the script, so no
    space, quote, newline or other character that Slurm or a shell would read as more."""
    if _PARTITION.fullmatch(text) is None:
        raise SlurmScriptError(f"--partition = {text!r} is not a partition name: allowed "
                               "letters, digits, _ . - (up to 64 characters, not starting "
                               "with . or -), or such names separated by commas")
    return text


@dataclass(frozen=True)
class ServerDatabase:
    """The database the pools share, as checked by ``server_database``."""

    #: As given, password included: what the script exports.
    url: str
    #: The password hidden, for messages.
    display: str
    has_password: bool
    #: Why only this machine reaches it (e.g. "127.0.0.1 is this machine"), else None.
    local_only: str | None


def _local_only(host: str | None, socket_dir: str | None) -> str | None:
    """Why a server at ``host`` (or the Unix socket folder ``socket_dir``) is reachable
    from this machine only, or None."""
    if socket_dir and socket_dir.startswith("/"):
        return f"the Unix socket in {socket_dir} is on this machine only"
    if not host and not socket_dir:
        return "a URL without a host means a Unix socket of this machine"
    name = host or socket_dir or ""
    if name.lower() in _LOCAL_NAMES:
        return f"{name} is this machine"
    try:
        loopback = ipaddress.ip_address(name.strip("[]")).is_loopback
    except ValueError:  # a host name
        return None
    return f"{name} is this machine" if loopback else None


def server_database(url: str | None) -> ServerDatabase:
    """``--db`` (or $SLOPETUI_DB, given here as ``url``): it must name a database server.
    SQLite (and no URL at all, whose default is a SQLite file) is refused: every node would
    need the same file, and SQLite's locks are not safe on a network file system."""
    where = ("give --db URL of a PostgreSQL server the nodes reach, e.g. "
             "postgresql+psycopg://USER@HOST/DB; `slopetui db serve` starts a PostgreSQL "
             "server of your own and prints its URL")
    if not url:
        raise SlurmScriptError("--db: no database given and $SLOPETUI_DB is not set (the "
                               "default store is a SQLite file, which cannot be shared "
                               f"between nodes): {where}")
    # here, not at the top: the store imports SQLAlchemy, which `slopetui --help` must not
    from slopetui.store.database import parse_url
    parsed = parse_url(url)
    display = password_hidden(parsed.render_as_string(hide_password=True))
    if parsed.get_backend_name() == "sqlite":
        raise SlurmScriptError(f"--db = {display!r} is SQLite, which cannot be shared "
                               "between nodes (its locks are not safe on a network file "
                               f"system): {where}")
    socket_dir = parsed.query.get("host")
    if not isinstance(socket_dir, str):  # several hosts (a tuple): the first decides
        socket_dir = socket_dir[0] if socket_dir else None
    return ServerDatabase(url=url, display=display, has_password=holds_password(url),
                          local_only=_local_only(parsed.host, socket_dir))


def _in_range(option: str, value: int, low: int, high: int, what: str = "") -> None:
    if not low <= value <= high:
        raise SlurmScriptError(f"{option} = {value} is out of range: allowed an integer "
                               f"from {low} to {high}{what}")


@dataclass(frozen=True)
class SlurmWorkers:
    """One job array of worker pools, checked on creation (SlurmScriptError).

    db_url           : a server database URL (``server_database``), password included.
    python           : absolute path of the Python that runs slopetui on the nodes (the
                       one of the virtual environment, not its resolved symlink).
    workers_per_node : worker processes of each pool, and the CPUs it asks for, 1 to
                       MAX_WORKERS_PER_NODE.
    nodes            : array tasks, one pool (one node) each, 1 to MAX_NODES.
    time_s           : time limit of each task (s), MIN_TIME_S to MAX_TIME_S.
    partition        : ``check_partition``; None: the cluster's default partition.
    """

    db_url: str
    python: str
    workers_per_node: int
    nodes: int
    time_s: int
    partition: str | None = None

    def __post_init__(self) -> None:
        _in_range("--workers-per-node", self.workers_per_node, 1, MAX_WORKERS_PER_NODE)
        _in_range("--nodes", self.nodes, 1, MAX_NODES, " (array tasks, one node each)")
        if not MIN_TIME_S <= self.time_s <= MAX_TIME_S:
            raise SlurmScriptError(f"--time = {format_time(self.time_s)} is out of range: "
                                   f"{_time_range()}")
        if self.partition is not None:
            check_partition(self.partition)
        if not os.path.isabs(self.python) or "\0" in self.python:
            raise SlurmScriptError(f"--python = {self.python!r}: allowed an absolute path")
        if not self.db_url or "\0" in self.db_url:
            raise SlurmScriptError("--db: allowed a database URL")
        # the backend, as SQLAlchemy reads it: the scheme before any +driver
        if self.db_url.partition(":")[0].partition("+")[0].lower() == "sqlite":
            raise SlurmScriptError("--db: SQLite cannot be shared between nodes: allowed the "
                                   "URL of a database server (server_database)")


def _directives(job: SlurmWorkers) -> list[str]:
    """The #SBATCH lines, with the comments that say why."""
    lines = [
        f"#SBATCH --job-name={JOB_NAME}",
        f"#SBATCH --array=0-{job.nodes - 1}",
        "#SBATCH --nodes=1",
        "#SBATCH --ntasks=1",
        f"#SBATCH --cpus-per-task={job.workers_per_node}",
        f"#SBATCH --time={format_time(job.time_s)}",
    ]
    if job.partition is not None:
        lines.append(f"#SBATCH --partition={job.partition}")
    lines += [
        "# One file per task (%A: the array's job id, %a: the task) in the folder sbatch runs",
        "# in: Slurm's output and the pool's log (--log below) are the same file, in append",
        "# mode so that both write at its end rather than over each other.",
        f"#SBATCH --output={LOG_PATTERN}",
        "#SBATCH --open-mode=append",
        f"# {SIGNAL_MARGIN_S} s before the time limit (Slurm may send it up to "
        f"{SIGNAL_EARLY_S} s early), SIGTERM to",
        "# the batch shell alone (B:), which is the pool itself (exec below). Without B:",
        "# Slurm signals the job's srun steps, and there are none: nothing would hear it.",
        "# The pool's workers finish the runs they are computing, then exit. At the limit",
        "# Slurm sends SIGTERM to every process of the job, the pool's second: the runs",
        "# still being computed go back to the queue at once (their attempt not counted),",
        "# before the SIGKILL that follows KillWait (30 s by default) later.",
        f"#SBATCH --signal=B:TERM@{SIGNAL_MARGIN_S}",
    ]
    return lines


def _body(job: SlurmWorkers) -> list[str]:
    """The shell lines after the directives."""
    python = shlex.quote(job.python)
    return [
        "set -euo pipefail",
        ': "${SLURM_ARRAY_JOB_ID:?is not set: submit this script with sbatch}"',
        "",
        "# The database of every pool: a server that every node reaches (in the environment,",
        "# where slopetui reads it: never on a command line, see exec below).",
        f"export SLOPETUI_DB={shlex.quote(job.db_url)}",
        "# The Python that wrote this script: with its virtual environment on the shared",
        "# file system, every node runs the same slopetui (the interpreter the environment",
        "# was made from must exist on the nodes too). -P keeps the folder sbatch runs in",
        "# off sys.path, where a checkout of another version would be imported instead.",
        f"PYTHON={python}",
        "",
        "# numba's compiled kernels go in a folder of this node, not in the shared home:",
        "# processes of several nodes compiling into one cache at once can corrupt it. It",
        "# is the folder slopetui falls back to on a node whose home is on a network file",
        "# system (core.jit_cache), and must be ours alone (the workers load the machine",
        "# code in it): in a shared /tmp, a folder another user made, or a symbolic link,",
        "# is refused.",
        'export SLOPETUI_KERNEL_CACHE="${SLURM_TMPDIR:-${TMPDIR:-/tmp}}/slopetui-kernels-$(id -u)"',
        'mkdir -p -m 700 -- "$SLOPETUI_KERNEL_CACHE"',
        'if [ -L "$SLOPETUI_KERNEL_CACHE" ] || [ ! -O "$SLOPETUI_KERNEL_CACHE" ]; then',
        '    echo "slopetui: $SLOPETUI_KERNEL_CACHE is not a folder of yours; not used" >&2',
        "    exit 1",
        "fi",
        'chmod 700 -- "$SLOPETUI_KERNEL_CACHE"',
        "# Compile (or load) the kernels before the pool starts, one task of this node at a",
        "# time: Slurm may place two array tasks on one node, and their pools would",
        "# otherwise compile into the same cache at once. The pool then only loads them.",
        'flock "$SLOPETUI_KERNEL_CACHE/warm-up.lock" \\',
        '    "$PYTHON" -P -c "from slopetui.queue.warm_up import warm_up; warm_up()"',
        "",
        "# exec: the pool replaces this shell, so it is the process --signal=B:TERM reaches.",
        "# --another-pool: two array tasks on one node each have CPUs of their own.",
        "# No --db: the pool reads the database from $SLOPETUI_DB, exported above. A command",
        "# line is readable by every user of the node (ps), an environment by its owner only.",
        f'exec "$PYTHON" -P -m slopetui worker -j {job.workers_per_node} --exit-when-idle '
        "--another-pool \\",
        '    --log "slopetui-worker-${SLURM_ARRAY_JOB_ID}_${SLURM_ARRAY_TASK_ID}.log"',
    ]


def sbatch_script(job: SlurmWorkers, script_name: str = DEFAULT_SCRIPT) -> str:
    """The whole script (``script_name`` only for the comment that says how to submit; a
    name with a control character, which could end the comment, is left out)."""
    submit = shlex.quote(script_name) if script_name.isprintable() else "THIS_FILE"
    header = [
        "#!/bin/bash",
        f"# slopetui worker pools on Slurm, written by `slopetui cluster slurm` (slopetui "
        f"{__version__}).",
        f"# Submit it with:  sbatch {submit}",
        "#",
        f"# A job array of {job.nodes} task{'s' if job.nodes > 1 else ''}, each one node's "
        f"pool of {job.workers_per_node} worker{'s' if job.workers_per_node > 1 else ''}. "
        "The pools compute",
        "# the runs queued in the database below until none is left, then exit.",
        "# This file holds the database's URL, a password too if the URL has one: it is",
        "# written readable by its owner only.",
        "#",
    ]
    return "\n".join(header + _directives(job) + [""] + _body(job)) + "\n"
