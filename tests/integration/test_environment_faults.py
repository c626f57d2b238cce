"""Faults of the environment (issue 30): numba's and the finite-element cache folders, the
mesher, resource limits, the finite-element extra missing.  Each ends in one line: a note
and the run going on, or ``rvsim: error: ...`` naming what to fix; tested in real processes
with real signals and limits where the case is about them."""

from __future__ import annotations

import math
import os
import resource
import shutil
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

from rvsim.errors import ParameterError, RvsimError

from .conftest import SRC, default_signals

PACKAGE = Path(SRC) / "rvsim"


def rvsim(args, cwd, env=None, preexec_fn=None, script=None, timeout=120):
    """``python -m rvsim ARGS`` (or ``python -c SCRIPT ARGS``) in ``cwd``: (code, out, err)."""
    command = [sys.executable, "-c", script, *args] if script else \
        [sys.executable, "-m", "rvsim", *args]
    done = subprocess.run(command, cwd=cwd, capture_output=True, text=True, timeout=timeout,
                          env={**os.environ, "PYTHONPATH": SRC, **(env or {})},
                          preexec_fn=preexec_fn, stdin=subprocess.DEVNULL)
    return done.returncode, done.stdout, done.stderr


def one_line(err: str, start: str, *words: str) -> None:
    assert err.startswith(start) and err.count("\n") == 1, err
    assert "Traceback" not in err
    for word in words:
        assert word in err, err


# -- 1. numba's cache folder cannot be written ---------------------------------------------

def read_only_package(tmp_path: Path) -> Path:
    """A copy of the package whose ``__pycache__`` folders cannot be created (a file stands
    in their place: unwritable even for root, who writes into read-only folders)."""
    root = tmp_path / "pkg"
    shutil.copytree(PACKAGE, root / "rvsim", ignore=shutil.ignore_patterns("__pycache__"))
    for folder in [root / "rvsim", *(root / "rvsim").rglob("*")]:
        if folder.is_dir():
            (folder / "__pycache__").write_text("")
    return root


NUMBA_ROWS = {
    # NUMBA_CACHE_DIR not a folder, the package's __pycache__ unwritable, HOME a file
    "NUMBA_CACHE_DIR unwritable": {"NUMBA_CACHE_DIR": "/dev/null/numba", "HOME": "{file}"},
    # no NUMBA_CACHE_DIR and no home folder (numba's user-wide cache under ~ fails)
    "no HOME, no NUMBA_CACHE_DIR": {"NUMBA_CACHE_DIR": None, "HOME": "{file}",
                                    "XDG_CACHE_HOME": "{file}"},
}


@pytest.mark.parametrize("case", NUMBA_ROWS, ids=list(NUMBA_ROWS))
def test_numba_compiles_in_memory_without_a_cache_folder(tmp_path, case):
    # a reviewer's `rvsim profile` ended in "RuntimeError: cannot cache function
    # 'curve_point': no locator available" at import; the import is where it failed
    package = read_only_package(tmp_path)
    (tmp_path / "a_file").write_text("")
    env = {k: v.replace("{file}", str(tmp_path / "a_file")) for k, v in NUMBA_ROWS[case].items()
           if v is not None}
    base = {k: v for k, v in os.environ.items() if k not in NUMBA_ROWS[case]}
    script = ("import rvsim.geometry._curve as c, rvsim.quasistatic._solver as s\n"
              "print(sorted({type(f._cache).__name__ for m in (c, s)\n"
              "              for f in vars(m).values() if hasattr(f, '_cache')}))\n")
    done = subprocess.run([sys.executable, "-c", script], cwd=tmp_path, capture_output=True,
                          text=True, timeout=120, env={**base, **env, "PYTHONPATH": str(package)})
    assert done.returncode == 0, done.stderr
    one_line(done.stderr, "rvsim: note: numba's cache folder cannot be written",
             "compiling in memory", "NUMBA_CACHE_DIR")
    assert done.stdout.strip() == "['NullCache']"        # compiled in memory, each one


# -- 2. the finite-element cache -----------------------------------------------------------

