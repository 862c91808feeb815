"""Shared fixtures. The numba kernels compile once per machine (cache=True)."""

from __future__ import annotations

import pytest

from core import Params


@pytest.fixture
def paper() -> Params:
    """The paper's defaults (eq. 8, d = 1e-4) at the Fig. 4A point tau = 10, delta = 0.1."""
    return Params()
