"""The kernel's compile options: no reference counting where Numba offers it, plain cached
compilation where it does not, numpy's error model throughout (rvsim._jit;
docs/decisions.md)."""

import importlib

import pytest
from numba.core import cpu

from rvsim import _jit

HAS_NRT_OPTION = hasattr(cpu.CPUTargetOptions, "_nrt")


@pytest.mark.skipif(not HAS_NRT_OPTION,
                    reason="this Numba has no _nrt option (the fallback is tested below)")
def test_no_refcount_where_numba_has_the_option():
    assert _jit.NO_REFCOUNT == {"cache": True, "error_model": "numpy", "_nrt": False}
    assert _jit.REFCOUNT == {"cache": True, "error_model": "numpy", "_nrt": True}


@pytest.mark.skipif(not HAS_NRT_OPTION, reason="this Numba has no _nrt option")
def test_step_loop_counts_no_references_and_allocating_callees_do():
    # Numba's callees inherit the caller's reference counting: the step loop and the bearings
    # it calls every step go without, the functions that allocate set it back explicitly
    from rvsim.dynamics import _kernel, _stiff_nodes
    from rvsim.physics import _crank_bearings, _fe_carrier, _pins

    for function in (_kernel._advance, _crank_bearings.crank_bearings, _pins.pin_loop):
        assert function.targetoptions["_nrt"] is False, function.__name__
    for function in (_kernel.integrate, _pins.ring_pins, _pins.coupled_pins,
                     _crank_bearings.arm_pair, _fe_carrier.plate_supports,
                     _stiff_nodes.node_omega_dt):
        assert function.targetoptions["_nrt"] is True, function.__name__


def _kernel_functions():
    """Every compiled function of the kernel's modules that is not inlined."""
    import importlib
    import pkgutil

    import rvsim.dynamics
    import rvsim.physics
    names = ["rvsim.geometry._curve"] + [
        f"{package.__name__}.{m.name}" for package in (rvsim.physics, rvsim.dynamics)
        for m in pkgutil.iter_modules(package.__path__)
        if m.name.startswith("_") and m.name != "_layout"]
    found = []
    for name in names:
        module = importlib.import_module(name)
        for attribute, value in vars(module).items():
            options = getattr(value, "targetoptions", None)
            if options is None or getattr(value, "__module__", name) != name:
                continue
            if options.get("inline", "never") == "always":
                continue                 # compiled into its caller, with the caller's options
            found.append((f"{name}.{attribute}", options))
    return found


def test_every_kernel_function_states_its_options():
    # Numba keys a compiled function by its argument types only: one that set neither option
    # would keep those of whichever function compiled it first (docs/decisions.md)
    functions = _kernel_functions()
    assert len(functions) > 80
    for name, options in functions:
        assert options.get("error_model") == "numpy", name
        if HAS_NRT_OPTION:
            assert "_nrt" in options, name


def test_plain_cached_compilation_without_the_option(monkeypatch):
    monkeypatch.setattr(cpu, "CPUTargetOptions", type("OptionsWithoutNrt", (), {}))
    try:
        module = importlib.reload(_jit)
        assert module.NO_REFCOUNT == {"cache": True, "error_model": "numpy"}
        assert module.REFCOUNT == {"cache": True, "error_model": "numpy"}
    finally:
        monkeypatch.undo()
        importlib.reload(_jit)
