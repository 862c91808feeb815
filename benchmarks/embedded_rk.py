"""An error-controlled method measured against RK4 and Euler.

Run:  python benchmarks/embedded_rk.py [--markdown FILE]

The candidate is JiTCDDE's: the Bogacki-Shampine 3(2) pair (FSAL: three new right-hand
sides a step), its step chosen from the embedded error estimate (mixed tolerance
atol = rtol on every component), the delayed m_x taken from the cubic Hermite interpolant
of the accepted steps with the exact slope m_y (eq. 6a; 4th order, beyond the pair's
3rd), the step never longer than tau (no extrapolation inside a step), the constant
history delta before t = 0 (eq. 19). Output: m_y at the window's sample times by the cubic
Hermite interpolant of each step with slopes from the FSAL stages.

Measured, per point: the relative error of the window's amplitude (refined maxima minus
minima of m_y, core.classify.find_peaks) against a reference (RK4 at dt = 1e-4, checked
against dt = 2e-4) and the CPU time, for Euler at dt 1e-3 and 5e-4, RK4 at dt 0.05 to 5e-3
and the pair at rtol 1e-4 to 1e-9; each contender run twice, interleaved, the better time
kept. The pair earns a place in ``--method`` only if it is faster at equal accuracy.
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import numpy as np
from numba import njit

from core.classify import find_peaks
from core.model import JIT, coefficients, rhs
from core.params import Params
from core.solve import SolverSettings, simulate


@njit(**JIT)
def _delayed(t, ts, xs, ys, n, j, delta):
    """m_x(t) from the accepted steps (times ts[:n], values xs, slopes ys) by cubic Hermite,
    delta before 0; j: a hint for the interval, returned updated."""
    if t <= 0.0:
        return delta, j
    while j + 1 < n - 1 and ts[j + 1] <= t:
        j += 1
    while j > 0 and ts[j] > t:
        j -= 1
    h = ts[j + 1] - ts[j]
    s = (t - ts[j]) / h
    return ((2 * s**3 - 3 * s**2 + 1) * xs[j] + (s**3 - 2 * s**2 + s) * h * ys[j]
            + (-2 * s**3 + 3 * s**2) * xs[j + 1] + (s**3 - s**2) * h * ys[j + 1]), j


@njit(**JIT)
def _axpy(z, h, k):
    """z + h k on 5-tuples."""
    return (z[0] + h * k[0], z[1] + h * k[1], z[2] + h * k[2], z[3] + h * k[3], z[4] + h * k[4])


@njit(**JIT)
def bs23(coef, tau, t_end, rtol, out_t, out_y, cap):
    """Integrate eqs. 6a-6e by Bogacki-Shampine 3(2) to t_end; m_y at the times out_t
    (increasing) into out_y. Returns (accepted steps, rejected steps, evaluations).
    Scalars and tuples only in the loop: no allocation per step."""
    a, q, f1, k, d, delta = coef[0], coef[1], coef[2], coef[3], coef[4], coef[5]
    ts = np.empty(cap)
    xs = np.empty(cap)
    ys = np.empty(cap)
    z = (delta, delta, delta, delta, delta)  # (19)
    t = 0.0
    n = 1
    ts[0], xs[0], ys[0] = 0.0, delta, delta
    j1 = j2 = 0
    xd, j1 = _delayed(t - tau, ts, xs, ys, n, j1, delta)
    k1 = rhs(z[0], z[1], z[2], z[3], z[4], xd, a, q, f1, k, d)
    h = min(1e-3, tau)
    acc = rej = 0
    evals = 1
    i_out = 0
    while t < t_end and n < cap - 1:
        h = min(h, t_end - t, tau)
        xd, j2 = _delayed(t + 0.5 * h - tau, ts, xs, ys, n, j2, delta)
        zz = _axpy(z, 0.5 * h, k1)
        k2 = rhs(zz[0], zz[1], zz[2], zz[3], zz[4], xd, a, q, f1, k, d)
        xd, j2 = _delayed(t + 0.75 * h - tau, ts, xs, ys, n, j2, delta)
        zz = _axpy(z, 0.75 * h, k2)
        k3 = rhs(zz[0], zz[1], zz[2], zz[3], zz[4], xd, a, q, f1, k, d)
        w1, w2, w3 = 2.0 / 9.0 * h, 1.0 / 3.0 * h, 4.0 / 9.0 * h
        zn = (z[0] + w1 * k1[0] + w2 * k2[0] + w3 * k3[0], z[1] + w1 * k1[1] + w2 * k2[1] + w3 * k3[1],
              z[2] + w1 * k1[2] + w2 * k2[2] + w3 * k3[2], z[3] + w1 * k1[3] + w2 * k2[3] + w3 * k3[3],
              z[4] + w1 * k1[4] + w2 * k2[4] + w3 * k3[4])
        xd, j1 = _delayed(t + h - tau, ts, xs, ys, n, j1, delta)
        k4 = rhs(zn[0], zn[1], zn[2], zn[3], zn[4], xd, a, q, f1, k, d)
        evals += 3
        err = 0.0
        for c in range(5):
            e = h * (-5.0 / 72.0 * k1[c] + 1.0 / 12.0 * k2[c] + 1.0 / 9.0 * k3[c] - 1.0 / 8.0 * k4[c])
            r = e / (rtol * (1.0 + max(abs(z[c]), abs(zn[c]))))
            err += r * r
        err = math.sqrt(err / 5.0)
        if err <= 1.0:
            while i_out < out_t.shape[0] and out_t[i_out] <= t + h:
                s = (out_t[i_out] - t) / h
                out_y[i_out] = ((2 * s**3 - 3 * s**2 + 1) * z[1] + (s**3 - 2 * s**2 + s) * h * k1[1]
                                + (-2 * s**3 + 3 * s**2) * zn[1] + (s**3 - s**2) * h * k4[1])
                i_out += 1
            t += h
            z = zn
            k1 = k4
            ts[n], xs[n], ys[n] = t, z[0], z[1]
            n += 1
            acc += 1
        else:
            rej += 1
        h *= min(5.0, max(0.2, 0.9 * (1.0 / max(err, 1e-12)) ** (1.0 / 3.0)))
    return acc, rej, evals


def amplitude(t: np.ndarray, y: np.ndarray) -> float:
    _, top = find_peaks(t, y)
    _, low = find_peaks(t, -y)
    return float(top.max() + low.max())


def fixed(p: Params, method: str, dt: float, t_end: float, window: float) -> tuple[float, float]:
    t0 = time.process_time()
    tr = simulate(p, SolverSettings(method=method, dt=dt, t_end=t_end, window=window, lyap=False,
                                    trace_points=2))
    cpu = time.process_time() - t0
    return amplitude(tr.window_t, tr.window[1]), cpu


def embedded(p: Params, rtol: float, t_end: float, window: float) -> tuple[float, float, int]:
    out_t = np.arange(t_end - window, t_end + 1e-9, 0.01)
    out_y = np.full(out_t.size, np.nan)
    t0 = time.process_time()
    _, _, evals = bs23(coefficients(p), p.tau, t_end, rtol, out_t, out_y, 50_000_000)
    cpu = time.process_time() - t0
    return amplitude(out_t, out_y), cpu, evals


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--t-end", type=float, default=2000.0)
    ap.add_argument("--markdown", type=Path)
    args = ap.parse_args()
    t_end, window = args.t_end, 200.0
    rows = [f"| point | method | step / rtol | relative error of the amplitude | CPU s "
            f"(t_end {t_end:g}) |", "|---|---|---|---:|---:|"]
    for p in (Params(k=10.0, tau=10.0), Params(k=40.0, tau=0.5)):
        embedded(p, 1e-3, 20.0, 10.0)
        fixed(p, "rk4", 1e-2, 20.0, 10.0)
        fixed(p, "euler", 1e-3, 20.0, 10.0)
        ref, _ = fixed(p, "rk4", 1e-4, t_end, window)
        check, _ = fixed(p, "rk4", 2e-4, t_end, window)
        name = f"k = {p.k:g}, τ = {p.tau:g}"
        print(name, "reference", ref, "dt 2e-4 off by", check / ref - 1, flush=True)
        contenders = ([("euler", dt) for dt in (1e-3, 5e-4)]
                      + [("rk4", dt) for dt in (0.05, 0.02, 1e-2, 5e-3)]
                      + [("bs23", r) for r in (1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9)])
        best: dict[tuple[str, float], float] = {}
        errs: dict[tuple[str, float], float] = {}
        for _ in range(2):
            for c in contenders:
                if c[0] == "bs23":
                    amp, cpu, _ = embedded(p, c[1], t_end, window)
                else:
                    if p.tau / c[1] != round(p.tau / c[1]):
                        continue
                    amp, cpu = fixed(p, c[0], c[1], t_end, window)
                errs[c] = amp / ref - 1.0
                best[c] = min(best.get(c, math.inf), cpu)
        for c in contenders:
            if c in best:
                rows.append(f"| {name} | {c[0]} | {c[1]:g} | {errs[c]:+.1e} | {best[c]:.3f} |")
                print(rows[-1], flush=True)
    table = "\n".join(rows) + ("\n\nBest of 2 interleaved rounds, CPU time, the machine shared "
                               "with other jobs (benchmarks/embedded_rk.py).\n")
    if args.markdown:
        args.markdown.write_text(table)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
