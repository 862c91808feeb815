"""The paper's figures, one preset per panel, as sweep specs.

Each preset quotes the paper's claim for its panel (the report compares it with what
slopetui measures) and says where its ranges come from. The paper gives the fixed
parameters in its captions but not its axis ranges (and some captions are missing from
the text); where it does not say, the range is ours and ``note`` says why. Solver: the
paper's Euler at dt = 1e-3 to t_end = 1e5, classified on [99000, 100000], every run to
t_end whatever it has become (stop = "t_end": the paper's protocol, not a new sweep's
certified stop). Phase diagrams
skip lambda_max (the paper computed it only for Figs. 3 and 8); the 0-1 test still
separates chaos from quasi-periodicity.

``spec`` holds the full resolution; ``at_resolution`` scales a preset down (or up).
"""

from __future__ import annotations

import copy
from dataclasses import dataclass
from typing import Any

PAPER_SOLVER = {"method": "euler", "dt": 1e-3, "t_end": 1e5, "window": 1000.0, "lyap": True,
                "stop": "t_end"}
PLANE_SOLVER = {**PAPER_SOLVER, "lyap": False}
#: tau range of the phase diagrams: the sharp small-tau drop of the Hopf line (eq. 26)
#: and the large-delay complex region both show between 0.1 and 20.
TAU_AXIS = {"param": "tau", "start": 0.1, "stop": 20.0, "num": 40, "spacing": "linear"}


@dataclass(frozen=True)
class Preset:
    key: str        # e.g. "fig5a"
    figure: str     # the panel, e.g. "Fig. 5A"
    title: str
    claim: str      # the paper's words
    note: str       # where the ranges come from
    spec: dict[str, Any]

    def at_resolution(self, points: int | None = None, t_end: float | None = None) -> dict[str, Any]:
        """The spec with ``points`` per axis of a phase diagram, and up to 4 x points on a
        bifurcation diagram's single axis (a line is cheap next to a plane); a single-point
        preset stays one point. Another t_end shrinks the window to fit."""
        spec = copy.deepcopy(self.spec)
        if points is not None:
            plane = "y" in spec
            for axis in ("x", "y"):
                if axis in spec and spec[axis]["num"] > 1:
                    spec[axis]["num"] = points if plane else min(spec[axis]["num"], 4 * points)
        if t_end is not None:
            spec["solver"]["t_end"] = t_end
            spec["solver"]["window"] = min(spec["solver"]["window"], t_end / 2)
        return spec


def _axis(param: str, start: float, stop: float, num: int, spacing: str = "linear") -> dict:
    return {"param": param, "start": start, "stop": stop, "num": num, "spacing": spacing}


def _preset(key: str, figure: str, title: str, claim: str, note: str, x: dict,
            y: dict | None = None, *, solver: dict | None = None, **fixed: float) -> Preset:
    return _preset_of(key, figure, title, claim, note, x, y, solver, fixed)


def _preset_of(key: str, figure: str, title: str, claim: str, note: str, x: dict,
               y: dict | None, solver: dict | None, fixed: dict[str, float]) -> Preset:
    spec: dict[str, Any] = {"name": f"{figure}: {title}", "x": x, "fixed": fixed,
                            "solver": dict(solver or (PLANE_SOLVER if y else PAPER_SOLVER))}
    if y is not None:
        spec["y"] = y
    return Preset(key, figure, title, claim, note, spec)


def _pair(n: int, title: str, claim: str, note: str, x: dict, **fixed: float) -> tuple[Preset, Preset]:
    """Panels A (delta = 1e-6, near the fixed point) and B (delta = 0.1, far from it) of
    a (parameter, tau) phase diagram; the paper compares the two in each figure."""
    near = _preset_of(f"fig{n}a", f"Fig. {n}A", f"{title}, delta = 1e-6", claim, note, x,
                      dict(TAU_AXIS), None, {"delta": 1e-6, **fixed})
    far = _preset_of(f"fig{n}b", f"Fig. {n}B", f"{title}, delta = 0.1", f"(see Fig. {n}A)",
                     f"As Fig. {n}A, far from the fixed point.", dict(x), dict(TAU_AXIS), None,
                     {"delta": 0.1, **fixed})
    return near, far


FIG2_CLAIM = ("Examples of solutions in these regimes are shown in Figure 2. [...] Period-doubling "
              "is the simplest example of this regime (Figure 2C).")
FIG2_NOTE = ("The caption of Fig. 2 is not in our copy of the text: the points are ours, one "
             "per regime, at the defaults of eq. 8 and tau = 10, chosen from Fig. 4A's ranges "
             "(and Fig. 7's low a for the unstable one).")

