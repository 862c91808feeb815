"""Python's garbage collection kept out of the way of drawing.

Measured with a 100 x 100 sweep open (benchmarks/bench_tui.py): each switch of screens
leaves ~2,000 objects in reference cycles (on every resume Textual derives the
component styles of the DataTables, the Header and the Footer anew, each a DOMNode with
its Styles and caches), and CPython's automatic full collections gathered them by tens of
thousands among the ~140,000 objects of the application, in pauses of 90 to 230 ms: one
switch in about twenty took three times as long as the others.

Two remedies. Once the application has started (its first diagram drawn), ``settle``
moves the objects that exist by then out of every later collection (``gc.freeze``: they
are still freed by reference counting; one that ends up in a cycle would stay, a bounded
cost paid once). And once a screen switched to has been drawn, ``collect`` gathers that
switch's garbage while the user looks at the screen: 2 to 8 ms for up to ~2,600 objects,
instead of a long pause at a moment nobody chose.
"""

from __future__ import annotations

import gc

_settled = False


def settle() -> None:
    """Leave the objects of start-up out of later collections (once; module docstring)."""
    global _settled
    if not _settled:
        gc.collect()  # what start-up left as garbage is not kept forever
        gc.freeze()
        _settled = True


def collect() -> None:
    """Gather what the last switch of screens left (module docstring)."""
    gc.collect()
