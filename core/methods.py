"""The names of the solver methods (what each is: core.solve, core.euler, core.rk4,
core.stiff).

Its own module, without numpy, so that a command line can offer the names as choices
without loading the engine (as core.regimes holds the regime names).
"""

from __future__ import annotations

METHODS: tuple[str, ...] = ("euler", "rk4", "stiff")
