"""Jobs under a lease: the one lease every kind shares (``leases``), the statements of jobs
computed point by point (``point_jobs``), the continuations and hysteresis sweeps that are
such jobs, and what is left in the queue (``backlog``). The runs' own claims are
``slopetui.store.runs.claims``.
"""