def test_a_damaged_fe_cache_entry_is_rebuilt_once(tmp_path, monkeypatch, capsys):
    # a truncated entry gave a BadZipFile traceback at every later FE run
    from rvsim.fe import cache

    monkeypatch.setenv("RVSIM_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(cache, "_NOTED", set())
    compute = lambda: {"x": np.arange(3.0)}                             # noqa: E731
    cache.cached("t", {"a": 1.0}, compute)
    path = cache.cache_dir() / f"{cache.geometry_key('t', {'a': 1.0})}.npz"
    path.write_bytes(path.read_bytes()[:100])
    assert cache.cached("t", {"a": 1.0}, compute)[2] is False         # rebuilt
    one_line(capsys.readouterr().err, "rvsim: note: finite-element cache: damaged entry",
             "BadZipFile", "rebuilt")
    assert cache.cached("t", {"a": 1.0}, compute)[2] is True          # and read again
    assert capsys.readouterr().err == ""


def test_an_unwritable_fe_cache_runs_uncached_with_one_note(tmp_path, monkeypatch, capsys):
    from rvsim.fe import cache

    (tmp_path / "a_file").write_text("")
    monkeypatch.setenv("RVSIM_CACHE_DIR", str(tmp_path / "a_file"))
    monkeypatch.setattr(cache, "_NOTED", set())
    for kind in ("disc", "crank", "carrier"):                         # three bodies, one note
        arrays, _, cached = cache.cached(kind, {"a": 1.0}, lambda: {"x": np.arange(3.0)})
        assert not cached and list(arrays["x"]) == [0.0, 1.0, 2.0]
    one_line(capsys.readouterr().err, "rvsim: note: finite-element cache: cannot write",
             "running uncached", "RVSIM_CACHE_DIR")


# -- 3. the mesher -------------------------------------------------------------------------

def circle(radius, n=64):
    angle = 2 * math.pi * np.arange(n) / n
    return radius * np.column_stack([np.cos(angle), np.sin(angle)])


def bad_carrier():
    """The reviewer's carrier: radius 40 mm, crank bores of 13 mm at +-45 mm (gmsh meshed it
    forever)."""
    from rvsim.fe.mesh import Circle

    return circle(0.04), [Circle(0.045, 0.0, 0.013), Circle(-0.045, 0.0, 0.013),
                          Circle(0.0, 0.0, 0.02)], 0.0016


REGION_ROWS = {
    "carrier radius 40 mm": (bad_carrier, "beyond the part's outline"),
    "hole outside the part": (lambda: (circle(0.04), [__import__("rvsim.fe.mesh").fe.mesh
                                                      .Circle(0.1, 0.0, 0.005)], 0.002),
                              "beyond the part's outline"),
    "overlapping holes": (lambda: (circle(0.04), [
        __import__("rvsim.fe.mesh").fe.mesh.Circle(0.01, 0.0, 0.008),
        __import__("rvsim.fe.mesh").fe.mesh.Circle(-0.005, 0.0, 0.008)], 0.002), "overlap"),
    "a plate of metres": (lambda: (circle(2.0), [], 0.0016), "more than 1,000,000"),
}


@pytest.mark.parametrize("case", REGION_ROWS, ids=list(REGION_ROWS))
def test_the_mesher_refuses_a_region_it_cannot_mesh(case):
    from rvsim.fe.mesh import mesh_plane_region

    make, words = REGION_ROWS[case]
    outline, holes, size = make()
    with pytest.raises(ParameterError, match=words.replace("(", r"\(")) as caught:
        mesh_plane_region(outline, holes, size, field="cycloid.carrier_radius")
    assert caught.value.field == "cycloid.carrier_radius"


def test_the_carrier_of_the_hostile_review_is_refused_before_meshing():
    from rvsim.fe.carrier import carrier_table
    from rvsim.parameters import RV40E, with_values

    reducer = with_values(RV40E, {"cycloid.carrier_radius": 40, "A": 1,
                                  "flexibility.model": "fe"}, check=False)
    with pytest.raises(ParameterError, match="cycloid.carrier_radius"):
        carrier_table(reducer)


HANG = textwrap.dedent("""
    import sys
    from rvsim._stopping import stop_signals
    from rvsim.fe.mesh import _mesh_plane_region, in_child
    sys.path.insert(0, {tests!r})
    from integration.test_environment_faults import bad_carrier
    print("meshing", flush=True)
    with stop_signals():
        in_child(_mesh_plane_region, *bad_carrier(), seconds=float(sys.argv[1]))
""")


def run_hang(seconds, sig=None, after=0.0):
    """gmsh meshing the bad carrier for real (the region check bypassed) in a process that
    gets ``sig`` ``after`` s once it meshes: (exit code, stderr, seconds from the signal)."""
    script = HANG.format(tests=str(Path(__file__).parents[1]))
    proc = subprocess.Popen([sys.executable, "-c", script, str(seconds)], text=True,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            env={**os.environ, "PYTHONPATH": SRC}, preexec_fn=default_signals())
    try:
        assert proc.stdout.readline() == "meshing\n"
        time.sleep(after)
        start = time.monotonic()
        if sig is not None:
            proc.send_signal(sig)
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    return proc.returncode, err, time.monotonic() - start


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT], ids=["SIGTERM", "SIGINT"])
def test_a_stop_signal_ends_a_mesher_that_hangs(sig):
    # gmsh meshed this carrier at 100 % CPU for 11 minutes, deaf to Ctrl-C and SIGTERM; the
    # signal comes 1 s into the meshing (its child meshes from its first milliseconds)
    code, err, took = run_hang(600, sig, after=1.0)
    assert code != 0 and ("Terminated" in err or "KeyboardInterrupt" in err), err
    assert took < 10


