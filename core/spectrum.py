"""The top N Lyapunov exponents of a run, the m_x shift quotiented out (run --spectrum N).

A second pass of the run's own scheme (core.tangents: the same steps from the same
history, so the same trajectory) co-iterates N tangents and re-orthonormalises them every
T_r (core.solve's renormalisation interval: tau clamped to [1, 10]). The logs of the
Gram-Schmidt lengths are the finite-time exponents; each exponent is their block mean over
the run's second half with its standard error, exactly as lambda_max (core.lyapunov).
The top one is lambda_max.

What the spectrum decides (``evidence``, used by core.classify):
  - on a periodic orbit the top exponent is the flow's, 0; the others are
    log|mu| / T of its Floquet multipliers mu;
  - a torus has two zero exponents besides the shift's (the flow's and one more) and the
    third clearly negative;
  - chaos has a positive exponent significant at 3 sigma (core.classify.CHAOS_LAMBDA_MIN);
  - near-neutral exponents that fit neither say nothing yet: a slow transient, perhaps.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from core.chunk_state import ring_shape
from core.history import CarriedState
from core.history import start as history_start
from core.lyapunov import estimate, format_with_error
from core.methods import METHOD_TABLE, method
from core.params import ParameterError, Params
from core.solve import MAX_RUN_BYTES, SolverSettings, make_grid

#: At most this many exponents. The states the spectrum is for need few: a torus shows
#: in the top three, an n-slip transient at tau = 10 (n <= 3) in the top 2(n - 1) + 2 = 6;
#: each exponent costs one more tangent (docs/speed.md), so 16 bounds a run at about
#: 16 times a lambda_max run's tangent work.
MAX_EXPONENTS = 16
#: The schemes with a tangent kernel (core.tangents; core.methods). The stiff scheme has none.
SPECTRUM_METHODS = tuple(m.name for m in METHOD_TABLE if m.tangents_name)
#: Seed of the random initial tangents: the same spectrum to the bit on every rerun.
TANGENT_SEED = 20261203
#: An exponent is zero "with confidence" when |value| <= ZERO_SIGMAS * its error and
#: |value| <= ZERO_ABS. 3 sigma as for chaos; ZERO_ABS = 1e-3 /t is CHAOS_LAMBDA_MIN's
#: bound: an exponent above it would count as chaos, so a zero one stays below it.
ZERO_SIGMAS = 3.0
ZERO_ABS = 1e-3
#: The third exponent of a torus is clearly negative: below -NEGATIVE_SIGMAS errors and
#: below -ZERO_ABS (the settled orbit at k = tau = 10, RK4 dt 0.01: its next exponents
#: are log|mu| / T = -0.04 /t, far below; an n-slip transient's are ~ -1e-5).
NEGATIVE_SIGMAS = 3.0


@dataclass(frozen=True, slots=True)
class Spectrum:
    """The top exponents (1/time, descending as Gram-Schmidt orders them) and their
    standard errors, over ``t_measured`` time units (the run's second half)."""

    values: tuple[float, ...]
    errors: tuple[float, ...]
    t_measured: float

    def format(self) -> str:
        """The exponents in the paper's notation, e.g. '-0.0001(2), -0.0405(3)'."""
        return ", ".join(format_with_error(v, e) for v, e in zip(self.values, self.errors,
                                                                   strict=True))


def check_count(n: object) -> int:
    """N for --spectrum: an integer in [1, MAX_EXPONENTS], else a ParameterError."""
    allowed = f"an integer 1 <= N <= {MAX_EXPONENTS}"
    try:
        value = int(str(n)) if not isinstance(n, bool) else None
    except ValueError:
        value = None
    if value is None or not 1 <= value <= MAX_EXPONENTS:
        raise ParameterError("spectrum", n, allowed)
    return value


def check_spectrum(p: Params, s: SolverSettings, n: int) -> None:
    """Raise a ParameterError if N exponents cannot be computed for this run: a scheme
    without a tangent kernel, more exponents than the system has without a delay (four
    besides the shift), or more memory than a run may take."""
    n = check_count(n)
    if s.method not in SPECTRUM_METHODS:
        raise ParameterError("spectrum", n, f"only with --method {' or '.join(SPECTRUM_METHODS)} "
                                            f"(the {s.method} scheme has no tangent kernel)")
    if p.tau == 0.0 and n > 4:
        raise ParameterError("spectrum", n, "1 <= N <= 4 at tau = 0 (m_y, s_x, s_y, u: "
                                            "the m_x shift is quotiented out)")
    g = make_grid(p, s)
    rows = method(s.method).ring_rows
    need = 8 * n * (rows * (g.n_delay + 1) + g.n_steps // g.renorm_steps)
    if need > MAX_RUN_BYTES:
        most = max(1, n * MAX_RUN_BYTES // need)
        raise ParameterError("spectrum", n, f"1 <= N <= {most} at tau = {p.tau:g}, "
                                            f"t_end = {s.t_end:g} (N delay rings and logs "
                                            f"within {MAX_RUN_BYTES / 1024**3:g} GiB)")


def spectrum(p: Params, s: SolverSettings, n: int,
             carried: CarriedState | None = None) -> Spectrum | None:
    """The top n exponents of the run (p, s) from its history (``carried`` as for
    core.solve.simulate); None if the scheme blew up before the end."""
    from core.model import coefficients
    from core.tangents import orthonormalise

    check_spectrum(p, s, n)
    g = make_grid(p, s)
    init, hx = history_start(p, g.dt, g.n_delay, s.history, carried)
    m = method(s.method)
    rows, slots = ring_shape(m, g.n_delay)
    rng = np.random.default_rng(TANGENT_SEED)
    e = rng.standard_normal((n, 5))
    h = rng.standard_normal((n, rows, slots))
    orthonormalise(e, h, slots, g.dt, np.zeros((1, n)), 0)
    logs = np.zeros((g.n_steps // g.renorm_steps, n))
    done = m.tangents()(coefficients(p), g.dt, g.n_delay, g.n_steps, g.renorm_steps, init, hx, e, h,
                  logs)
    if done < 0:  # blew up (core.tangents: a negative count)
        return None
    estimates = [estimate(logs[:, i], g.renorm_interval) for i in range(n)]
    return Spectrum(tuple(x.value for x in estimates), tuple(x.error for x in estimates),
                    estimates[0].t_measured if estimates else 0.0)


@dataclass(frozen=True, slots=True)
class Evidence:
    """What the top exponents say about the attractor (see the module docstring)."""

    chaotic: bool       # a positive exponent significant at 3 sigma, above ZERO_ABS
    torus: bool         # two zero exponents, the third clearly negative
    neutral: int        # exponents zero with confidence (the flow's among them)
    reason: str         # why neither, in words (empty when one holds)


def is_zero(value: float, error: float) -> bool:
    """The exponent is 0 with confidence (ZERO_SIGMAS, ZERO_ABS); without an error bar (a
    run too short for two blocks) only an exact 0 is."""
    if not math.isfinite(error):
        return value == 0.0
    return abs(value) <= min(ZERO_SIGMAS * error, ZERO_ABS)


def evidence(sp: Spectrum, chaos_min: float) -> Evidence:
    """Chaos, a torus, or neither, from the spectrum; ``chaos_min`` is the classifier's
    CHAOS_LAMBDA_MIN."""
    vals, errs = sp.values, [e if math.isfinite(e) else math.inf for e in sp.errors]
    chaotic = bool(vals) and vals[0] > max(3.0 * errs[0], chaos_min)
    zeros = [is_zero(v, e) for v, e in zip(vals, errs, strict=True)]
    neutral = sum(zeros)
    if chaotic:
        return Evidence(True, False, neutral, "")
    if len(vals) < 3:
        return Evidence(False, False, neutral, "quasi-periodic needs the top 3 exponents (two "
                                               "zero, one negative): run --spectrum 3")
    third_negative = vals[2] < -max(NEGATIVE_SIGMAS * errs[2], ZERO_ABS)
    if zeros[0] and zeros[1] and third_negative:
        return Evidence(False, True, neutral, "")
    if vals[0] > 0.0 and not zeros[0]:
        reason = "top exponent positive but below 3 sigma or the chaos bound"
    elif zeros[0] and zeros[1]:
        reason = "near-neutral exponents: a slow transient? (the third not clearly negative)"
    else:
        reason = "no two zero exponents: not quasi-periodic"
    return Evidence(False, False, neutral, reason)
