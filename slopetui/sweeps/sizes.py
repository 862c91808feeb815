"""The sweep size above which the faces ask before queueing (``slopetui submit --yes``,
``slopetui reproduce --yes``, the application's new-sweep form).

Its own module, without numpy (``slopetui.sweeps.spec`` loads it), so that the command
line's parsers can name it in their help without loading it.
"""

from __future__ import annotations

#: A sweep with more runs than this asks for --yes (a 50 x 50 diagram at the paper's
#: t_end is ~1 h on 2 cores; beyond that a typo in num should not fill the queue).
CONFIRM_ABOVE_RUNS = 2500
