"""slopetui's numerical engine: the mean-field spring-block model of a conditionally
stable slope (eqs. 6a-6e of the seed paper), its solvers, lambda_max, linear stability
and regime classification. Pure computation: no database, no UI.

The package exports nothing: a name is imported from the module that defines it
(``from core.params import Params``, ``from core.point import run_point``), so that what
a module costs is what it imports. ``core.params``, ``core.methods``, ``core.regimes`` and
``core.result_fields`` load neither numpy nor numba (the command line's parser reads
them); ``core.point`` and the solvers load numba and the kernels (~0.5 s). The numba cache
folder is set by ``core.model``, which every kernel module imports before it decorates a
kernel (see ``core.jit_cache``).
"""
