"""What the warm-up runs (slopetui.queue.warm_up.warm_up): every kernel a worker can
call, the batched one (core.batch) included, so that the pool compiles them serially
before its workers start (numba#10128) and the workers only load them."""

from __future__ import annotations

from collections import Counter

import core.point
from core.batch import MIN_LANES
from core.solve import make_grid
from slopetui.queue import warm_up


def test_the_warm_up_reaches_the_batched_kernel_of_each_explicit_method(monkeypatch):
    """core.batch.simulate_batch gives a group of fewer than MIN_LANES points of one grid
    (one tau) to the single-run kernel: a warm-up batch of two taus never compiled the
    batched kernel, which every worker then compiled at once at its first real batch
    (~12 s of CPU each)."""
    batches, points = [], []
    monkeypatch.setattr(core.point, "run_batch", lambda ps, s: batches.append((list(ps), s)))
    monkeypatch.setattr(core.point, "run_point", lambda p, s: points.append((p, s)))
    warm_up.warm_up()
    widest = {}
    for ps, s in batches:
        groups = Counter(make_grid(p, s) for p in ps)
        widest[s.method] = max(widest.get(s.method, 0), *groups.values())
    assert widest["euler"] >= MIN_LANES and widest["rk4"] >= MIN_LANES, widest
    assert {s.method for _, s in points} == {"euler", "rk4", "stiff"}