def test_a_mesher_that_hangs_is_stopped_by_its_time_bound():
    code, err, _ = run_hang(1)
    assert code == 1 and "the mesher did not finish in 1 s" in err, err


# -- 4. resource limits --------------------------------------------------------------------

def test_a_process_limit_is_said_in_one_line(empty_workdir, monkeypatch, cli):
    # under ulimit -u a tolerance study said "interrupted" in five lines; fork(2) refused as
    # at the process limit (in this process: the real limit is the test below, run as a user)
    import errno

    def refuse(*args, **kwargs):
        raise BlockingIOError(errno.EAGAIN, "Resource temporarily unavailable")

    monkeypatch.setattr(os, "fork", refuse)
    res = cli("tolerance", "rv40e-tolerances", "--out", "tol", "--samples", "4")
    monkeypatch.undo()
    assert res.code == 2, res.err
    one_line(res.err, "rvsim: error: ", "cannot start a worker process", "Resource temporarily")


@pytest.mark.skipif(os.geteuid() == 0, reason="RLIMIT_NPROC does not bind root")
def test_a_real_process_limit_is_said_in_one_line(tmp_path):
    def limit():
        default_signals()()
        resource.setrlimit(resource.RLIMIT_NPROC, (1, 1))
    code, out, err = rvsim(["tolerance", "rv40e-tolerances", "--out", "tol", "--samples", "4"],
                           tmp_path, preexec_fn=limit)
    assert code == 2, err
    assert err.count("\n") == 1 and "Traceback" not in err and "interrupted" not in err, err


def test_a_thread_refused_is_a_resource_line(monkeypatch, capsys):
    import rvsim.quasistatic
    from rvsim.cli import main

    def refused(*args, **kwargs):
        raise RuntimeError("can't start new thread")

    monkeypatch.setattr(rvsim.quasistatic, "ltca", refused)
    assert main(["ltca", "--positions", "81"]) == 2
    one_line(capsys.readouterr().err, "rvsim: error: resource limit: cannot start a process")


def test_blas_runs_one_thread_under_a_memory_limit(tmp_path):
    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (4 << 30, resource.RLIM_INFINITY))
    script = ("import os, sys; sys.argv = ['rvsim', '--version']\n"
              "from rvsim.__main__ import _limited_threads; _limited_threads()\n"
              "print(os.environ.get('OPENBLAS_NUM_THREADS'))")
    env = {k: v for k, v in os.environ.items() if not k.endswith("NUM_THREADS")}
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          env={**env, "PYTHONPATH": SRC}, preexec_fn=limit, timeout=60)
    assert done.stdout.strip() == "1", done


@pytest.mark.parametrize("megabytes", [100, 200, 300, 350, 500])
def test_a_memory_limit_too_small_to_start_is_one_line(tmp_path, megabytes):
    """Measured under real limits: 100 MB gave OpenBLAS's own failure, 200 MB a 25-line
    llvmlite traceback, 300 MB `rvsim params` died of SIGSEGV, 350 MB it spun deaf to SIGTERM,
    500 MB a cold `simulate` aborted in LLVM: refused before any compiled library loads."""
    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (megabytes << 20, resource.RLIM_INFINITY))
    done = subprocess.run([sys.executable, "-m", "rvsim", "params"], capture_output=True,
                          text=True, env={**os.environ, "PYTHONPATH": SRC}, cwd=tmp_path,
                          preexec_fn=limit, timeout=60)
    assert done.returncode == 2 and done.stdout == ""
    one_line(done.stderr, f"rvsim: error: out of memory: the memory limit of "
                          f"{(megabytes << 20) / 1e6:.0f} MB (ulimit -v) is below the 1000 MB")
    assert list(tmp_path.iterdir()) == []


def test_a_library_that_cannot_load_under_a_limit_is_one_line(monkeypatch, cli):
    """llvmlite's shared object refused under a memory limit above the floor (a 25-line
    traceback under a real 200 MB limit before the floor existed)."""
    from rvsim.cli import _geometry

    def refused(args):
        raise OSError("Could not find/load shared object file 'libllvmlite.so'")

    monkeypatch.setattr(_geometry, "_params", refused)
    monkeypatch.setattr(resource, "getrlimit", lambda kind: (1200 << 20, -1))
    res = cli("params")
    assert res.code == 2
    one_line(res.err, "rvsim: error: out of memory: a compiled library could not be loaded "
                      "under the memory limit of 1258 MB")
    monkeypatch.undo()
    monkeypatch.setattr(_geometry, "_params", refused)
    with pytest.raises(OSError):              # without a limit: not a memory error
        cli("params")


