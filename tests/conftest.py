"""Shared fixtures: the built-in reducer, the paper's reference tables and a CLI runner."""

from __future__ import annotations

import importlib.util
import io
import os
import shutil
import signal
import subprocess
import sys
import tempfile
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import pandas as pd
import pytest

from rvsim.cli import main
from rvsim.parameters import RV40E
from tests._warmup import CHAINS, COMPILE_LOCKS, SECONDS, chains_for

try:
    import fcntl
except ImportError:          # not POSIX: the warm-up runs before the tests instead
    fcntl = None

REFERENCE = Path(__file__).parent / "reference" / "data"


#: the finite-element extra (rvsim[fe]) is installed: scikit-fem and gmsh import
def _has_fe() -> bool:
    try:
        return all(importlib.util.find_spec(name) is not None for name in ("skfem", "gmsh"))
    except ValueError:          # a module set to None in sys.modules (hidden on purpose)
        return False


HAS_FE = _has_fe()
#: the reason FE tests give when they are skipped
NO_FE = "needs the finite-element extra: pip install 'rvsim[fe]'"

#: environment variable naming the test run's one FE cache (set by the first process, so
#: pytest-xdist's workers share it; never the user's own cache)
_TEST_CACHE = "RVSIM_TEST_FE_CACHE"


def pytest_configure(config):
    config.addinivalue_line("markers", "fe: needs the finite-element extra (skipped without it)")
    _default_signals()
    _write_bytecode()
    _one_fe_cache(config)
    _compile_kernels_once(config)


def pytest_unconfigure(config):
    _end_warmup(config)
    folder = getattr(config, "_rvsim_fe_cache", None)
    if folder is not None:
        shutil.rmtree(folder, ignore_errors=True)


def pytest_collection_modifyitems(config, items):
    _order_files(items)
    if HAS_FE:
        return
    skip = pytest.mark.skip(reason=NO_FE)
    for item in items:
        if item.get_closest_marker("fe") is not None:
            item.add_marker(skip)


def _order_files(items) -> None:
    """The order pytest-xdist hands the files out in (``--no-loadscope-reorder``, pyproject):
    the files that need no kernel first, then those that need only the dynamic chain's (they
    run while the rest still compiles), then the others; within each group the longest files
    first (:data:`tests._warmup.SECONDS`, else the number of tests), so that the last files
    handed out are short and both workers finish together.  A file's tests stay together."""
    counts: dict[str, int] = {}
    for item in items:
        counts[item.path.name] = counts.get(item.path.name, 0) + 1

    def key(item):
        name = item.path.name
        return len(chains_for(name)), -SECONDS.get(name, 0.05 * counts[name]), str(item.path)
    items.sort(key=key)     # stable: a file keeps its tests' order


def _one_fe_cache(config) -> None:
    """One FE cache for the whole test run (meshes are built once, not once per test), in a
    temporary folder: the user's ~/.cache/rvsim is neither read nor written.  The process that
    creates it (the only one, or pytest-xdist's controller) removes it at the end; workers
    inherit it through the environment.  Tests that must see a cache miss use the
    ``fresh_fe_cache`` fixture."""
    folder = os.environ.get(_TEST_CACHE)
    if folder is None:
        folder = tempfile.mkdtemp(prefix="rvsim-test-fe-cache-")
        os.environ[_TEST_CACHE] = folder
        config._rvsim_fe_cache = folder
    os.environ["RVSIM_CACHE_DIR"] = folder


def _write_bytecode() -> None:
    """Let the test run keep Python's bytecode caches (``__pycache__``, pytest's rewritten test
    modules) when the environment says not to (``PYTHONDONTWRITEBYTECODE``, set on this project's
    machines): otherwise every xdist worker rewrote all test modules' assertions (about 4.5 s of
    CPU each, measured) and every rvsim process the tests start compiled
    rvsim's sources anew.  The variable is dropped for this process's children too (xdist's
    workers, the warm-up, the CLI processes the tests start)."""
    if os.environ.pop("PYTHONDONTWRITEBYTECODE", None) is not None:
        sys.dont_write_bytecode = False


#: environment variable naming each warm-up chain's lock file, ``chain=path`` joined by
#: os.pathsep (set by the first process, inherited by pytest-xdist's workers)
_WARMUP_LOCKS = "RVSIM_TEST_WARMUP_LOCKS"
#: the tests' scheduling priority below the warm-up's (os.nice; CFS gives a nice-10 process
#: about a tenth of a core beside a nice-0 one)
_TEST_NICENESS = 10


