"""The whole state of a run between two chunks: what a kernel needs to continue it.

A run integrated to t1 and continued from its ChunkState to t2 is the run integrated to
t2 in one call, bit for bit (core.methods, the kernel contract, item 6): the kernels read
these arrays at the start of a call and write them back at the end, and keep nothing else
from one step to the next. core.solve.simulate stops a run early (``until``) and continues
it (``resume``), so that a run can stop as soon as its attractor is certified.

Layout of the arrays the kernels take (indices below; numba reads them as constants):

* ``now`` (float64, NOW_SIZE): the five variables m_x, m_y, s_x, s_y, u at the current
  step (model units: m_x a displacement, m_y a velocity, s_x, s_y, u the covariance of
  eq. 6c-6e), the tangent e_x .. e_u (dimensionless: renormalised to length 1 every
  renormalisation), and the running minima of s_x, s_y and s_x s_y - u^2 over every step
  so far (core.recording.lowest; inf before the first step).
* ``counts`` (int64, COUNTS_SIZE): the step the state is at (N_AT: t = N_AT dt), the ring
  position (POS: where the kernel reads m_x(t - tau) or writes step N_AT, per its
  layout), the window sampler's next step and column (NEXT_W, I_W), the trace's (NEXT_T,
  I_T), the next renormalisation's step and log index (NEXT_R, I_R), the first step at
  which a minimum fell below -REALISABLE_TOL (FIRST, -1: none) and the step after which
  the state left the bounds (BLOWN, -1: none; core.recording.blown_up).
* ``ring`` (float64, RING_SHAPES): the state over the last delay at the kernel's step
  (Euler and stiff: m_x at the N steps before this one; RK4: m_x and m_y at the N + 1
  steps up to this one, Hermite's nodes); ``e_ring``: the tangent's, same shape.
* ``plan`` (int64, PLAN_SIZE; not part of the state: the grid's): the step to stop at
  (END) and the samplers' schedule (core.solve.Grid), in steps.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from core.closure import Realisability
from core.history import CarriedState
from core.methods import Method

# now
M_X, M_Y, S_X, S_Y, U, E_X, E_Y, E_SX, E_SY, E_U, LO_X, LO_Y, LO_D = range(13)
NOW_SIZE = 13
# counts
N_AT, POS, NEXT_W, I_W, NEXT_T, I_T, NEXT_R, I_R, FIRST, BLOWN = range(10)
COUNTS_SIZE = 10
# plan
END, SAMPLE_START, WIN_STRIDE, WIN_JUMP, WIN_RESUME, TRACE_STRIDE, RENORM_STEPS = range(7)
PLAN_SIZE = 7
#: The tangent a kernel starts from: the five-vector (0, 1, 1, 1, 1), its ring 0 (core.euler).
START_TANGENT = (0.0, 1.0, 1.0, 1.0, 1.0)


def ring_shape(m: Method, n_delay: int) -> tuple[int, int]:
    """(rows, slots) of the method's delay ring (its tangent's is the same)."""
    return m.ring_rows, n_delay + m.ring_extra


def plan_of(end: int, sample_start: int, win_stride: int, win_jump: int, win_resume: int,
            trace_stride: int, renorm_steps: int) -> np.ndarray:
    """The kernels' ``plan``: stop at step ``end``; the rest as core.solve.Grid's."""
    return np.array([end, sample_start, win_stride, win_jump, win_resume, trace_stride,
                     renorm_steps], dtype=np.int64)


def start_arrays(m: Method, n_delay: int, sample_start: int, renorm_steps: int,
                 init: np.ndarray, hx: np.ndarray
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A kernel's (now, counts, ring, e_ring) at step 0: the five variables ``init`` and the
    history ``hx`` (core.history.start), the tangent at START_TANGENT, nothing sampled."""
    now = np.empty(NOW_SIZE)
    now[M_X:U + 1] = init
    now[E_X:E_U + 1] = START_TANGENT
    now[LO_X:LO_D + 1] = np.inf
    counts = np.zeros(COUNTS_SIZE, dtype=np.int64)
    counts[NEXT_W], counts[NEXT_R] = sample_start, renorm_steps
    counts[FIRST] = counts[BLOWN] = -1
    ring = np.zeros(ring_shape(m, n_delay))
    if m.ring_extra == 0:  # a ring of m_x(-tau + j dt), read from slot 0 on
        ring[0] = hx[0:2 * n_delay:2]
    # RK4's ring fills as it steps: it reads hx itself while t - tau < 0
    return now, counts, ring, np.zeros(ring.shape)


@dataclass(frozen=True, eq=False)
class ChunkState:
    """A run's state at step ``step`` (t = step dt) of its grid, as a kernel left it. Its
    arrays are read-only; ``arrays()`` gives the writable copies a kernel call takes."""

    method: str
    dt: float
    n_delay: int
    now: np.ndarray
    counts: np.ndarray
    ring: np.ndarray
    e_ring: np.ndarray

    def __post_init__(self) -> None:
        for a in (self.now, self.counts, self.ring, self.e_ring):
            a.flags.writeable = False

    @classmethod
    def start(cls, m: Method, dt: float, n_delay: int, sample_start: int, renorm_steps: int,
              init: np.ndarray, hx: np.ndarray) -> ChunkState:
        """Step 0 (start_arrays, read-only)."""
        return cls(m.name, dt, n_delay, *start_arrays(m, n_delay, sample_start, renorm_steps,
                                                      init, hx))

    def arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Writable copies of (now, counts, ring, e_ring) for a kernel to continue from."""
        return self.now.copy(), self.counts.copy(), self.ring.copy(), self.e_ring.copy()

    @property
    def step(self) -> int:
        return int(self.counts[N_AT])

    @property
    def t(self) -> float:
        """Model time of the state."""
        return self.step * self.dt

    @property
    def blew_up(self) -> bool:
        return int(self.counts[BLOWN]) >= 0

    def realisability(self) -> Realisability:
        """The minima over every step so far, and the first violation."""
        first = int(self.counts[FIRST])
        return Realisability(float(self.now[LO_X]), float(self.now[LO_Y]), float(self.now[LO_D]),
                             first * self.dt if first >= 0 else None)

    def carried(self, tau: float) -> CarriedState:
        """The state for another run to start from (core.history): the five variables and
        m_x at t - tau + j dt, j = 0..N-1, read from the ring from its oldest slot."""
        size = self.ring.shape[1]
        oldest = (int(self.counts[POS]) + size - self.n_delay) % size if size else 0
        ring = self.ring[0]
        m_x = np.concatenate((ring[oldest:], ring[:oldest]))[:self.n_delay]
        return CarriedState(tau, self.dt, self.now[M_X:U + 1].copy(), m_x)
