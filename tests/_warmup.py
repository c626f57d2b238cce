"""Compile rvsim's numba kernels once, while the tests start (``python -m tests._warmup CHAIN``).

The kernels are cached on disk (numba's ``cache=True``, guarded by
``rvsim._cache_guard``), so what one process compiles every later process loads.
Without this, the first test of each kernel in each pytest-xdist worker compiled it, both
workers the same kernels at once (a unit test took 68 s).  ``tests/conftest.py`` starts the
two :data:`CHAINS` of tasks in two background processes, one per core: the quasi-static
solver's (the longest, about 60 % of the compile time) and the dynamic engine's.  Each holds
an exclusive lock on a file of its own until it ends; a test waits (a shared lock) for the
chains its file needs (:func:`chains_for`) before it starts, so the tests that need no kernel
run during the compile and those that need only the dynamic engine start when its chain ends,
on the core the quasi-static chain leaves free (docs/decisions.md, issue 30, third session).
The chains share the force elements: each function is compiled by the first chain that
reaches it, under a per-function file lock (:func:`share_compiles`); the other waits and loads
it from the cache (cold, on an otherwise loaded machine: 252 s of CPU for the two chains
without the locks, 209 s with them), and its core goes to the tests meanwhile.  Each task is
the smallest run that reaches one engine's scheme; with a warm cache a chain takes a few
seconds.  ``python -m tests._warmup`` runs both side by side.
"""
from __future__ import annotations

import os
import sys
import tempfile
import time

#: a short schedule of the dynamic model (the integration tests' own, tests/integration)
SHORT = {"operating.duration": 0.05, "operating.speed_ramp_time": 0.01,
         "operating.load_start": 0.01, "operating.load_ramp_end": 0.02,
         "operating.steady_start": 0.03}

BEARINGS = {"bearings.arm_needles": True, "bearings.support_rollers": True}


def _ltca() -> None:
    from rvsim.parameters import RV40E
    from rvsim.quasistatic import ltca

    ltca(RV40E, positions=16, raise_on_failure=False, allow_aliasing=True)


def _geometry() -> None:
    from rvsim.geometry.cycloid import pin_gaps, profile_of
    from rvsim.parameters import RV40E

    pin_gaps(RV40E, 0.0)                     # the geometry's compiled curve functions
    profile_of(RV40E).points(64)             # the profile's points (rvsim profile, FE meshes)


def _simulate() -> None:
    from rvsim.dynamics import simulate
    from rvsim.parameters import RV40E, with_values

    short = with_values(RV40E, SHORT)
    simulate(short, raise_on_failure=False)
    simulate(short, time_step=7e-6, raise_on_failure=False)        # the step guard


def _implicit() -> None:
    from rvsim.dynamics import simulate
    from rvsim.parameters import RV40E, with_values

    simulate(with_values(RV40E, SHORT), scheme="implicit-bearings", raise_on_failure=False)


def _simulate_others() -> None:
    from rvsim.dynamics import simulate
    from rvsim.parameters import BUILT_IN_SETS, RV40E, with_values

    simulate(with_values(BUILT_IN_SETS["cycloid-drive"], SHORT), raise_on_failure=False)
    simulate(with_values(RV40E, {**SHORT, **BEARINGS}), raise_on_failure=False)


def _efficiency() -> None:
    from rvsim.parameters import RV40E, with_values
    from rvsim.quasistatic import efficiency

    friction = with_values(RV40E, {"friction.mesh_coefficient": 0.05,
                                   "contact.friction_coefficient": 0.05})
    efficiency(friction, speeds_rpm=[500.0], torques=[200.0], positions=8)


def _hysteresis() -> None:
    from rvsim.parameters import RV40E, with_values
    from rvsim.quasistatic import hysteresis

    hysteresis(RV40E, points_per_branch=6, raise_on_failure=False)
    hysteresis(with_values(RV40E, BEARINGS), points_per_branch=6, raise_on_failure=False)


def _others() -> None:
    from rvsim.geometry.cycloid import pin_gaps, undercut_ratio
    from rvsim.parameters import BUILT_IN_SETS, RV40E
    from rvsim.quasistatic import ltca

    pin_gaps(RV40E, 0.0)                     # the geometry's compiled curve functions
    undercut_ratio(RV40E, samples=50)
    ltca(BUILT_IN_SETS["cycloid-drive"], positions=16, raise_on_failure=False,
         allow_aliasing=True)


#: two chains of tasks, one per core (tests/conftest.py): the quasi-static solver's (the longest:
#: ltca compiles the one sweep that efficiency and hysteresis reuse) and the dynamic engine's
CHAINS = {"quasistatic": (_ltca, _efficiency, _hysteresis, _others),
          "dynamic": (_geometry, _simulate, _implicit, _simulate_others)}


