"""slopetui's numerical engine: the mean-field spring-block model of a conditionally
stable slope (eqs. 6a-6e of the seed paper), its solvers, lambda_max, linear stability
and regime classification. Pure computation: no database, no UI.

Inside the project every name is imported from the module that defines it (``from
core.params import Params``), so that what a module costs is what it imports.
``core.params``, ``core.methods``, ``core.regimes`` and ``core.result_fields`` load
neither numpy nor numba (the command line's parser reads them); ``core.point`` and the
solvers load numba and the kernels (~0.5 s). The numba cache folder is set by
``core.model``, which every kernel module imports before it decorates a kernel (see
``core.jit_cache``).

For scripts and notebooks the documented names (``from core import Params,
SolverSettings, run_point``) are also the package's, imported on first use (PEP 562), so
that ``import core`` costs nothing. The classifier is not among them: its function and
its module share the name ``classify``, and once the module is imported the package
attribute is the module; import it as ``from core.classify import classify``.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

#: Public name -> the module that defines it.
_EXPORTS = {
    "REGIMES": "core.regimes", "Summary": "core.classify",
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


if TYPE_CHECKING:  # for type checkers and editors: the same names, eagerly
    from core.classify import Summary
    from core.lyapunov import LyapunovEstimate
    from core.methods import METHODS
    from core.params import PARAM_NAMES, ParameterError, Params, friction_warnings
    from core.point import PointResult, run_batch, run_point
    from core.regimes import REGIMES
    from core.solve import SolverSettings, Trajectory, simulate
