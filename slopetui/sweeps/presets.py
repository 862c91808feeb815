"""Sweeps that redo the paper's figures, as specs (the New sweep form offers them).

The paper gives the fixed parameters of each figure in its caption but rarely its axis
ranges; where it does not, the range below is ours and the note says why. Resolutions
are modest defaults (the form and `reproduce` can raise them); t_end and dt are the
paper's (Euler, dt = 1e-3, t_end = 1e5, window [99000, 100000]).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

PAPER_SOLVER = {"method": "euler", "dt": 1e-3, "t_end": 1e5, "window": 1000.0, "lyap": True}


@dataclass(frozen=True)
class Preset:
    key: str
    title: str
    note: str
    spec: dict[str, Any]


def _axis(param: str, start: float, stop: float, num: int, spacing: str = "linear") -> dict:
    return {"param": param, "start": start, "stop": stop, "num": num, "spacing": spacing}


def _plane(key: str, title: str, note: str, x: dict, y: dict, **fixed: float) -> Preset:
    return Preset(key, title, note, {"name": title, "x": x, "y": y, "fixed": fixed,
                                     "solver": dict(PAPER_SOLVER)})


PRESETS: tuple[Preset, ...] = (
    Preset("fig4a", "Fig. 4A: bifurcation in k (tau = 10, delta = 0.1)",
           "Caption: sliding k <= 6, oscillatory 6-17, complex k >= 17; k 3-24 covers it.",
           {"name": "Fig. 4A: bifurcation in k (tau = 10, delta = 0.1)",
            "x": _axis("k", 3, 24, 43), "fixed": {"tau": 10, "delta": 0.1},
            "solver": dict(PAPER_SOLVER)}),
    Preset("fig4b", "Fig. 4B: period-doubling zoom, k 17-21 (tau = 10, delta = 0.1)",
           "Caption: four distinct amplitudes up to about k = 20.5.",
           {"name": "Fig. 4B: period-doubling zoom", "x": _axis("k", 17, 21, 41),
            "fixed": {"tau": 10, "delta": 0.1}, "solver": dict(PAPER_SOLVER)}),
    _plane("fig5a", "Fig. 5A: (k, tau) plane, delta = 1e-6",
           "Ours: k 0.5-30 and tau 0.1-30 show the Hopf drop at small tau and the complex "
           "region at large k and tau that the text describes.",
           _axis("k", 0.5, 30, 30), _axis("tau", 0.1, 30, 20), delta=1e-6),
    _plane("fig5b", "Fig. 5B: (k, tau) plane, delta = 0.1",
           "As 5A; far initial conditions push the complex region to higher k and tau.",
           _axis("k", 0.5, 30, 30), _axis("tau", 0.1, 30, 20), delta=0.1),
    _plane("fig6a", "Fig. 6A: (a, tau) plane at k = 12, delta = 1e-6",
           "Ours: a 0.1-10 around the default 3.2; eq. 27 was fitted on this figure.",
           _axis("a", 0.1, 10, 30), _axis("tau", 0.1, 30, 20), k=12, delta=1e-6),
    _plane("fig6b", "Fig. 6B: (a, tau) plane at k = 12, delta = 0.1",
           "As 6A, far from the fixed point.",
           _axis("a", 0.1, 10, 30), _axis("tau", 0.1, 30, 20), k=12, delta=0.1),
    _plane("fig7", "Fig. 7: low a (0.03-0.04), k = 12, delta = 0.1",
           "Text: unstable for a in 0.03-0.04 regardless of tau.",
           _axis("a", 0.03, 0.04, 11), _axis("tau", 0.1, 30, 20), k=12, delta=0.1),
    _plane("fig8a", "Fig. 8A: (b, tau) plane, delta = 1e-6",
           "Ours: b 0-24 (F'(v) < 0 beyond b ~ 24.5 at v = 0.1); the text places a mixed "
           "regime at high b.",
           _axis("b", 0.5, 24, 30), _axis("tau", 0.1, 30, 20), k=12, delta=1e-6),
    _plane("fig8b", "Fig. 8B: (b, tau) plane, delta = 0.1", "As 8A.",
           _axis("b", 0.5, 24, 30), _axis("tau", 0.1, 30, 20), k=12, delta=0.1),
    _plane("fig9a", "Fig. 9A: (c, tau) plane, delta = 1e-6",
           "Ours: c 0.1-10 around the default 4.8.",
           _axis("c", 0.1, 10, 30), _axis("tau", 0.1, 30, 20), k=12, delta=1e-6),
    _plane("fig9b", "Fig. 9B: (c, tau) plane, delta = 0.1", "As 9A.",
           _axis("c", 0.1, 10, 30), _axis("tau", 0.1, 30, 20), k=12, delta=0.1),
    _plane("fig10a", "Fig. 10A: (d, tau) plane, delta = 1e-6",
           "Ours: d on a log axis 1e-6 to 1 (noise intensity).",
           _axis("d", 1e-6, 1, 25, "log"), _axis("tau", 0.1, 30, 20), k=12, delta=1e-6),
    _plane("fig10b", "Fig. 10B: (d, tau) plane, delta = 0.1", "As 10A.",
           _axis("d", 1e-6, 1, 25, "log"), _axis("tau", 0.1, 30, 20), k=12, delta=0.1),
)

BY_KEY = {p.key: p for p in PRESETS}
