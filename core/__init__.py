"""slopetui's numerical engine: the mean-field spring-block model of a conditionally
stable slope (eqs. 6a-6e of the seed paper), its solvers, lambda_max, linear stability
and regime classification. Pure computation: no database, no UI.

The names below are imported on first use (PEP 562): ``from core import PARAM_NAMES``
must not pay ~1 s for numba and the kernels, which ``slopetui --help`` and ``slopetui
status`` never run. The numba cache folder is set by ``core.model``, which every kernel
module imports before it decorates a kernel (see ``core.jit_cache``).
"""

from __future__ import annotations

import importlib
import sys
import types
from typing import TYPE_CHECKING, Any

#: Public name -> the module that defines it.
_EXPORTS = {
    "REGIMES": "core.regimes", "Summary": "core.classify", "classify": "core.classify",
    "LyapunovEstimate": "core.lyapunov",
    "PARAM_NAMES": "core.params", "ParameterError": "core.params", "Params": "core.params",
    "friction_warnings": "core.params",
    "PointResult": "core.point", "run_batch": "core.point", "run_point": "core.point",
    "METHODS": "core.methods", "SolverSettings": "core.solve", "Trajectory": "core.solve",
    "simulate": "core.solve",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str) -> Any:
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'core' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value  # later look-ups skip this function
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *_EXPORTS})


class _Engine(types.ModuleType):
    """``core.classify`` is a submodule and the function it defines. Importing the
    submodule sets the package attribute to the module (the import system does that),
    which would hide the function from ``from core import classify``; the function wins,
    as it did when this package imported everything eagerly."""

    def __setattr__(self, name: str, value: Any) -> None:
        if isinstance(value, types.ModuleType) and _EXPORTS.get(name) == value.__name__:
            value = getattr(value, name)
        super().__setattr__(name, value)


sys.modules[__name__].__class__ = _Engine


if TYPE_CHECKING:  # for type checkers and editors: the same names, eagerly
    from core.classify import Summary, classify
    from core.lyapunov import LyapunovEstimate
    from core.methods import METHODS
    from core.params import PARAM_NAMES, ParameterError, Params, friction_warnings
    from core.point import PointResult, run_batch, run_point
    from core.regimes import REGIMES
    from core.solve import SolverSettings, Trajectory, simulate
