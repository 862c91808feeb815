"""The original N-block model (eq. 5), whose mean-field limit is eqs. 6a-6e.

N blocks, each with displacement x_i and velocity y_i relative to the steady state:

    dx_i = y_i dt
    dy_i = [F(v) - F(v + y_i) + kappa sum_{j != i} (x_j(t - tau) - x_i)] dt + sqrt(2d) dw_i

with all-to-all coupling kappa = k / N, so that the coupling tends to k (m_x,tau - x_i)
as N grows (the term of eq. 6b), and independent Wiener noises w_i. Integrated with
Euler-Maruyama at the step of the mean-field Euler solver.

Decisions where the paper is silent, chosen to match core.solve's mean-field setup:
- initial state (eq. 19 asks mean and (co)variances all equal to delta): x_i = delta +
  sqrt(delta) z_i and y_i = delta + sqrt(delta) z_i with the *same* z_i, normal draws
  standardised to sample mean 0 and variance 1, so that the ensemble's moments at t = 0
  are exactly those of eq. 19 for every N (otherwise a small N starts elsewhere and the
  comparison measures the draw, not the model);
- history: x_i(t) = x_i(0) for t <= 0 (the mean-field solver's constant history);
- the ensemble statistics are population moments (1/N), as in the mean-field closure.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from core.model import JIT, coefficients
from core.params import Params
from core.recording import BLOWUP_BOUND
from core.solve import SolverSettings, simulate


@njit(**JIT)
def ensemble_moments(x, y, out, i):
    """Column i of out: (m_x, m_y, s_x, s_y, u) of the ensemble, population moments."""
    n = x.size
    m_x = x.sum() / n
    m_y = y.sum() / n
    s_x = s_y = u = 0.0
    for j in range(n):
        dx = x[j] - m_x
        dy = y[j] - m_y
        s_x += dx * dx
        s_y += dy * dy
        u += dx * dy
    out[0, i], out[1, i], out[2, i], out[3, i], out[4, i] = m_x, m_y, s_x / n, s_y / n, u / n


@njit(**JIT)
def nblock_euler_maruyama(coef, dt, n_delay, n_steps, stride, x, y, seed, out):
    """Advance the blocks (x, y in place) n_steps; sample the moments every stride steps
    into out (5, n_samples). Returns n_steps, or minus the steps done if a block blew up
    (the step that blew up counted: at the last step too)."""
    a, q, f1, k, d = coef[0], coef[1], coef[2], coef[3], coef[4]
    np.random.seed(seed)
    n = x.size
    kappa = k / n
    noise = math.sqrt(2.0 * d * dt)
    depth = max(n_delay, 1)
    hist = np.empty((depth, n))        # x over (t - tau, t]; history = x(0)
    for r in range(depth):
        hist[r, :] = x
    pos = 0
    for step in range(n_steps):
        if step % stride == 0:
            ensemble_moments(x, y, out, step // stride)
        delayed = hist[pos] if n_delay > 0 else x
        total_tau = delayed.sum()
        for i in range(n):
            x_tau = delayed[i]
            yi = y[i]
            coupling = kappa * (total_tau - x_tau) - kappa * (n - 1) * x[i]   # (5)
            friction = -yi * (f1 + yi * (q + a * yi))        # F(v) - F(v + y_i)
            hist[pos, i] = x[i]
            x[i] += dt * yi
            y[i] = yi + dt * (friction + coupling) + noise * np.random.standard_normal()
            if not abs(y[i]) < BLOWUP_BOUND:
                return -(step + 1)  # negative: blew up, even at the last step
        if n_delay > 0:
            pos += 1
            if pos == n_delay:
                pos = 0
    if n_steps % stride == 0:
        ensemble_moments(x, y, out, n_steps // stride)
    return n_steps


@dataclass(frozen=True)
class Ensemble:
    """Moments of the N-block ensemble sampled at t (rows m_x, m_y, s_x, s_y, u)."""

    params: Params
    n_blocks: int
    seed: int
    t: np.ndarray
    moments: np.ndarray
    t_blowup: float | None


def simulate_ensemble(p: Params, n_blocks: int, t_end: float, dt: float = 1e-3,
                      sample_dt: float = 0.1, seed: int = 0) -> Ensemble:
    """Integrate eq. 5 for n_blocks blocks to t_end (model time units) with step dt,
    sampling the ensemble moments every sample_dt. The same seed gives the same run."""
    if n_blocks < 2:
        raise ValueError("n_blocks must be >= 2 (a variance needs two blocks)")
    if p.tau > 0:
        n_delay = math.ceil(p.tau / dt - 1e-9)
        dt = p.tau / n_delay                      # tau on the grid, as core.solve does
    else:
        n_delay = 0
    n_steps = math.ceil(t_end / dt - 1e-9)
    stride = max(1, round(sample_dt / dt))
    out = np.full((5, n_steps // stride + 1), np.nan)
    rng = np.random.default_rng(seed)
    z = rng.standard_normal(n_blocks)
    z = (z - z.mean()) / z.std()  # exact moments at t = 0: the sample starts on eq. 19
    spread = math.sqrt(p.delta) if p.delta > 0 else 0.0
    x = p.delta + spread * z                      # (19), see the module docstring
    y = x.copy()
    done = nblock_euler_maruyama(coefficients(p), dt, n_delay, n_steps, stride, x, y,
                                 int(rng.integers(2**31 - 1)), out)
    blown, done = done < 0, abs(done)
    n_samples = done // stride if blown else done // stride + 1
    t = np.arange(out.shape[1]) * stride * dt
    t_blowup = done * dt if blown else None
    return Ensemble(p, n_blocks, seed, t[:n_samples], out[:, :n_samples], t_blowup)


VARIABLES = ("m_x", "m_y", "s_x", "s_y", "u")


@dataclass(frozen=True)
class Comparison:
    """The ensemble against the mean-field solution on the same parameters and grid.

    errors[name] = ||ensemble - mean field|| / ||mean field|| over the sampled times (the
    relative RMS difference of one variable's time series).
    """

    ensemble: Ensemble
    t: np.ndarray
    mean_field: np.ndarray   # (5, len(t)), the mean-field moments at the ensemble's times
    errors: dict[str, float]


def compare_with_mean_field(p: Params, n_blocks: int, t_end: float, dt: float = 1e-3,
                            sample_dt: float = 0.1, seed: int = 0) -> Comparison:
    """Run eq. 5 and eqs. 6a-6e (Euler, the same dt) and measure how far apart they are."""
    ens = simulate_ensemble(p, n_blocks, t_end, dt, sample_dt, seed)
    n = len(ens.t)
    settings = SolverSettings(method="euler", dt=dt, t_end=t_end, window=min(t_end, 1.0),
                              lyap=False, trace_points=max(2, round(t_end / sample_dt) + 1))
    tr = simulate(p, settings)
    mf = np.vstack([np.interp(ens.t, tr.trace_t, tr.trace[i]) for i in range(5)])
    errors = {}
    for i, name in enumerate(VARIABLES):
        scale = float(np.sqrt(np.mean(mf[i, :n] ** 2)))
        diff = float(np.sqrt(np.mean((ens.moments[i] - mf[i, :n]) ** 2)))
        errors[name] = diff / scale if scale > 0 else math.inf
    return Comparison(ens, ens.t, mf, errors)
