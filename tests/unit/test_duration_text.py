"""The one duration formatter: every unit boundary, the unknown, and a clock skew."""

from __future__ import annotations

import math

import pytest

from slopetui.duration_text import duration_text


@pytest.mark.parametrize(("seconds", "fine", "text"), [
    (None, False, "-"), (math.nan, True, "-"), (-3.0, False, "0 s"),
    (0.0123, True, "12 ms"), (2.345, True, "2.35 s"), (59.0, True, "59.00 s"),
    (0.0123, False, "0 s"), (119.4, False, "119 s"), (120.0, False, "2 min"),
    (7199.0, False, "120 min"), (7200.0, False, "2.0 h"), (9000.0, True, "2.5 h"),
])
def test_each_unit_from_its_boundary(seconds, fine, text):
    assert duration_text(seconds, fine=fine) == text
