"""Typed SQLAlchemy 2.0 models of the store: sweeps, their runs (which are also the jobs of
the queue), continuations of periodic orbits (jobs too) with their branch points and
bifurcations, and the workers that run them. The README documents this schema for SQL users;
every change to it goes through a migration in ``migrations/versions``."""

from __future__ import annotations

from datetime import datetime
from typing import TYPE_CHECKING, Any, ClassVar

from sqlalchemy import (
    JSON,
    Boolean,
    CheckConstraint,
    DateTime,
    Double,
    ForeignKey,
    FromClause,
    Index,
    Integer,
    LargeBinary,
    MetaData,
    String,
    Text,
    func,
)
from sqlalchemy.orm import DeclarativeBase, Mapped, mapped_column, relationship

from slopetui.store.column_types import Measure
from slopetui.store.statuses import RUN_STATUSES, SWEEP_STATUSES

#: Constraint names that batch migrations on SQLite can find again (unnamed CHECK
#: constraints are silently dropped when Alembic rebuilds a table).
NAMING_CONVENTION = {
    "ix": "ix_%(table_name)s_%(column_0_N_name)s",
    "uq": "uq_%(table_name)s_%(column_0_N_name)s",
    "ck": "ck_%(table_name)s_%(constraint_name)s",
    "fk": "fk_%(table_name)s_%(column_0_name)s_%(referred_table_name)s",
    "pk": "pk_%(table_name)s",
}

#: The table option of the tables whose ids the commands take and print: on SQLite, an id
#: is never handed out twice, even after the row holding the largest was deleted (without
#: it SQLite takes max(id) + 1; migration 0009). PostgreSQL's sequences never go back.
IDS_NEVER_REUSED = {"sqlite_autoincrement": True}


def _one_of(column: str, values: tuple[str, ...]) -> str:
    return f"{column} IN ({', '.join(repr(v) for v in values)})"


class Base(DeclarativeBase):
    metadata = MetaData(naming_convention=NAMING_CONVENTION)
    type_annotation_map = {dict[str, Any]: JSON, list[float]: JSON}


class Sweep(Base):
    """A 1-D (bifurcation diagram) or 2-D (phase diagram) sweep over model parameters."""

    __tablename__ = "sweeps"

    id: Mapped[int] = mapped_column(primary_key=True)
    name: Mapped[str] = mapped_column(String(200))
    #: The whole spec as submitted: axes, fixed parameters, solver settings (JSON).
    spec: Mapped[dict[str, Any]]
    x_param: Mapped[str] = mapped_column(String(8))
    y_param: Mapped[str | None] = mapped_column(String(8))
    #: Points of the lattice (of an adaptive sweep: of the final lattice, which computed
    #: and inferred runs fill when it is refined).
    n_runs: Mapped[int]
    status: Mapped[str] = mapped_column(String(16), default="active")
    created_at: Mapped[datetime] = mapped_column(DateTime, server_default=func.now())
    #: An adaptive phase diagram (slopetui.sweeps.adaptive): how many times its coarse
    #: lattice is refined at most, the level queued last, and whether refinement is over
    #: (its inferred runs are written). NULL, NULL, false for a sweep of every point.
    adaptive_levels: Mapped[int | None]
    level: Mapped[int | None]
    #: server defaults '0' as in migration 0002 (why a literal: see there).
    refined: Mapped[bool] = mapped_column(Boolean, default=False, server_default="0")
    #: The user's note on the sweep (``slopetui note``), NULL for none (migration 0014).
    note: Mapped[str | None] = mapped_column(Text)

    runs: Mapped[list[Run]] = relationship(back_populates="sweep", passive_deletes=True)

    __table_args__ = (CheckConstraint(_one_of("status", SWEEP_STATUSES), name="status"),
                      IDS_NEVER_REUSED)


