"""The warm-up's marker (core.jit_cache.mark_warm, warmed) and the pool's warm-up that
trusts it (slopetui.queue.warm_up.pool_warm_up): a pool skips its serial warm-up only
while the kernel cache is what a finished warm-up left, for this interpreter and CPU."""

from __future__ import annotations

import json
import logging
import os
import time

import pytest

from core import jit_cache
from slopetui.queue import warm_up


@pytest.fixture
def folder(tmp_path, monkeypatch):
    """A kernel folder of the test's own (NUMBA_CACHE_DIR), holding one index and one
    kernel as numba names them."""
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    kernels = tmp_path / "core_0123"
    kernels.mkdir()
    (kernels / "rk4.steps-10.py311.nbi").write_bytes(b"index")
    (kernels / "rk4.steps-10.py311.1.nbc").write_bytes(b"kernel")
    return kernels


def test_a_marked_cache_is_warm_until_anything_in_it_changes(folder):
    assert not jit_cache.warmed()  # never marked
    jit_cache.mark_warm()
    assert jit_cache.warmed()
    kernel = folder / "rk4.steps-10.py311.1.nbc"
    kernel.write_bytes(b"recompiled")  # another size: a compilation since
    assert not jit_cache.warmed()
    jit_cache.mark_warm()
    (folder / "rk4.steps-10.py311.2.nbc").write_bytes(b"kernel")  # a new signature
    assert not jit_cache.warmed()
    jit_cache.mark_warm()
    stat = kernel.stat()
    os.utime(kernel, ns=(stat.st_atime_ns, stat.st_mtime_ns + 1))  # rewritten, same size
    assert not jit_cache.warmed()


def test_a_marker_for_another_machine_or_engine_file_is_not_trusted(folder, monkeypatch):
    jit_cache.mark_warm()
    monkeypatch.setenv("NUMBA_CPU_NAME", "generic")  # numba keys kernels on the CPU
    assert not jit_cache.warmed()
    monkeypatch.delenv("NUMBA_CPU_NAME")
    assert jit_cache.warmed()
    marker = folder.parent / jit_cache.WARM_MARKER
    recorded = json.loads(marker.read_text())
    recorded["sources"]["model.py"][1] -= 1  # the engine file touched since
    marker.write_text(json.dumps(recorded))
    assert not jit_cache.warmed()
    marker.write_text("{")  # cut short
    assert not jit_cache.warmed()


def test_an_empty_cache_is_never_marked(tmp_path, monkeypatch):
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    jit_cache.mark_warm()  # numba cached nothing: nothing to vouch for
    assert not (tmp_path / jit_cache.WARM_MARKER).exists() and not jit_cache.warmed()


def test_the_pool_warms_up_and_marks_then_skips_while_the_marker_holds(folder, monkeypatch,
                                                                      caplog):
    calls = []
    monkeypatch.setattr(warm_up, "warm_up", lambda: calls.append("warm-up"))
    with caplog.at_level(logging.INFO, logger="slopetui"):
        assert warm_up.pool_warm_up(lambda: False) is not None
        assert calls == ["warm-up"] and jit_cache.warmed()
        assert warm_up.pool_warm_up(lambda: False) is not None
        assert calls == ["warm-up"]  # skipped
        assert "numba's cache holds every kernel" in caplog.text
        (folder / "euler.steps-20.py311.nbi").write_bytes(b"index")  # compiled since
        assert warm_up.pool_warm_up(lambda: False) is not None
    assert calls == ["warm-up", "warm-up"] and jit_cache.warmed()


def test_a_pool_stopped_during_its_warm_up_leaves_no_marker(folder, monkeypatch):
    monkeypatch.setattr(warm_up, "warm_up", lambda: time.sleep(5))
    assert warm_up.pool_warm_up(lambda: True) is None
    assert not (folder.parent / jit_cache.WARM_MARKER).exists()
