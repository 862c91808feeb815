"""A two-parameter continuation's request checked from text: ``slopetui continue --param P
--param2 Q``'s flags, each refusal a ParameterError naming the flag and its range. No UI
here, and no numpy: the command line imports it at start.

Four curves start here: the fold of cycles (``--from-fold``: the fold of the branch in P
born at the N-th Hopf point, continued in (P, Q) by core.fold_continuation's minimally
augmented system), the Hopf curve with its first Lyapunov coefficient (``--from-hopf``: the
Hopf point in P at values of Q --max-step apart, core.lyapunov_coefficient, and the Bautin
points where l1 changes sign), and the period-doubling and torus curves (``--from-pd``,
``--from-ns``: from the first real such crossing on the branch in P from the N-th Hopf
point, followed up to --to; core.flip_continuation, core.torus_continuation).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from core.params import ParameterError, Params
from slopetui.sweeps.continuation_request import CONTINUABLE, MAX_POINTS, max_step
from slopetui.sweeps.request_fields import number, whole

if TYPE_CHECKING:
    from core.curve_start import CurveSpec

#: The parameters a Hopf curve is traced in: those with a Hopf point to start from
#: (core.hopf_start: k, tau and the friction parameters a, b, c). A fold curve starts in any
#: (core.fold_start reaches a fold in d or v along the fold surface from one in k).
STARTS_IN = ("k", "tau", "a", "b", "c")
#: The curves a request may start (core.curve_start.STARTS, not imported: numpy).
STARTS = ("fold", "hopf", "pd", "ns")
#: The curves that start from a crossing found on the branch from a Hopf point: --to is
#: where that branch is followed to, looking for it.
FROM_BRANCH = {"pd": "period doubling", "ns": "torus bifurcation"}
#: The most Hopf-curve points: each is four corrected small orbits (~0.1 to 0.3 s).
MAX_HOPF_POINTS = 400


def curve_spec(params: Params, dt: float, param: str, param2: str, start: str,
               to2: str | None, points: str, step: str, hopf_branch: int = 1,
               to: str | None = None) -> CurveSpec:
    """The request, checked: ParameterError naming the flag (param2, to2, from-..., points,
    max-step, to) and what it allows. ``to``: a period-doubling or torus curve's branch
    end (where the branch from the Hopf point is followed to, looking for that crossing)."""
    if param2 not in CONTINUABLE or param2 == param:
        raise ParameterError("param2", param2,
                             f"one of {', '.join(n for n in CONTINUABLE if n != param)}")
    if start not in STARTS:
        raise ParameterError("from", start, "--from-fold, --from-hopf, --from-pd or --from-ns")
    if start != "fold" and param not in STARTS_IN:
        raise ParameterError("param", param, f"one of {', '.join(STARTS_IN)} with --param2 "
                             f"--from-{start} (its branch starts at a Hopf point in it)")
    branch_end = None
    if start in FROM_BRANCH:
        if to is None:
            raise ParameterError("to", "", f"a value of {param}: how far the branch from the "
                                 f"Hopf point is followed, looking for its {FROM_BRANCH[start]}")
        branch_end = number("to", to, params, param)
    if to2 is None:
        raise ParameterError("to2", "", f"a value of {param2} where the curve ends")
    end = number("to2", to2, params, param2)
    if end == getattr(params, param2):
        raise ParameterError("to2", to2, f"a value other than the start, {param2} = {end:g}")
    if param2 == "tau" and end <= 0:
        raise ParameterError("to2", to2, "tau > 0: there is no Hopf point without a delay")
    n = whole("points", points, 2, MAX_HOPF_POINTS if start == "hopf" else MAX_POINTS)
    largest = max_step(step)
    from core.curve_start import CurveSpec, hopf_count  # numpy: module docstring
    if start == "hopf" and hopf_count(getattr(params, param2), end, largest) > n:
        raise ParameterError("max-step", step, f"at least {abs(end - getattr(params, param2)) / (n - 1):.4g} "
                             f"(the Hopf curve's {n} points, --points, span {param2} "
                             f"from {getattr(params, param2):g} to {end:g})")
    return CurveSpec(params, param, param2, start, dt, end, n, largest, hopf_branch,
                     branch_end)
