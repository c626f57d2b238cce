"""The kernel's compile options: no reference counting where Numba offers it, plain cached
compilation where it does not (dynamics._jit; docs/decisions.md)."""

import importlib

import pytest
from numba.core import cpu

from rvsim.dynamics import _jit


@pytest.mark.skipif(not hasattr(cpu.CPUTargetOptions, "_nrt"),
                    reason="this Numba has no _nrt option (the fallback is tested below)")
def test_no_refcount_where_numba_has_the_option():
    assert _jit.NO_REFCOUNT == {"cache": True, "_nrt": False}


def test_plain_cached_compilation_without_the_option(monkeypatch):
    monkeypatch.setattr(cpu, "CPUTargetOptions", type("OptionsWithoutNrt", (), {}))
    try:
        assert importlib.reload(_jit).NO_REFCOUNT == {"cache": True}
    finally:
        monkeypatch.undo()
        importlib.reload(_jit)
