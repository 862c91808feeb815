"""A request's fields read from text, for the checks that the CLI's flags and the
application's forms share (continuation_request, hysteresis_request): each refusal a
ParameterError naming the field (as the CLI names its flag) and its range."""

from __future__ import annotations

import math

from core.params import ParameterError, Params


def number(flag: str, text: object, params: Params | None = None, name: str = "") -> float:
    """A finite number; with ``params``, a value of the parameter ``name`` (Params names
    its range)."""
    try:
        value = float(str(text))
    except ValueError:
        raise ParameterError(flag, text, "a finite number") from None
    if not math.isfinite(value):
        raise ParameterError(flag, text, "a finite number")
    if params is not None:
        params.with_(**{name: value})  # raises ParameterError naming the parameter's range
    return value


def whole(flag: str, text: str, low: int, high: int) -> int:
    """An integer from ``low`` to ``high``."""
    allowed = f"an integer from {low} to {high}"
    try:
        value = int(text)
    except ValueError:
        raise ParameterError(flag, text, allowed) from None
    if not low <= value <= high:
        raise ParameterError(flag, value, allowed)
    return value