class Run(Base):
    """One parameter point of a sweep: its inputs, its place in the queue and its result.

    Measurements are NaN where undefined (see ``Measure``); t_blowup is NULL when the run
    did not blow up.
    """

    __tablename__ = "runs"

    id: Mapped[int] = mapped_column(primary_key=True)
    sweep_id: Mapped[int] = mapped_column(ForeignKey("sweeps.id", ondelete="CASCADE"))
    #: Position on the sweep's grid: ix along x_param, iy along y_param (0 for 1-D).
    ix: Mapped[int]
    iy: Mapped[int] = mapped_column(default=0)

    # Model parameters (eqs. 6a-6e, 8) and the initial offset delta (eq. 19).
    a: Mapped[float] = mapped_column(Double)
    b: Mapped[float] = mapped_column(Double)
    c: Mapped[float] = mapped_column(Double)
    d: Mapped[float] = mapped_column(Double)
    k: Mapped[float] = mapped_column(Double)
    v: Mapped[float] = mapped_column(Double)
    tau: Mapped[float] = mapped_column(Double)
    delta: Mapped[float] = mapped_column(Double)
    # Solver settings.
    method: Mapped[str] = mapped_column(String(8))
    dt: Mapped[float] = mapped_column(Double)
    t_end: Mapped[float] = mapped_column(Double)
    window: Mapped[float] = mapped_column(Double)
    lyap: Mapped[bool] = mapped_column(Boolean, default=True)
    #: m_x before t = 0 (core.history): constant, consistent, or state:<digest>, a final
    #: state kept in initial_states. Server default as in migration 0006 (rows before it
    #: all started from the constant history).
    history: Mapped[str] = mapped_column(String(24), default="constant",
                                         server_default="constant")
    #: When the run stops (core.solve.STOPS): t_end, or where its attractor is certified.
    #: Server default as in migration 0013 (rows before it all ran to their t_end).
    stop: Mapped[str] = mapped_column(Text, default="t_end", server_default="t_end")
    #: Which of the sweep's initial conditions (spec [[initial]]) the run starts from.
    ic: Mapped[int] = mapped_column(default=0, server_default="0")
    #: Digest of the engine's sources (core/*.py) the run is computed with.
    engine: Mapped[str] = mapped_column(String(16))
    #: Hash of the parameters, solver settings and engine: equal keys, equal results.
    cache_key: Mapped[str] = mapped_column(String(64))

    # The queue.
    status: Mapped[str] = mapped_column(String(16), default="queued")
    worker_id: Mapped[str | None] = mapped_column(String(128))
    attempts: Mapped[int] = mapped_column(default=0)
    created_at: Mapped[datetime] = mapped_column(DateTime, server_default=func.now())
    started_at: Mapped[datetime | None] = mapped_column(DateTime)
    #: Database time of the last heartbeat of the worker holding the run; the lease
    #: expires when it is older than the lease length.
    heartbeat_at: Mapped[datetime | None] = mapped_column(DateTime)
    finished_at: Mapped[datetime | None] = mapped_column(DateTime)
    error: Mapped[str | None] = mapped_column(Text)
    #: The finished run whose result this one copied (the cache), if any.
    cached_from: Mapped[int | None] = mapped_column(ForeignKey("runs.id", ondelete="SET NULL"))
    #: Adaptive sweeps: the refinement level at which the run was queued, or for an
    #: inferred run the level of the cell it was inferred from; NULL in other sweeps.
    level: Mapped[int | None]
    #: Not computed: the regime was inferred from the 4 equal corners of its cell of an
    #: adaptive sweep. Its measurements are NULL, and it never serves as a cache hit.
    inferred: Mapped[bool] = mapped_column(Boolean, default=False, server_default="0")

    # The result (core.point.PointResult.as_record).
    regime: Mapped[str | None] = mapped_column(String(16))
    #: Why the classifier chose the regime; where a run at an unstable rest state is
    #: headed, or why that is not known (core.heading), can take ~200 characters.
    detail: Mapped[str | None] = mapped_column(Text)
    lambda_max: Mapped[float | None] = mapped_column(Measure)
    lambda_err: Mapped[float | None] = mapped_column(Measure)
    amplitude: Mapped[float | None] = mapped_column(Measure)
    period: Mapped[float | None] = mapped_column(Measure)
    period_count: Mapped[int | None] = mapped_column(Integer)
    maxima_per_period: Mapped[int | None] = mapped_column(Integer)
    #: The longest word is unstable-fixed-point, 20 characters (core.result_fields.ATTRACTORS).
    attractor: Mapped[str | None] = mapped_column(String(24))
    settled: Mapped[bool | None] = mapped_column(Boolean)
    #: Comma-separated words (core.result_fields): query them with LIKE '%uphill%'.
    flags: Mapped[str | None] = mapped_column(String(160))
    #: Peak clusters of m_y in the analysis window (JSON list of floats).
    peaks: Mapped[list[float] | None]
    frequency: Mapped[float | None] = mapped_column(Measure)
    drift: Mapped[float | None] = mapped_column(Measure)
    zero_one_k: Mapped[float | None] = mapped_column(Measure)
    t_blowup: Mapped[float | None] = mapped_column(Double)
    runtime_s: Mapped[float | None] = mapped_column(Double)
    #: When the run stopped (migration 0013 backfilled the runs done before it).
    t_stop: Mapped[float | None] = mapped_column(Measure)
    #: Migration 0012: NULL for runs computed before it, which were never tried.
    certified: Mapped[bool | None] = mapped_column(Boolean)
    certificate: Mapped[str | None] = mapped_column(Text)
    #: The certified orbit's Floquet multipliers, a JSON list of [re, im].
    multipliers: Mapped[list[list[float]] | None] = mapped_column(JSON)
    slips: Mapped[int | None] = mapped_column(Integer)
    dt_error: Mapped[float | None] = mapped_column(Measure)
    spectrum: Mapped[list[float] | None]
    spectrum_err: Mapped[list[float] | None]

    sweep: Mapped[Sweep] = relationship(back_populates="runs")

    __table_args__ = (
        CheckConstraint(_one_of("status", RUN_STATUSES), name="status"),
        CheckConstraint("attempts >= 0", name="attempts"),
        # The claim: the oldest queued run (of an active sweep).
        Index(None, "status", "id"),
        # A batch's claim: the oldest queued runs of one tau (store.runs.claims.claim_batch). On
        # (status, id) alone it read the whole queue whenever a tau had fewer queued runs
        # than the batch (6 ms a claim at 10,000 queued runs; migration 0008).
        Index(None, "status", "tau", "id"),
        # Progress per sweep, and "the runs of sweep N with regime R".
        Index(None, "sweep_id", "status"),
        Index(None, "sweep_id", "regime"),
        Index(None, "cache_key", "status"),
        # "The sliding/oscillatory boundary per tau" across sweeps.
        Index(None, "regime", "tau"),
        IDS_NEVER_REUSED,
    )


