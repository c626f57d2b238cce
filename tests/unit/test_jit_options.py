"""The kernel's compile options: no reference counting where Numba offers it, plain cached
compilation where it does not (dynamics._jit; docs/decisions.md)."""

import importlib

from numba.core import cpu

from rvsim.dynamics import _jit


def test_no_refcount_where_numba_has_the_option():
    assert hasattr(cpu.CPUTargetOptions, "_nrt")
    assert _jit.NO_REFCOUNT == {"cache": True, "_nrt": False}


def test_plain_cached_compilation_without_the_option(monkeypatch):
    monkeypatch.setattr(cpu, "CPUTargetOptions", type("OptionsWithoutNrt", (), {}))
    try:
        assert importlib.reload(_jit).NO_REFCOUNT == {"cache": True}
    finally:
        monkeypatch.undo()
        importlib.reload(_jit)
    assert _jit.NO_REFCOUNT == {"cache": True, "_nrt": False}
