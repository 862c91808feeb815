"""Axis labels of the model parameters, and stored text made safe to draw.

The model is dimensionless (core/params.py: "All quantities are in the paper's
dimensionless model units"; the paper attaches no physical units), so a label gives the
symbol and its meaning, and a unit only where one exists in model terms (tau is a time).
The meanings are those of core.params.Params.

Stored text (a sweep's name) may hold anything another user or tool wrote: control
characters are escaped as on the terminal (slopetui.display_text.terminal_safe), and a
dollar sign is escaped so that matplotlib does not read a pair of them as mathtext (a
name such as "cost $5 to $10" would otherwise be typeset, or fail to parse at save time).
"""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType

from slopetui.display_text import terminal_safe
from slopetui.sweeps.run_labels import SHOWN_AS

#: What each parameter is (core.params.Params), with its model unit where it has one.
MEANINGS: Mapping[str, str] = MappingProxyType({
    "a": "friction coefficient of v³ (eq. 1)",
    "b": "friction coefficient of v² (eq. 1)",
    "c": "friction coefficient of v (eq. 1)",
    "d": "noise intensity",
    "k": "spring stiffness",
    "v": "steady sliding velocity",
    "tau": "delay (model time units)",
    "delta": "initial offset (eq. 19)",
})

#: The quantities of the run figures (model units: time in model time units).
TIME_LABEL = "t (model time units)"
FREQUENCY_LABEL = "frequency (cycles per time unit)"
MX_LABEL = "$m_x$ − trend"
MY_LABEL = "$m_y$"
PEAKS_LABEL = "peaks of $m_y$"
LAMBDA_LABEL = "running λ(t) (1 / time unit)"
POWER_LABEL = "log$_{10}$ power of $m_y$"


def time_label(origin: float = 0.0) -> str:
    """TIME_LABEL, or for a time axis drawn from ``origin`` (canvas.time_origin)
    "t − 100000 (model time units)"."""
    if origin == 0.0:
        return TIME_LABEL
    shown = str(int(origin)) if origin.is_integer() and abs(origin) < 1e15 else f"{origin:.10g}"
    sign = "−" if origin > 0 else "+"
    return f"t {sign} {shown.lstrip('-')} (model time units)"


def symbol(param: str) -> str:
    """The parameter's symbol as the paper writes it (τ for tau: run_labels.SHOWN_AS);
    any other name as it is, made plain."""
    return SHOWN_AS.get(param) or plain(param)


def axis_label(param: str) -> str:
    """"k, spring stiffness", "τ, delay (model time units)": the axis of a parameter."""
    meaning = MEANINGS.get(param)
    return f"{symbol(param)}, {meaning}" if meaning else symbol(param)


def plain(text: object) -> str:
    """Text drawn as it is: control characters escaped, dollar signs not mathtext."""
    return terminal_safe(text).replace("$", r"\$")