class Worker(Base):
    """A worker process of a pool: who is alive, and what each one runs."""

    __tablename__ = "workers"

    id: Mapped[str] = mapped_column(String(128), primary_key=True)
    host: Mapped[str] = mapped_column(String(255))
    pid: Mapped[int]
    started_at: Mapped[datetime] = mapped_column(DateTime, server_default=func.now())
    heartbeat_at: Mapped[datetime] = mapped_column(DateTime, server_default=func.now())
    stopped_at: Mapped[datetime | None] = mapped_column(DateTime)
    run_id: Mapped[int | None] = mapped_column(ForeignKey("runs.id", ondelete="SET NULL"))
    jobs_done: Mapped[int] = mapped_column(default=0)


class LeasedJob:
    """The queue columns of a job computed point by point under a lease (continuations,
    hysteresis sweeps): the runs' columns of the same names, documented there. Only the
    columns: ``Run`` keeps its own, column by column, as the queue's hot path.

    SQLAlchemy places a mixin's columns after the class's own, while the migrations'
    tables have them before the results: harmless, as rows are read by column name and
    autogenerate does not compare column order."""

    status: Mapped[str] = mapped_column(String(16), default="queued")
    worker_id: Mapped[str | None] = mapped_column(String(128))
    attempts: Mapped[int] = mapped_column(default=0)
    created_at: Mapped[datetime] = mapped_column(DateTime, server_default=func.now())
    started_at: Mapped[datetime | None] = mapped_column(DateTime)
    heartbeat_at: Mapped[datetime | None] = mapped_column(DateTime)
    finished_at: Mapped[datetime | None] = mapped_column(DateTime)
    error: Mapped[str | None] = mapped_column(Text)

    if TYPE_CHECKING:
        # Defined by each job class itself (the id first, the compute time among its
        # results), and used by the lease statements (slopetui.store.jobs.leases, point_jobs).
        __table__: ClassVar[FromClause]
        id: Mapped[int]
        runtime_s: Mapped[float]

    @staticmethod
    def queue_args(*more: Any) -> tuple[Any, ...]:
        """A job table's ``__table_args__``: the status check and the claim's index
        ("the oldest queued"), then ``more``, and ids never reused (a job's id is what the
        commands take). New objects each call: a constraint belongs to one table, and the
        naming convention names it after that table."""
        return (CheckConstraint(_one_of("status", RUN_STATUSES), name="status"),
                Index(None, "status", "id"), *more, dict(IDS_NEVER_REUSED))


