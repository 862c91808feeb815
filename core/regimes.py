"""The names of the dynamical regimes of Section 3 (what each means: core.classify).

``undetermined``: the window sits at a rest state that linear theory calls unstable, and
where the run is headed could not be decided (core.heading; the reason is in the run's
detail).

Its own module, without numpy, so that a command line can offer the names as choices
without loading the classifier.
"""

from __future__ import annotations

REGIMES: tuple[str, ...] = ("sliding", "oscillatory", "complex", "mixed", "unstable",
                            "undetermined")
#: Not a regime: the label of a lattice cell whose initial conditions end in different
#: regimes (slopetui.sweeps.initial_dependence), the paper's conditionally stable slope.
DEPENDS = "depends"