PRESETS: tuple[Preset, ...] = (
    _preset("fig2a", "Fig. 2A", "sliding example (k = 4, tau = 10)", FIG2_CLAIM, FIG2_NOTE,
            _axis("k", 4, 4, 1), tau=10, delta=0.1),
    _preset("fig2b", "Fig. 2B", "oscillatory example (k = 10, tau = 10)", FIG2_CLAIM, FIG2_NOTE,
            _axis("k", 10, 10, 1), tau=10, delta=0.1),
    _preset("fig2c", "Fig. 2C", "period-doubling example (k = 20, tau = 10)", FIG2_CLAIM,
            "k = 20 is inside Fig. 4B's period-doubling window (17-20.5).",
            _axis("k", 20, 20, 1), tau=10, delta=0.1),
    _preset("fig2d", "Fig. 2D", "unstable example (a = 0.035, k = 12, tau = 1)", FIG2_CLAIM,
            FIG2_NOTE, _axis("a", 0.035, 0.035, 1), k=12, tau=1, delta=0.1),
    _preset("fig3", "Fig. 3", "complex oscillations with large delay, with lambda_max",
            "Examples of the complex oscillatory regime with large delay for a = 3.2, b = 7.2, "
            "c = 4.8, d = 10^-4, v = 0.1, and initial conditions with offset delta = 10^-4. [...] "
            "The Lyapunov exponents (J), (K), and (L) converge to lambda_max(J) = 0.0008(9), "
            "lambda_max(K) = -0.15(6) and lambda_max(L) = -0.12(3).",
            "The caption gives neither k nor tau: we sweep the large delays tau = 20-100 at "
            "k = 20 (complex at tau = 10 in Fig. 4A) and report lambda_max of every complex run.",
            _axis("tau", 20, 100, 17), k=20, delta=1e-4),
    _preset("fig4a", "Fig. 4A", "bifurcation in k (tau = 10, delta = 0.1)",
            "Plot (A) clearly shows sliding (k <= 6), oscillatory (6 <= k <= 17) and complex "
            "oscillatory regime (k >= 17).",
            "Caption parameters; k from 3 to 24 covers the three regimes in steps of 0.25.",
            _axis("k", 3, 24, 85), tau=10, delta=0.1),
    _preset("fig4b", "Fig. 4B", "period-doubling zoom (tau = 10, delta = 0.1)",
            "Plot (B) in addition shows zoomed-in region in which period-doubling appears - up "
            "to about k = 20.5, there are four distinct amplitudes for each k, which is "
            "consistent with the period-doubling time series in Figure 2C.",
            "Caption parameters; k from 17 to 21 in steps of 0.05 around the 20.5 of the text.",
            _axis("k", 17, 21, 81), tau=10, delta=0.1),
    _preset("fig4c", "Fig. 4C", "(k, tau) phase diagram, delta = 1e-6",
            "(C) Phase diagram for a = 3.2, b = 7.2, c = 4.8, d = 10^-4, v = 0.1, with initial "
            "conditions delta = 10^-6, showing the onset of the period-doubling within the "
            "complex oscillatory regime.",
            "Ours: k 10-30 and tau 5-20, where Fig. 4A puts the complex regime (k >= 17 at "
            "tau = 10).",
            _axis("k", 10, 30, 40), _axis("tau", 5, 20, 30), delta=1e-6),
    *_pair(5, "(k, tau) plane",
            "From the point of view of spring stiffness, i.e., the deformability of the slope, "
            "and the time delay, distant initial conditions \"stabilize\" the landslide "
            "dynamics (Figure 5). In particular, when the initial conditions are away from the "
            "fixed point, a complex oscillatory regime is pushed towards higher values of k and "
            "tau.",
            "Ours: k 0.5-30 (the Hopf line starts at F'^2/2 = 5.97) and tau 0.1-20.",
            _axis("k", 0.5, 30, 60)),
    *_pair(6, "(a, tau) plane at k = 12",
            "As far as the effect of the friction parameters is concerned, the influence of the "
            "variation of the higher values of the parameter a is similar to the effect of the "
            "slope deformability (Figure 6). [...] It also explains the nearly vertical "
            "small-delay transition line in Figure 6 and Figure 9.",
            "Ours: a 0.1-10 around the default 3.2 (eq. 13a keeps the friction's shape for "
            "2.7 < a < 3.6; the paper explores far outside it).",
            _axis("a", 0.1, 10, 50), k=12),
    *_pair(7, "low a (0.03-0.04), k = 12",
            "At very low values of the parameter a, a new dynamical regime appears, namely, the "
            "unstable regime (Figure 7). The investigated system exhibits such dynamics "
            "regardless of the values of the time delay for the values of the parameter a in "
            "the range of 0.03-0.04. The influence of the initial conditions can further "
            "destabilize the dynamics of the landslide, i.e., the sliding regime with small "
            "time delay (Figure 7B) \"vanishes\" when the initial conditions are away from the "
            "fixed point.",
            "a 0.03-0.04 from the text; k = 12 as in Fig. 6; tau 0.1-20.",
            _axis("a", 0.03, 0.04, 21), k=12),
    *_pair(8, "(b, tau) plane at k = 12",
            "Shifting the initial conditions away from the fixed point interacting with b "
            "destabilizes the dynamics of the landslide. Indeed, the oscillatory regime occurs "
            "at much lower values of b and tau when delta is closer to 0. Moreover, at higher "
            "values of b, the system enters a mixed sliding/oscillatory regime, the extent of "
            "which is largely independent of the initial conditions (Figure 8).",
            "Ours: b 0.5-24 (F'(v) < 0 beyond b = 24.5 at v = 0.1: no damped sliding state), "
            "k = 12 as in Fig. 6.",
            _axis("b", 0.5, 24, 48), k=12),
    *_pair(9, "(c, tau) plane at k = 12",
            "As for the joint effect of the friction parameter c and the change in initial "
            "conditions, the dynamics of the landslide seems to stabilize for initial conditions "
            "away from the fixed point. In particular, it can be seen in Figure 9 that in this "
            "case the complex oscillatory regime occurs for lower values of c than when the "
            "initial conditions are close to the fixed point.",
            "Ours: c 0.1-10 around the default 4.8.",
            _axis("c", 0.1, 10, 50), k=12),
    *_pair(10, "(d, tau) plane at k = 12",
            "The interaction of noise and change in initial conditions is shown in Figure 10. "
            "It appears that moving away from the fixed point stabilizes the dynamics of the "
            "landslide, as complex oscillations only occur for a very narrow range of "
            "parameters when delta is away from 0 (Figure 10B).",
            "Ours: d from 1e-6 to 1 on a log axis (the default is 1e-4).",
            _axis("d", 1e-6, 1, 40, "log"), k=12),
)

BY_KEY = {p.key: p for p in PRESETS}