class Continuation(LeasedJob, Base):
    """A continuation of periodic orbits in one parameter (core.branch_start.BranchSpec):
    a job of the queue like a run, whose branch points are saved as they are computed, so
    that a worker taking it over resumes from the last one."""

    __tablename__ = "continuations"

    id: Mapped[int] = mapped_column(primary_key=True)
    #: The parameter continued in, and where the branch starts: "hopf" (the Hopf point of
    #: the steady state in ``param``) or "orbit" (the orbit a simulation settles on).
    param: Mapped[str] = mapped_column(String(8))
    start: Mapped[str] = mapped_column(String(8))
    #: Of a "hopf" start, which Hopf point: the n-th root pair's crossing (1 the first;
    #: core.stability's omega_n); NULL for an "orbit" start.
    hopf_branch: Mapped[int | None]
    # The starting point's parameters (eqs. 6a-6e, 8; delta places the seed of "orbit").
    a: Mapped[float] = mapped_column(Double)
    b: Mapped[float] = mapped_column(Double)
    c: Mapped[float] = mapped_column(Double)
    d: Mapped[float] = mapped_column(Double)
    k: Mapped[float] = mapped_column(Double)
    v: Mapped[float] = mapped_column(Double)
    tau: Mapped[float] = mapped_column(Double)
    delta: Mapped[float] = mapped_column(Double)
    #: The stored run whose parameters it started from, if any.
    from_run: Mapped[int | None] = mapped_column(ForeignKey("runs.id", ondelete="SET NULL"))
    # What was asked: grid step, end value (NULL: none), point budget, largest step.
    dt: Mapped[float] = mapped_column(Double)
    end_value: Mapped[float | None] = mapped_column(Double)
    max_points: Mapped[int]
    max_step: Mapped[float] = mapped_column(Double)
    engine: Mapped[str] = mapped_column(String(16))

    # The queue: status, worker_id, attempts and the times from LeasedJob.

    # The result: the Hopf point (of a "hopf" start), criticality, why the branch ended,
    # points saved so far, compute time over every attempt (s).
    hopf_value: Mapped[float | None] = mapped_column(Double)
    hopf_period: Mapped[float | None] = mapped_column(Double)
    criticality: Mapped[str | None] = mapped_column(String(16))
    #: The first Lyapunov coefficient at the Hopf point (core.lyapunov_coefficient), whose
    #: sign the criticality is; NULL for an orbit start, and for a branch stored before
    #: migration 0016 (whose criticality was read from its first orbits).
    l1: Mapped[float | None] = mapped_column(Double)
    end_reason: Mapped[str | None] = mapped_column(Text)
    n_points: Mapped[int] = mapped_column(default=0, server_default="0")
    runtime_s: Mapped[float] = mapped_column(Double, default=0.0, server_default="0")

    __table_args__ = LeasedJob.queue_args(
        CheckConstraint(_one_of("start", ("hopf", "orbit")), name="start"))