#: test files that call only kernels the dynamic chain compiles (traced: the compiled functions
#: each file calls from Python, its child processes included): they start as soon as that chain
#: is cached.  Any file not listed waits for both chains.  A file listed wrongly costs time (it
#: compiles what a chain is compiling), never a wrong result.
DYNAMIC_ONLY = frozenset({
    "test_api_inputs.py", "test_assembly.py", "test_carried_values.py", "test_cli_foundation.py",
    "test_cycloid_geometry.py", "test_dynamics.py", "test_implicit_bearings.py",
    "test_joint_model.py", "test_kernel_gaps.py", "test_layer_moves.py", "test_lost_motion.py",
    "test_mesh_flanks.py", "test_model.py", "test_modification_signs.py", "test_parameters.py",
    "test_part_validity.py", "test_profile_export.py", "test_robust_sn.py", "test_run_report.py",
    "test_run_status.py", "test_simulate_cli.py", "test_stiff_nodes.py", "test_study_store.py",
    "test_table1_sensitivity.py", "test_unit_strings.py",
})
#: test files that call no compiled kernel of the shared cache (the compile-notice and cache
#: guard tests compile in private caches of their own): they run while the chains compile
NO_KERNELS = frozenset({
    "test_analysis.py", "test_cache_guard.py", "test_catalogue.py", "test_compile_watch.py",
    "test_declared_ranges.py", "test_designs.py", "test_files.py", "test_import_layers.py",
    "test_interactions.py", "test_jit_options.py", "test_lazy_imports.py", "test_result.py",
    "test_stopping.py", "test_table3_range_analysis.py", "test_testrig_import.py",
})


#: the test files that take longest (summed test seconds, one worker, warm cache; measured
#: 2026-11-28): handed out first within their group so that no long file is left for last
#: (tests/conftest.py); a file not listed counts 0.05 s a test
SECONDS: dict[str, float] = {
    "test_study_faults.py": 40, "test_cli_process.py": 39, "test_fe.py": 31,
    "test_guide_commands.py": 31,
    "test_tolerance_cli.py": 20, "test_report_browser.py": 17, "test_fe_pin.py": 17,
    "test_dynamics.py": 15, "test_environment_faults.py": 14, "test_single_stage.py": 14,
    "test_stiff_nodes.py": 14, "test_fe_modes.py": 12, "test_fe_holes.py": 11,
    "test_study.py": 11, "test_cache_guard.py": 9, "test_fe_carrier.py": 8,
    "test_analysis.py": 8, "test_hostile_calibrate_and_files.py": 7, "test_bad_inputs.py": 7,
    "test_testrig_cli.py": 7, "test_testrig.py": 6, "test_implicit_bearings.py": 6,
    "test_ring_output.py": 5, "test_fe_engines.py": 5, "test_compile_message.py": 5,
    "test_simulate_cli.py": 5, "test_friction.py": 5,
}


def chains_for(filename: str) -> tuple[str, ...]:
    """The chains a test file waits for (by its file name)."""
    if filename in NO_KERNELS:
        return ()
    if filename in DYNAMIC_ONLY:
        return ("dynamic",)
    return tuple(CHAINS)


#: environment variable naming the folder of the per-function compile locks the two chains share
COMPILE_LOCKS = "RVSIM_TEST_COMPILE_LOCKS"


def share_compiles(folder: str) -> None:
    """Make this process compile each rvsim function (one signature) only if no other chain
    process is compiling it, else wait for that one and load its result from the cache.

    Both chains reach the force elements they share; each compiled them (about 60 s of CPU of
    the cold run).  Here numba's ``Dispatcher.compile`` (which looks in the disk cache before it
    compiles, and saves to it after) runs under an exclusive ``flock`` of a file named after the
    function and signature, so the second process finds the first one's machine code in the
    cache.  The locks are taken caller before callee, following the call graph, which has no
    cycle: no deadlock.  A process that waits leaves its core to the tests.  A function numba
    cannot cache is compiled again by the waiter, as before: a cost, never a wrong result."""
    import fcntl
    import hashlib

    from numba.core.dispatcher import Dispatcher

    original = Dispatcher.compile

    def compile_once(self, sig):
        if not getattr(self.py_func, "__module__", "").startswith("rvsim"):
            return original(self, sig)
        name = f"{self.py_func.__module__}.{self.py_func.__qualname__}{sig}"
        path = os.path.join(folder, hashlib.sha1(name.encode()).hexdigest() + ".lock")
        with open(path, "a") as handle:
            fcntl.flock(handle, fcntl.LOCK_EX)
            return original(self, sig)

    Dispatcher.compile = compile_once


def run_chain(name: str) -> list[tuple[str, float]]:
    """Run one chain's tasks in order; (task, seconds) of each."""
    if os.environ.get(COMPILE_LOCKS):
        share_compiles(os.environ[COMPILE_LOCKS])
    times = []
    for task in CHAINS[name]:
        start = time.perf_counter()
        task()
        times.append((task.__name__.lstrip("_"), time.perf_counter() - start))
    return times


def main() -> None:
    """Both chains side by side, in two spawned processes (nothing of numba's inherited)."""
    import multiprocessing

    with tempfile.TemporaryDirectory(prefix="rvsim-compile-locks-") as locks:
        os.environ.setdefault(COMPILE_LOCKS, locks)
        with multiprocessing.get_context("spawn").Pool(len(CHAINS)) as pool:
            for times in pool.imap_unordered(run_chain, list(CHAINS)):
                print(", ".join(f"{name} {seconds:.1f} s" for name, seconds in times),
                      flush=True)


if __name__ == "__main__":
    if len(sys.argv) > 1:
        print(run_chain(sys.argv[1]))
    else:
        main()
