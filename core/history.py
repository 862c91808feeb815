"""The state before t = 0: a choice, since eq. 19 fixes only t = 0.

Eq. 19 sets the five variables to delta at t = 0, but the delayed term needs m_x on
[-tau, 0) too. The kernels (core.euler, core.rk4, core.stiff) read that history from an
array at every half step, t = -tau + j dt / 2 for j = 0..2N, and start from five given
values. The choices:

* ``constant``: m_x(t) = delta for t < 0 (the default, and the paper-faithful reading:
  core.solve says why). Its slope, 0, differs from m_y(0) = delta: a kink at t = 0, whose
  echoes every tau are the stick-slip pulse trains the honest-labels audit found at
  large tau.
* ``consistent``: m_x(t) = delta (1 + t) for t <= 0, the history that moves with the
  initial velocity m_y(0) = delta (eq. 6a: dm_x/dt = m_y), so m_x has no kink at t = 0.
* ``state:<digest>``: the final state of another run (CarriedState): its five variables
  at t_end, and m_x over its last delay. It must come from a run with the same tau and
  step (the history is N = tau / dt values). RK4 reads half steps between the carried
  grid values: cubic Lagrange midpoints (3 points at the two ends), 4th order in dt as
  the RK4 stages themselves; Euler reads the grid values only. The warm start of
  core.hysteresis hands over RK4 half steps exactly instead (it keeps m_y's history).

The constant history gives arrays equal to delta, so a run with it is bit for bit the
run the kernels computed before histories were a choice.
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass

import numpy as np

from core.params import ParameterError, Params

#: The histories named by a word; a carried state is named "state:" + its digest.
HISTORIES = ("constant", "consistent")
STATE_PREFIX = "state:"
#: Hex digits of a carried state's digest.
DIGEST_LENGTH = 16


@dataclass(frozen=True)
class CarriedState:
    """The final state of a run, for another run to start from: tau and the step of the
    run it came from, the five variables (m_x, m_y, s_x, s_y, u) at its t_end, and m_x at
    t_end - tau + j dt for j = 0..N-1."""

    tau: float
    dt: float
    now: np.ndarray
    m_x: np.ndarray

    @property
    def digest(self) -> str:
        h = hashlib.sha256(f"{self.tau!r};{self.dt!r};".encode())
        h.update(np.ascontiguousarray(self.now, dtype="<f8").tobytes())
        h.update(np.ascontiguousarray(self.m_x, dtype="<f8").tobytes())
        return h.hexdigest()[:DIGEST_LENGTH]

    @property
    def name(self) -> str:
        """The history's name on a run: "state:" + digest."""
        return STATE_PREFIX + self.digest

    def to_bytes(self) -> bytes:
        return np.concatenate(([self.tau, self.dt], self.now, self.m_x)).astype("<f8").tobytes()

    @staticmethod
    def from_bytes(blob: bytes) -> CarriedState:
        a = np.frombuffer(blob, dtype="<f8")
        return CarriedState(float(a[0]), float(a[1]), a[2:7].copy(), a[7:].copy())


def check_history(text: object) -> str:
    """The history's name, or ParameterError naming the field and what is allowed."""
    if isinstance(text, str) and (text in HISTORIES or (
            text.startswith(STATE_PREFIX) and len(text) == len(STATE_PREFIX) + DIGEST_LENGTH
            and all(c in "0123456789abcdef" for c in text[len(STATE_PREFIX):]))):
        return text
    raise ParameterError("history", text, "constant, consistent, or the final state of a "
                                          "stored run (run:ID where a command takes it)")


def start(p: Params, dt: float, n_delay: int, history: str,
          carried: CarriedState | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The five variables at t = 0 and m_x at t = -tau + j dt / 2, j = 0..2N (the
    kernels' ``init`` and ``hx``)."""
    t = -p.tau + 0.5 * dt * np.arange(2 * n_delay + 1)
    if history == "constant":
        return np.full(5, p.delta), np.full(2 * n_delay + 1, p.delta)
    if history == "consistent":
        return np.full(5, p.delta), p.delta * (1.0 + t)
    if carried is None or history != carried.name:
        raise ParameterError("history", history, "constant, consistent, or a state given "
                                                 "with the run (a carried state's name)")
    if not (math.isclose(carried.tau, p.tau, rel_tol=1e-12) and carried.m_x.size == n_delay
            and math.isclose(carried.dt, dt, rel_tol=1e-9)):
        raise ParameterError("history", history,
                             f"a state from a run with this run's tau = {p.tau:g} and step "
                             f"{dt:g} (it comes from tau = {carried.tau:g}, step "
                             f"{carried.dt:g})")
    return carried.now.copy(), half_steps(np.append(carried.m_x, carried.now[0]))


def half_steps(x: np.ndarray) -> np.ndarray:
    """Values at the grid points x_0..x_N and midpoints between them (cubic Lagrange, 3
    points at the ends), interleaved: 2N + 1 values."""
    n = x.size - 1
    out = np.empty(2 * n + 1)
    out[0::2] = x
    if n == 0:  # tau = 0: the state alone, no delay to fill
        return out
    if n == 1:
        out[1] = 0.5 * (x[0] + x[1])
        return out
    mid = np.empty(n)
    mid[0] = (3 * x[0] + 6 * x[1] - x[2]) / 8
    mid[-1] = (-x[-3] + 6 * x[-2] + 3 * x[-1]) / 8
    if n > 2:
        mid[1:-1] = (-x[:-3] + 9 * x[1:-2] + 9 * x[2:-1] - x[3:]) / 16
    out[1::2] = mid
    return out


__all__ = ["HISTORIES", "CarriedState", "check_history", "half_steps", "start"]
