"""How long something took or will take, as text: the one formatter of every duration
the tool prints (the SQL console's query time, the sweeps' ETA, a pool's uptime and a
worker's age, the estimate of a sweep, the report's generation time).

A leaf with no imports of the project's own: anyone may import it.
"""

from __future__ import annotations

import math


def duration_text(seconds: float | None, *, fine: bool = False) -> str:
    """``seconds`` in the unit a reader takes in at a glance: "45 s", "12 min", "2.5 h";
    "-" when unknown (None or NaN). ``fine``: below a minute to the millisecond, for a
    query's time ("850 ms", "2.35 s"). Negative values (clocks of two hosts) count as 0."""
    if seconds is None or math.isnan(seconds):
        return "-"
    seconds = max(seconds, 0.0)
    if fine and seconds < 1:
        return f"{seconds * 1000:.0f} ms"
    if fine and seconds < 60:
        return f"{seconds:.2f} s"
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"