class BranchPoint(Base):
    """One periodic orbit of a continuation: parameter value, period, amplitude (peak to
    peak of m_y), stability and multipliers, and the state it is resumed from."""

    __tablename__ = "branch_points"

    continuation_id: Mapped[int] = mapped_column(
        ForeignKey("continuations.id", ondelete="CASCADE"), primary_key=True)
    idx: Mapped[int] = mapped_column(primary_key=True)
    value: Mapped[float] = mapped_column(Double)
    period: Mapped[float] = mapped_column(Double)
    amplitude: Mapped[float] = mapped_column(Double)
    stable: Mapped[bool] = mapped_column(Boolean)
    #: Nontrivial multipliers outside the unit circle.
    unstable_count: Mapped[int]
    #: The largest nontrivial multiplier (the one that crosses first).
    leading_re: Mapped[float] = mapped_column(Double)
    leading_im: Mapped[float] = mapped_column(Double)
    #: The leading multipliers by modulus as [re, im] pairs, which one is the flow's, and
    #: the translation multiplier (both exactly 1 in theory: the built-in check).
    multipliers: Mapped[list[float]]
    flow_index: Mapped[int]
    translation: Mapped[float] = mapped_column(Double)
    #: The step along the branch tried after this point, and the point's unknowns
    #: y = (z, T, p) followed by its unit secant t, float64 little-endian.
    step: Mapped[float] = mapped_column(Double)
    state: Mapped[bytes] = mapped_column(LargeBinary)


class Bifurcation(Base):
    """A bifurcation located on a finished continuation's branch, in branch order."""

    __tablename__ = "bifurcations"

    continuation_id: Mapped[int] = mapped_column(
        ForeignKey("continuations.id", ondelete="CASCADE"), primary_key=True)
    idx: Mapped[int] = mapped_column(primary_key=True)
    #: fold, period-doubling, torus, branch-point, hopf or undetermined
    #: (core.continuation.Bifurcation).
    type: Mapped[str] = mapped_column(String(16))
    value: Mapped[float] = mapped_column(Double)
    period: Mapped[float] = mapped_column(Double)
    mu_re: Mapped[float] = mapped_column(Double)
    mu_im: Mapped[float] = mapped_column(Double)
    #: What decided a multiplier's crossing (its figures against its uncertainty); NULL for
    #: a fold or a Hopf end, and for a branch stored before migration 0016.
    reason: Mapped[str | None] = mapped_column(Text)


class HysteresisSweep(LeasedJob, Base):
    """A hysteresis (warm-started) sweep along one parameter, up then down
    (core.hysteresis): a job of the queue like a continuation, whose points are saved as
    they are computed, each with the state it hands over, so that a worker taking it over
    resumes from the last one."""

    __tablename__ = "hysteresis_sweeps"

    id: Mapped[int] = mapped_column(primary_key=True)
    #: The parameter followed, its first and last value, and the values from one to the
    #: other, ends included (each branch has n_points points).
    param: Mapped[str] = mapped_column(String(8))
    start: Mapped[float] = mapped_column(Double)
    stop: Mapped[float] = mapped_column(Double)
    n_points: Mapped[int]
    # The base parameters (eqs. 6a-6e, 8; delta places the first point's start, eq. 19).
    a: Mapped[float] = mapped_column(Double)
    b: Mapped[float] = mapped_column(Double)
    c: Mapped[float] = mapped_column(Double)
    d: Mapped[float] = mapped_column(Double)
    k: Mapped[float] = mapped_column(Double)
    v: Mapped[float] = mapped_column(Double)
    tau: Mapped[float] = mapped_column(Double)
    delta: Mapped[float] = mapped_column(Double)
    # RK4 step, time integrated at each point and its analysis window (model time units).
    dt: Mapped[float] = mapped_column(Double)
    t_settle: Mapped[float] = mapped_column(Double)
    window: Mapped[float] = mapped_column(Double)
    #: The relative tolerance each transition is refined to (core.hysteresis.refine).
    tol: Mapped[float] = mapped_column(Double, default=1e-3, server_default="0.001")
    engine: Mapped[str] = mapped_column(String(16))

    # The queue: status, worker_id, attempts and the times from LeasedJob.

    # The result: where each branch changes regime (NULL: it keeps it, or not done yet),
    # refined to tol, with the grid's bracket (the last value on the old attractor, the
    # first on the new; NULL also for a sweep stored before migration 0011, whose onset_up
    # and offset_down are the grid's values), points saved so far, compute time over
    # every attempt (s).
    onset_up: Mapped[float | None] = mapped_column(Double)
    offset_down: Mapped[float | None] = mapped_column(Double)
    onset_up_before: Mapped[float | None] = mapped_column(Double)
    onset_up_after: Mapped[float | None] = mapped_column(Double)
    offset_down_before: Mapped[float | None] = mapped_column(Double)
    offset_down_after: Mapped[float | None] = mapped_column(Double)
    n_done: Mapped[int] = mapped_column(default=0, server_default="0")
    runtime_s: Mapped[float] = mapped_column(Double, default=0.0, server_default="0")

    __table_args__ = LeasedJob.queue_args()


