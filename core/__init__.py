"""slopetui's numerical engine: the mean-field spring-block model of a conditionally
stable slope (eqs. 6a-6e of the seed paper), its solvers, lambda_max, linear stability
and regime classification. Pure computation: no database, no UI.
"""

from core import jit_cache

jit_cache.configure()  # before the kernels below are decorated

from core.classify import REGIMES, Summary, classify
from core.lyapunov import LyapunovEstimate
from core.params import PARAM_NAMES, ParameterError, Params, friction_warnings
from core.point import PointResult, run_batch, run_point
from core.solve import METHODS, SolverSettings, Trajectory, simulate

__all__ = [
    "METHODS", "PARAM_NAMES", "REGIMES", "LyapunovEstimate", "ParameterError", "Params",
    "PointResult", "SolverSettings", "Summary", "Trajectory", "classify", "friction_warnings",
    "run_batch", "run_point", "simulate",
]
