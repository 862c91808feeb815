"""``slopetui roots``: the rest state's characteristic roots at one point, and its linear
stability (core.rest_stability)."""

from __future__ import annotations

import argparse
import shutil
import time

from core.params import PARAM_NAMES, ParameterError, Params
from core.rest_stability import rest_roots
from slopetui.cli.arguments.roots import MAX_COUNT
from slopetui.json_text import json_text
from slopetui.provenance import computed_at
from slopetui.sweeps.rest_roots import unstable_count, verdict

#: How the roots are computed, for the JSON's ``solver`` and the text (core.stability).
METHOD = "chebyshev collocation + newton"


def count_of(text: str) -> int:
    """--count as a whole number from 1 to MAX_COUNT; ParameterError naming it."""
    allowed = f"a whole number from 1 to {MAX_COUNT}"
    try:
        n = int(text)
    except ValueError:
        raise ParameterError("count", text, allowed) from None
    if not 1 <= n <= MAX_COUNT:
        raise ParameterError("count", text, allowed)
    return n


def handle(args: argparse.Namespace) -> int:
    params = Params(**{n: getattr(args, n) for n in PARAM_NAMES if getattr(args, n) is not None})
    count = count_of(args.count)
    t0 = time.perf_counter()
    try:
        found = rest_roots(params, count)
    except ArithmeticError as exc:
        raise ParameterError("roots", "", f"a point whose roots can be computed ({exc})") from None
    runtime = time.perf_counter() - t0
    said = verdict(found)
    unstable = unstable_count(found)
    if args.json:
        print(json_text({"roots": [[r.value.real, r.value.imag] for r in found],
                         "factors": [r.factor for r in found],
                         "leading": [found[0].value.real, found[0].value.imag],
                         "stability": said, "unstable_roots": unstable, "runtime_s": runtime,
                         **computed_at(params, {"method": METHOD, "count": count})}))
        return 0
    if args.plot:
        from slopetui.plots.root_plot import render_roots
        size = shutil.get_terminal_size((100, 30))
        print(render_roots([(r.value, r.factor) for r in found],
                           title=f"roots at k = {params.k:g}, tau = {params.tau:g}: {said}",
                           width=size.columns, height=max(size.lines - 2, 12)))
        return 0
    print("point     " + " ".join(f"{n}={getattr(params, n):g}" for n in PARAM_NAMES))
    print(f"roots     the rest state's rightmost ({METHOD}; the m_x shift's zero root left "
          f"out{'; carried to the noisy state, d = ' + format(params.d, 'g') if params.d > 0 else ''}):")
    for r in found:
        print(f"  {r.value.real:+.8e} {r.value.imag:+.8e}i  {r.factor}")
    lead = found[0].value
    print(f"leading   {lead.real:+.6g} ± {abs(lead.imag):.6g}i: {said}"
          + (f" ({unstable} root{'s' if unstable != 1 else ''} with Re > 0 among those shown)"
             if unstable else ""))
    return 0
