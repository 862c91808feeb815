"""The first orbit analysis after an install compiles its kernels for seconds (12.6 s wall
for a cold `slopetui continue` on the shared 2-core machine): the commands say so on
stderr first, and only then."""

from __future__ import annotations

import pytest

from core import jit_cache
from slopetui.cli import main
from slopetui.queue import warm_up


def numba_subfolder(base, core_dir):
    """The folder numba files core's kernels under (named after core's path)."""
    from numba.core.caching import _CacheLocator

    return base / _CacheLocator.get_suitable_cache_subpath(str(core_dir / "__init__.py"))


def test_kernels_compiled_looks_for_this_checkouts_index_files(tmp_path, monkeypatch):
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    assert not warm_up.kernels_compiled()
    other = numba_subfolder(tmp_path, tmp_path / "another-checkout" / "core")
    other.mkdir()
    (other / "period_map.flow-23.py311.nbi").touch()  # compiled for another checkout only
    assert not warm_up.kernels_compiled()
    ours = numba_subfolder(tmp_path, jit_cache.CORE_DIR)
    ours.mkdir()
    (ours / "model.rhs-67.py311.nbi").touch()  # not the analyses' kernel
    assert not warm_up.kernels_compiled()
    (ours / "period_map.flow-23.py311.nbi").touch()
    assert warm_up.kernels_compiled()


class Stop(Exception):
    """Raised where the command would compute (nothing is computed)."""


def stop(*args, **kwargs):
    raise Stop


@pytest.mark.parametrize("command", [["orbit"], ["hysteresis", "--param", "k", "--from", "8",
                                                 "--to", "9"],
                                     ["continue", "--param", "k", "--from-hopf"]])
def test_analyses_say_when_they_compile(command, monkeypatch, capsys):
    monkeypatch.setattr("slopetui.cli.orbit.find_orbit", stop)
    monkeypatch.setattr("core.hysteresis.hysteresis", stop)  # imported when computing
    monkeypatch.setattr("slopetui.cli.continuation.start", stop)
    for compiled, said in ((False, True), (True, False)):
        monkeypatch.setattr(warm_up, "kernels_compiled", lambda modules, c=compiled: c)
        with pytest.raises(Stop):
            main(command)
        err = capsys.readouterr().err
        assert (f"slopetui {command[0]}: compiling kernels (once" in err) is said
        assert ("compiling" in err) is said