class HysteresisPoint(Base):
    """One point of a hysteresis sweep, in sweep order (the up branch, then the down
    branch): what its window showed and the state it hands over to the next."""

    __tablename__ = "hysteresis_points"

    sweep_id: Mapped[int] = mapped_column(
        ForeignKey("hysteresis_sweeps.id", ondelete="CASCADE"), primary_key=True)
    idx: Mapped[int] = mapped_column(primary_key=True)
    direction: Mapped[str] = mapped_column(String(4))
    value: Mapped[float] = mapped_column(Double)
    regime: Mapped[str] = mapped_column(String(16))
    detail: Mapped[str] = mapped_column(Text)
    #: Peak-to-peak m_y over the window, and the growth rate at rest (1 / time unit); NaN
    #: when undefined (core.hysteresis.WarmPoint), which SQLite stores as NULL: nullable.
    amplitude: Mapped[float | None] = mapped_column(Measure)
    growth: Mapped[float | None] = mapped_column(Measure)
    jumped: Mapped[bool] = mapped_column(Boolean)
    #: The state handed over: 5 x (N + 1) float64, little endian, row-major; NULL for a
    #: point whose run left the finite range (nothing to hand over: the sweep ends there).
    state: Mapped[bytes | None] = mapped_column(LargeBinary)

    __table_args__ = (CheckConstraint(_one_of("direction", ("up", "down")), name="direction"),)


class InitialState(Base):
    """A final state a run's history starts from (core.history.CarriedState), kept under
    its name ("state:" + digest), with the run it came from."""

    __tablename__ = "initial_states"

    name: Mapped[str] = mapped_column(String(24), primary_key=True)
    source_run: Mapped[int | None] = mapped_column(ForeignKey("runs.id", ondelete="SET NULL"))
    tau: Mapped[float] = mapped_column(Double)
    dt: Mapped[float] = mapped_column(Double)
    #: CarriedState.to_bytes(): tau, dt, the five variables, m_x over the last delay.
    state: Mapped[bytes] = mapped_column(LargeBinary)
    created_at: Mapped[datetime] = mapped_column(DateTime, server_default=func.now())


class SweepTag(Base):
    """A tag of a sweep (``slopetui tag``): short words to filter sweeps and their runs by
    (slopetui.sweeps.annotations says what a tag may be)."""

    __tablename__ = "sweep_tags"

    sweep_id: Mapped[int] = mapped_column(ForeignKey("sweeps.id", ondelete="CASCADE"),
                                          primary_key=True)
    tag: Mapped[str] = mapped_column(String(32), primary_key=True)

    #: runs --tag and sweeps by tag look a tag up first
    __table_args__ = (Index("ix_sweep_tags_tag", "tag"),)


class Mark(Base):
    """A run marked (m) for comparison, kept across the application's restarts; ``id``
    orders the marks as they were made."""

    __tablename__ = "marks"

    id: Mapped[int] = mapped_column(primary_key=True)
    run_id: Mapped[int] = mapped_column(ForeignKey("runs.id", ondelete="CASCADE"), unique=True)


