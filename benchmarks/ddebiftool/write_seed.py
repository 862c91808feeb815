"""Write slopetui's equally spaced n-slip seed for threeslip.m (Newton's starting guess only).

The seed is core.orbit_seed.n_slip_seed, exactly as `slopetui orbit --slips N` builds it
(RK4 dt = 0.01 from eq. 19, 3000 time units, one slip cycle tiled over the delay and
integrated): an RK4 loop in Octave took 134 s for 600 time units on the shared machine,
too slow for the 3000 the unequal slip spacing needs. What is written is the seed integrated over one period T/n,
not slopetui's Newton-corrected orbit. Columns: t, m_x, m_y, s_x, s_y, u.

Usage: .venv/bin/python benchmarks/ddebiftool/write_seed.py K TAU DELTA N OUT
"""
import math
import sys

import numpy as np

from core.orbit import Grid
from core.orbit_seed import find_return, n_slip_seed, simulate, simulate_from
from core.params import Params
from core.periodic_orbit import ORBIT_DT, SEED_SPAN, SEED_T_END


def main() -> None:
    k, tau, delta, n, out = (float(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3]),
                             int(sys.argv[4]), sys.argv[5])
    p = Params(k=k, tau=tau, delta=delta)
    g = Grid.of(p, ORBIT_DT)
    traj = simulate(p, g, max(SEED_T_END, 4 * p.tau + SEED_SPAN))
    _, period = find_return(traj, g, min(SEED_SPAN, SEED_T_END / 2))
    z0, _, target = n_slip_seed(p, g, traj, period, n)
    run = simulate_from(p, g, z0, target + 2 * g.dt)
    m = math.ceil(target / g.dt) + 1
    t = g.dt * np.arange(m)
    cols = run[:, g.n_delay:g.n_delay + m]
    np.savetxt(out, np.column_stack((t, cols.T)), fmt="%.17g",
               header=f"k={k} tau={tau} delta={delta} slips={n} return={period:.10g} "
                      f"seed_period={target:.10g}")
    print(f"seed written: return {period:.8g}, seed period {target:.8g}, {m} rows")


if __name__ == "__main__":
    main()