def _compile_kernels_once(config) -> None:
    """Compile the numba kernels into their on-disk cache once, in two background processes
    (tests/_warmup.py), so that no test (and no pair of pytest-xdist workers at once) pays for
    compiling them.  Each chain's process holds an exclusive lock on a file of its own until it
    ends (the lock is taken here and handed down, so no test can look before it is held); a test
    waits for the chains its file needs (:func:`pytest_runtest_setup`), so the tests that need no
    kernel, or only the dynamic chain's, run while the rest still compiles.  Only in the first
    process (not in xdist's workers), not for --collect-only; RVSIM_TEST_NO_WARMUP=1 leaves it
    out.  A warm-up that fails is reported at the end and the tests run anyway (they show the
    fault).  Without POSIX file locks the warm-up runs to its end before the tests."""
    if hasattr(config, "workerinput") or config.option.collectonly \
            or os.environ.get("RVSIM_TEST_NO_WARMUP"):
        return
    root = Path(__file__).resolve().parents[1]
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(
        [str(root / "src"), str(root)] + [os.environ.get("PYTHONPATH", "")]).rstrip(os.pathsep)}
    command = [sys.executable, "-m", "tests._warmup"]
    if fcntl is None:
        sys.stderr.write("rvsim tests: compiling the numba kernels once (a few seconds when "
                         "cached)\n")
        proc = subprocess.run(command, cwd=root, env=env, stdin=subprocess.DEVNULL,
                              stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if proc.returncode != 0:
            _report_warmup("both chains", proc.returncode, proc.stderr)
        return
    sys.stderr.write("rvsim tests: compiling the numba kernels in the background (a few "
                     "seconds when cached); the tests that need them wait\n")
    folder = Path(tempfile.mkdtemp(prefix="rvsim-test-warmup-"))
    env[COMPILE_LOCKS] = str(folder)                 # the chains compile each function once
    chains, locks = [], []
    for chain in CHAINS:
        lock = folder / f"{chain}.lock"
        descriptor = os.open(lock, os.O_RDWR | os.O_CREAT, 0o600)
        fcntl.flock(descriptor, fcntl.LOCK_EX)          # released when the chain's process ends
        log = open(folder / f"{chain}.log", "w+")
        try:
            proc = subprocess.Popen(command + [chain], cwd=root, env=env,
                                    stdin=subprocess.DEVNULL, stdout=log,
                                    stderr=subprocess.STDOUT, pass_fds=(descriptor,))
        finally:
            os.close(descriptor)
        chains.append((chain, proc, log))
        locks.append(f"{chain}={lock}")
    os.environ[_WARMUP_LOCKS] = os.pathsep.join(locks)
    config._rvsim_warmup = (folder, chains)
    # the quasi-static chain is the longest task of the run: the tests (this process, its
    # pytest-xdist workers and their children inherit it) yield the cores to both chains while
    # they compile, so the tests that need no kernel fill the idle time, not the critical path
    try:
        os.nice(_TEST_NICENESS)
    except OSError:
        pass


#: the chains this process has seen end (a test waits for each at most once)
_CHAINS_READY: set[str] = set()


@pytest.hookimpl(tryfirst=True)
def pytest_runtest_setup(item):
    """Before a test and its fixtures: wait for the warm-up chains its file needs."""
    locks = dict(entry.split("=", 1) for entry in
                 os.environ.get(_WARMUP_LOCKS, "").split(os.pathsep) if entry)
    for chain in chains_for(item.path.name):
        if chain in _CHAINS_READY or chain not in locks:
            continue
        with open(locks[chain]) as handle:
            fcntl.flock(handle, fcntl.LOCK_SH)   # free once the chain's process has ended
        _CHAINS_READY.add(chain)


def _end_warmup(config) -> None:
    """Stop a warm-up still running (an interrupted session), report one that failed."""
    folder, chains = getattr(config, "_rvsim_warmup", (None, ()))
    for chain, proc, log in chains:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        elif proc.returncode != 0:
            log.seek(0)
            _report_warmup(f"the {chain} chain", proc.returncode, log.read())
        log.close()
    if folder is not None:
        shutil.rmtree(folder, ignore_errors=True)


def _report_warmup(what: str, code: int, output: str) -> None:
    tail = "\n".join(output.strip().splitlines()[-5:])
    sys.stderr.write(f"rvsim tests: warm-up of {what} failed (exit {code}):\n{tail}\n")


@pytest.fixture
def fresh_fe_cache(tmp_path, monkeypatch):
    """An empty FE cache of this test's own (a cache miss is part of what it checks)."""
    folder = tmp_path / "fe-cache"
    monkeypatch.setenv("RVSIM_CACHE_DIR", str(folder))
    return folder


def _default_signals() -> None:
    """Stop signals at their interactive defaults in the test process (and so in every child it
    starts): a run in a background job (``nohup ... &``, many CI runners) inherits SIGINT and
    SIGHUP as *ignored*, and an ignored signal stays ignored across exec, so the tests that send
    real signals to rvsim processes would see nothing happen.  rvsim itself keeps an ignored
    signal ignored on purpose (tests/unit/test_stopping.py); the tests want the defaults."""
    if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)
    for sig in (signal.SIGTERM, signal.SIGHUP):
        if signal.getsignal(sig) is signal.SIG_IGN:
            signal.signal(sig, signal.SIG_DFL)


@pytest.fixture
def empty_workdir(tmp_path, monkeypatch):
    """An empty working folder for a command (its files, if any, land here)."""
    monkeypatch.chdir(tmp_path)
    return tmp_path


@pytest.fixture
def rv40e():
    return RV40E


def reference_table(name: str) -> pd.DataFrame:
    """A table of shared/reference (copied to tests/reference/data; see its README).

    The last column may hold unquoted commas (free-text notes), so each line is split at most
    header-width - 1 times.
    """
    lines = [ln.rstrip("\n") for ln in (REFERENCE / name).read_text().splitlines()
             if ln.strip() and not ln.startswith("#")]
    header = lines[0].split(",")
    rows = [ln.split(",", len(header) - 1) for ln in lines[1:]]
    frame = pd.DataFrame(rows, columns=header)
    for name in frame.columns:
        try:
            frame[name] = pd.to_numeric(frame[name])
        except ValueError:
            pass  # text column
    return frame


class CliResult:
    def __init__(self, code: int, out: str, err: str):
        self.code, self.out, self.err = code, out, err


def run_cli(*args: str) -> CliResult:
    """Run ``rvsim ARGS`` in-process and capture its exit code and streams."""
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        try:
            code = main(list(args))
        except SystemExit as exc:  # --help / --version exit through argparse
            code = int(exc.code or 0)
    return CliResult(code, out.getvalue(), err.getvalue())


@pytest.fixture
def cli():
    return run_cli