class Curve(LeasedJob, Base):
    """A curve in two parameters (core.curve_start.CurveSpec): the fold of cycles or the
    Hopf curve, a job of the queue like a continuation, whose points are saved as they are
    computed, so that a worker taking it over resumes from the last one."""

    __tablename__ = "curves"

    id: Mapped[int] = mapped_column(primary_key=True)
    #: "fold" (the fold of cycles of the branch in ``param``), "hopf" (the Hopf curve),
    #: "pd" (the first period doubling of that branch up to ``branch_end``) or "ns" (its
    #: first torus bifurcation up to ``branch_end``; migration 0017).
    kind: Mapped[str] = mapped_column(String(8))
    #: The parameter of the fold or Hopf point, and the one the curve follows it in.
    param: Mapped[str] = mapped_column(String(8))
    param2: Mapped[str] = mapped_column(String(8))
    # The starting point's parameters (eqs. 6a-6e, 8).
    a: Mapped[float] = mapped_column(Double)
    b: Mapped[float] = mapped_column(Double)
    c: Mapped[float] = mapped_column(Double)
    d: Mapped[float] = mapped_column(Double)
    k: Mapped[float] = mapped_column(Double)
    v: Mapped[float] = mapped_column(Double)
    tau: Mapped[float] = mapped_column(Double)
    delta: Mapped[float] = mapped_column(Double)
    # What was asked: grid step, where param2 ends, point budget, largest step.
    dt: Mapped[float] = mapped_column(Double)
    end_value: Mapped[float] = mapped_column(Double)
    max_points: Mapped[int]
    max_step: Mapped[float] = mapped_column(Double)
    #: Which Hopf point the curve starts from (the n-th root pair's crossing): its Hopf
    #: curve, or the fold of the branch born there.
    hopf_branch: Mapped[int] = mapped_column(default=1, server_default="1")
    #: A "pd" or "ns" curve: where its branch is followed to, looking for the period
    #: doubling or the torus.
    branch_end: Mapped[float | None] = mapped_column(Double)
    engine: Mapped[str] = mapped_column(String(16))

    # The queue: status, worker_id, attempts and the times from LeasedJob.

    # The result: why the curve ended, points saved so far, compute time over every
    # attempt (s).
    end_reason: Mapped[str | None] = mapped_column(Text)
    n_points: Mapped[int] = mapped_column(default=0, server_default="0")
    runtime_s: Mapped[float] = mapped_column(Double, default=0.0, server_default="0")

    __table_args__ = LeasedJob.queue_args(
        CheckConstraint(_one_of("kind", ("fold", "hopf", "pd", "ns")), name="kind"))


class CurvePoint(Base):
    """One point of a curve: both parameters and the period; a fold's amplitude (peak to
    peak of m_y), quadratic coefficient, multipliers, Newton steps and the state it is
    resumed from; a Hopf point's first Lyapunov coefficient (NULL where it does not
    apply)."""

    __tablename__ = "curve_points"

    curve_id: Mapped[int] = mapped_column(ForeignKey("curves.id", ondelete="CASCADE"),
                                          primary_key=True)
    idx: Mapped[int] = mapped_column(primary_key=True)
    first: Mapped[float] = mapped_column(Double)
    second: Mapped[float] = mapped_column(Double)
    period: Mapped[float] = mapped_column(Double)
    amplitude: Mapped[float | None] = mapped_column(Double)
    l1: Mapped[float | None] = mapped_column(Double)
    curvature: Mapped[float | None] = mapped_column(Double)
    #: The leading multipliers as [re, im] pairs, which one is the flow's, and the
    #: translation multiplier (core.floquet.Multipliers).
    multipliers: Mapped[list[float] | None]
    flow_index: Mapped[int | None]
    translation: Mapped[float | None] = mapped_column(Double)
    newton_steps: Mapped[int | None]
    #: The step along the curve tried after this point, and the resume state
    #: (core.curve_start.SavedCurvePoint), float64 little-endian.
    step: Mapped[float | None] = mapped_column(Double)
    state: Mapped[bytes | None] = mapped_column(LargeBinary)


class CurveBifurcation(Base):
    """A codimension-two point on a finished curve, in curve order (core.codim2)."""

    __tablename__ = "curve_bifurcations"

    curve_id: Mapped[int] = mapped_column(ForeignKey("curves.id", ondelete="CASCADE"),
                                          primary_key=True)
    idx: Mapped[int] = mapped_column(primary_key=True)
    #: cusp, bautin, fold-flip, fold-ns or resonance-1:1.
    type: Mapped[str] = mapped_column(String(16))
    first: Mapped[float] = mapped_column(Double)
    second: Mapped[float] = mapped_column(Double)
    period: Mapped[float] = mapped_column(Double)
    note: Mapped[str] = mapped_column(Text)