# -- 5. the finite-element extra missing ---------------------------------------------------

NO_FE = textwrap.dedent("""
    import sys
    class Block:
        def find_spec(self, name, path=None, target=None):
            if name.split(".")[0] in ("skfem", "gmsh", "cholespy"):
                raise ModuleNotFoundError(f"No module named {name!r}", name=name)
    sys.meta_path.insert(0, Block())
    sys.argv = ["rvsim", *sys.argv[1:]]
    from rvsim.__main__ import main
    main()
""")

FE_ROWS = {
    "disc only": ["ltca", "--set", "A=1", "--set", "flexibility.fe_crank=false",
                  "--set", "flexibility.fe_carrier=false"],
    "crank only": ["ltca", "--set", "flexibility.fe_carrier=false"],
    "pins": ["ltca", "--set", "B=1", "--set", "flexibility.fe_crank=false",
             "--set", "flexibility.fe_carrier=false"],
}


#: each row of FE_ROWS through the command line's main in one process without the extra
NO_FE_ROWS = NO_FE.replace("""sys.argv = ["rvsim", *sys.argv[1:]]
from rvsim.__main__ import main
main()""", """import contextlib, io, json
from rvsim.cli import main
seen = []
for args in json.loads(sys.argv[1]):
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        seen.append([main(args), err.getvalue()])
print(json.dumps(seen))""")
assert NO_FE_ROWS != NO_FE
FE_ONE_LINE = "rvsim: error: flexibility.model: the finite-element route needs"


def test_fe_without_the_extra_is_one_line(tmp_path):
    # the crank's path imported scikit-fem before the check: a traceback (the defaults: disc,
    # crank and carrier; a real process, its exit code and its stderr)
    code, out, err = rvsim(["ltca", "--set", "A=1", "--set", "flexibility.model=fe",
                            "--positions", "81"], tmp_path,
                           env={"RVSIM_CACHE_DIR": str(tmp_path / "cache")}, script=NO_FE)
    assert code == 2, err
    one_line(err, FE_ONE_LINE, "pip install 'rvsim[fe]'")


def test_each_fe_route_without_the_extra_is_one_line(tmp_path):
    """The disc, the crank and the pins alone, one after the other in one process (the
    command line's main, as the test above runs it through ``python -m rvsim``)."""
    import json

    rows = [[*args, "--set", "flexibility.model=fe", "--positions", "81"]
            for args in FE_ROWS.values()]
    code, out, err = rvsim([json.dumps(rows)], tmp_path,
                           env={"RVSIM_CACHE_DIR": str(tmp_path / "cache")}, script=NO_FE_ROWS)
    assert code == 0 and err == "", err
    for case, (code, err) in zip(FE_ROWS, json.loads(out)):
        assert code == 2, (case, err)
        one_line(err, FE_ONE_LINE, "pip install 'rvsim[fe]'")


def test_fe_extra_check_in_the_python_api(monkeypatch):
    from rvsim.fe import _extra

    monkeypatch.setattr(_extra, "MODULES", ("no_such_module_rvsim",))
    from rvsim.fe.elasticity import PlaneStressBody

    with pytest.raises(RvsimError, match=r"rvsim\[fe\]"):
        PlaneStressBody(np.zeros((2, 3)), np.array([[0], [1], [2]]), 2e11, 0.3, 0.01)


def test_a_study_meshes_in_its_workers(tmp_path, cli, fresh_fe_cache):
    """A study's workers are daemonic processes, which may start no child: the mesher's child
    process made every run of an FE study on the local pool fail ("daemonic processes are not
    allowed to have children"); in a worker the mesher runs in the worker itself."""
    study = tmp_path / "fe.toml"
    study.write_text('name = "fe"\ndesign = "L4"\nengine = "quasi-static"\n[set]\n'
                     '"flexibility.model" = "fe"\n"flexibility.cycloid_disc" = true\n'
                     '"flexibility.fe_element_size" = 4.0\n'
                     '"flexibility.fe_segments_per_tooth" = 2\n'
                     '"flexibility.fe_crank" = false\n"flexibility.fe_carrier" = false\n'
                     '[factors.H]\nparameter = "H"\nlevels = [0.0, 0.01]\n'
                     '[factors.I]\nparameter = "I"\nlevels = [0.0, 0.01]\n')
    res = cli("study", str(study), "--out", str(tmp_path / "out"), "--workers", "2",
              "--no-progress")
    assert res.code == 0, res.err
    import pandas as pd

    results = pd.read_csv(tmp_path / "out" / "results.csv")
    assert len(results) == 4 and (results["status"] == "ok").all()
    assert any(fresh_fe_cache.rglob("*.npz"))            # the workers meshed, and stored it
