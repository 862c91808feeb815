"""The result of one run, field by field: the one definition of a run's result schema.

``RESULT_FIELDS`` lists, in order, what ``core.point.PointResult.as_record`` computes
and the store keeps in the result columns of ``runs`` (``slopetui.store.models.Run``).
Everything else is derived from it: the cache's copy of a result
(``slopetui.queue.cache.RESULT_FIELDS``), the CSV columns of ``runs --csv`` and
``export --csv`` (``slopetui.sweeps.export``), the keys of ``slopetui run --json``
(``slopetui.cli.run``) and the result lines of the TUI's run detail screen.
``tests/unit/test_result_schema.py`` checks that the ORM columns, the migrated table, the
exporters and the engine agree with it.

**Adding a field:** add a ``ResultField`` here, compute its value in
``PointResult.as_record`` (core/point.py), and add the column with a migration in
``migrations/versions`` (and its ``Mapped`` declaration in ``Run``). The exporters, the
cache and the detail view follow from this table.

This module is light on purpose (no numpy, no numba): the CLI reads it while it builds
its parsers.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

#: How a value is stored and shown:
#: ``text``      a string (NULL before the run is done);
#: ``measure``   a float measurement, NaN where undefined (``store.column_types.Measure``);
#: ``count``     an integer;
#: ``list``      a list of floats (a JSON column);
#: ``optional``  a float that may not exist (None, SQL NULL: e.g. no blow-up);
#: ``flag``      a boolean;
#: ``pairs``     a list of [re, im] pairs (a JSON column): complex numbers.
Kind = Literal["text", "measure", "count", "list", "optional", "flag", "pairs"]


@dataclass(frozen=True, slots=True)
class ResultField:
    """One field of a run's result.

    ``contract``: one of the documented keys of ``slopetui run --json``, which come first
    and in table order. ``detail``: shown on the run detail screen's result lines, under
    ``label`` (the name when empty).
    """

    name: str
    kind: Kind
    unit: str
    description: str
    contract: bool = False
    detail: bool = False
    label: str = ""

    @property
    def shown_as(self) -> str:
        return self.label or self.name


#: The attractor words a run can carry (core.classify); the store's column holds the
#: longest (slopetui.store.models.Run.attractor). ``torus`` and ``chaotic`` only with the
#: exponents' evidence; ``undetermined``: maxima that never return without it (the reason
#: in the run's detail).
ATTRACTORS: tuple[str, ...] = ("fixed-point", "unstable-fixed-point", "fast-branch",
                               "variance-state", "periodic", "torus", "chaotic", "divergent",
                               "unsettled", "undetermined")
#: The flags a run can carry (core.point, core.classify, core.closure); the store's
#: column holds them all at once. ``unrealisable``: some step of the run, not only a
#: sample, left the possible covariances (core.closure.Realisability; the detail says when).
#: ``dt-sensitive``: the run's amplitude, period or label would change by more than 1 % at
#: half its step (core.accuracy; dt_error says by how much).
FLAGS: tuple[str, ...] = ("stiff-fallback", "closure-breakdown", "unrealisable", "uphill",
                          "linear-transient", "not-departed", "slow-modulation",
                          "decaying-alternation", "decaying", "dt-sensitive")

RESULT_FIELDS: tuple[ResultField, ...] = (
    ResultField("regime", "text", "", "the regime of the analysis window (core.regimes); "
                "at an unstable rest state, where the run is headed", contract=True, detail=True),
    ResultField("detail", "text", "", "why the classifier chose the regime (and, at an "
                "unstable rest state, where the run is headed or why that is not known)"),
    ResultField("lambda_max", "measure", "1/time", "the largest Lyapunov exponent",
                contract=True, detail=True, label="λmax"),
    ResultField("lambda_err", "measure", "1/time", "the standard error of lambda_max",
                contract=True),
    ResultField("amplitude", "measure", "m_y", "peak-to-peak of m_y in the window",
                contract=True, detail=True),
    ResultField("period", "measure", "time", "the return time of the orbit in state space "
                "(core.returns), NaN if it has none", contract=True, detail=True),
    ResultField("period_count", "count", "", "the return time in basic periods (the Hopf "
                "period 2 pi / omega_H): 0 at rest, n for period-n, -1 for a continuum"),
    ResultField("maxima_per_period", "count", "", "maxima of m_y in one return", detail=True,
                label="maxima"),
    ResultField("attractor", "text", "", f"{', '.join(ATTRACTORS[:-1])} or {ATTRACTORS[-1]} "
                "(core.classify)", detail=True),
    ResultField("settled", "flag", "", "the pattern was already there in the middle of the "
                "run (false: a slow transient or modulation)", detail=True),
    ResultField("flags", "text", "", f"comma-separated: {', '.join(FLAGS)}", detail=True),
    ResultField("peaks", "list", "m_y", "the maxima of m_y in one return (a continuum: "
                "sampled), in the window", contract=True, detail=True),
    ResultField("frequency", "measure", "1/time", "the dominant frequency of m_y (cycles per time)"),
    ResultField("drift", "measure", "m_x/time", "mean dm_x/dt over the window",
                contract=True, detail=True),
    ResultField("zero_one_k", "measure", "", "the 0-1 test statistic on the peak sequence (continua)"),
    ResultField("t_blowup", "optional", "time", "when the run blew up (None: it did not)",
                contract=True, detail=True),
    ResultField("runtime_s", "optional", "s", "wall time of the run (integration and "
                "analysis)", contract=True),
    ResultField("t_stop", "measure", "time", "when the run stopped: its t_end, earlier where "
                "its attractor was certified (stop = certified) or where it blew up",
                contract=True, detail=True),
    ResultField("certified", "flag", "", "the attractor was certified from the run's own "
                "final state (a fixed point by linear theory and the measured decay, an orbit "
                "by Newton-Krylov shooting): the label is a claim about the model, not the "
                "window", contract=True, detail=True),
    ResultField("certificate", "text", "", "how the attractor was certified, or why it was "
                "not", contract=True, detail=True),
    ResultField("multipliers", "pairs", "", "the certified orbit's Floquet multipliers "
                "[re, im], the translation multiplier (1) apart, largest modulus first",
                contract=True, detail=True),
    ResultField("slips", "count", "", "slips (maxima of m_y) in one period of the "
                "certified orbit; 0 when nothing was certified or at rest", detail=True),
    ResultField("dt_error", "measure", "", "the estimated relative error of amplitude and "
                "period of the run's scheme at its dt, from a shadow at dt/2 and Richardson's "
                "extrapolation (core.accuracy; NaN: not estimated, as at rest)", detail=True,
                label="dt error"),
    ResultField("spectrum", "list", "1/time", "the top Lyapunov exponents, the m_x shift "
                "quotiented out (run --spectrum N; empty: not computed)"),
    ResultField("spectrum_err", "list", "1/time", "the standard errors of spectrum"),
)

#: The names of the result fields, in order: the result columns of ``runs``.
RESULT_NAMES: tuple[str, ...] = tuple(f.name for f in RESULT_FIELDS)
#: Keys of ``as_record`` after the result: the solver settings the run resolved (its
#: time step and end time) and the stop rule it ran under (core.solve.STOPS), which the
#: store keeps among the run's inputs.
SOLVER_KEYS: tuple[str, ...] = ("dt", "t_end", "stop")
#: The keys of ``PointResult.as_record``, in order.
RECORD_KEYS: tuple[str, ...] = (*RESULT_NAMES, *SOLVER_KEYS)
#: The keys of ``slopetui run --json``, in order: the documented contract first (regime,
#: lambda_max, lambda_err, amplitude, period, peaks, drift, t_blowup, runtime_s), then
#: the rest of the record.
JSON_KEYS: tuple[str, ...] = (*(f.name for f in RESULT_FIELDS if f.contract),
                              *(f.name for f in RESULT_FIELDS if not f.contract),
                              *SOLVER_KEYS)
#: The fields the run detail screen shows, in order.
DETAIL_FIELDS: tuple[ResultField, ...] = tuple(f for f in RESULT_FIELDS if f.detail)
BY_NAME: dict[str, ResultField] = {f.name: f for f in RESULT_FIELDS}
