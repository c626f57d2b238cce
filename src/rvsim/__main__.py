"""``python -m rvsim`` and the ``rvsim`` executable (both enter at :func:`main`)."""

import os
import sys


#: a process limit below this is a deliberate one: BLAS single-threaded under it
SMALL_NPROC = 1024


def _limited_threads() -> None:
    """One BLAS thread under a memory or process limit, set before numpy is imported.

    OpenBLAS starts a thread per core when numpy is imported, each with its own buffers;
    under a memory limit (RLIMIT_AS of 400 MB) a failed start left it waiting forever,
    deaf to SIGTERM, and under a process limit it printed its failures before Python could
    act (issue 30).  rvsim's own parallelism is its worker processes, not BLAS threads.  A
    thread count the user set is kept."""
    try:
        import resource
    except ImportError:                 # pragma: no cover - not a Unix
        return
    memory = resource.getrlimit(resource.RLIMIT_AS)[0]
    processes = resource.getrlimit(resource.RLIMIT_NPROC)[0] \
        if hasattr(resource, "RLIMIT_NPROC") else resource.RLIM_INFINITY
    # a process limit below SMALL_NPROC is one set on purpose (distributions' defaults for a
    # user are in the tens of thousands)
    if memory != resource.RLIM_INFINITY or processes != resource.RLIM_INFINITY and \
            processes < SMALL_NPROC:
        for name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
            os.environ.setdefault(name, "1")


#: smallest address-space limit (ulimit -v) rvsim starts under [bytes].  Measured 2026-11-28
#: (numpy 2.4, numba 0.68, OpenBLAS): below 270 MB a compiled library cannot be loaded (one
#: line from rvsim.cli), at 300 MB `rvsim params` died of SIGSEGV, at 350 MB `params` and
#: `simulate` spun in native code deaf to SIGTERM, at 500 MB the first `simulate` (compiling
#: its kernel) aborted in LLVM ("out of memory", SIGABRT); at 1000 MB it compiled and ran
MIN_ADDRESS_SPACE = 1000e6


def _memory_floor() -> None:
    """Refuse, in one line and before any compiled library is loaded, a memory limit under
    which the libraries crash or hang instead of raising an error Python could report."""
    try:
        import resource
    except ImportError:                 # pragma: no cover - not a Unix
        return
    limit = resource.getrlimit(resource.RLIMIT_AS)[0]
    if limit != resource.RLIM_INFINITY and limit < MIN_ADDRESS_SPACE:
        print(f"rvsim: error: out of memory: the memory limit of {limit / 1e6:.0f} MB "
              f"(ulimit -v) is below the {MIN_ADDRESS_SPACE / 1e6:.0f} MB rvsim's compiled "
              "libraries need to start (under it they crash or hang): raise the limit",
              file=sys.stderr)
        sys.stderr.flush()
        os._exit(2)


def main() -> None:
    """Import the command line, then run it: a Ctrl-C while it is still being imported ends
    with the command line's own line and code 130, not a traceback."""
    _memory_floor()
    _limited_threads()
    try:
        from .cli import run
    except KeyboardInterrupt:
        print("rvsim: interrupted", file=sys.stderr)
        sys.stderr.flush()
        os._exit(130)       # not sys.exit: see rvsim.cli.run
    run()


if __name__ == "__main__":
    main()
