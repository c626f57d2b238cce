"""The ``rvsim`` command line: each subcommand reads files, calls one public function, writes.

User errors print one line ``rvsim: error: ...`` on stderr and exit with code 2.
"""

from __future__ import annotations

import argparse
import errno
import io
import os
import sys

from .. import __version__
from .._stopping import check_stop, stop_signals
from ..errors import RvsimError, Terminated
from . import _efficiency, _geometry, _grid, _quasistatic, _simulate, _study, _testrig, _tolerance
from ._common import EXAMPLES, Parser, flush_warnings

__all__ = ["main", "run", "build_parser"]


def build_parser() -> argparse.ArgumentParser:
    parser = Parser(prog="rvsim", description="Transmission error of RV reducers: geometry, "
                    "analytical error model, contact dynamics, quasi-static loaded contact analysis "
                    "and the catalogue tests, designs of experiments.",
                    epilog=EXAMPLES + "rvsim params\n  rvsim sensitivity --json\n  "
                    "rvsim profile --out disc.dxf\n  rvsim simulate --paper-run 2 --json\n  "
                    "rvsim life --params RV-40E-bearings",
                    formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--version", action="version", version=f"rvsim {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=Parser)
    _geometry.register(sub)
    _simulate.register(sub)
    _quasistatic.register(sub)
    _efficiency.register(sub)
    _grid.register(sub)
    _study.register(sub)
    _testrig.register(sub)
    _tolerance.register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run one command; returns the exit code (0 ok, 1 failed run, 2 user error, 130 Ctrl-C,
    143 SIGTERM or SIGHUP)."""
    return _main(argv)[0]


def _main(argv: list[str] | None) -> tuple[int, bool]:
    """(exit code, whether the process may end at once: :func:`_ends_at_once`)."""
    parser = build_parser()
    at_once = False
    flush_warnings(show=False)
    try:
        args = parser.parse_args(argv)
        at_once = _ends_at_once(getattr(args, "command", None), args)
        if not getattr(args, "func", None):
            parser.print_help()
            return 2, at_once
        with stop_signals():
            try:
                code = int(args.func(args) or 0)
            except Exception:
                check_stop()   # an exception a stop signal's became on its way: the stop
                raise
            if code not in (130, 143):   # the command has not said it was stopped:
                check_stop()             # a signal whose exception was swallowed still counts
        sys.stdout.flush()               # a full disk shows here, not lost at the exit
        return code, at_once
    except RvsimError as exc:
        flush_warnings(show=False)       # a refusal is one line
        # one line, whatever a library's text inside it held (SQLite's integrity report)
        print(f"rvsim: error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2, at_once
    except Terminated as exc:
        print(f"rvsim: terminated ({exc})", file=sys.stderr)
        return 143, at_once
    except KeyboardInterrupt:
        print("rvsim: interrupted", file=sys.stderr)
        return 130, at_once
    except BrokenPipeError:
        return 0, at_once
    except MemoryError as exc:
        # numpy's and scipy's own (a finite-element mesh too fine for this machine, a
        # reviewer's fe_element_size 0.4 mm under a 2.5 GB limit): one line, not a traceback
        flush_warnings(show=False)       # an error is one line
        said = " ".join(str(exc).split())
        print(f"rvsim: error: out of memory{f' ({said})' if said else ''}: a coarser "
              "finite-element mesh (flexibility.fe_element_size, fe_crank_element_size) or "
              "shorter histories need less", file=sys.stderr)
        return 1, at_once
    except RuntimeError as exc:
        # a thread the process limit refused (Python's "can't start new thread"), or LLVM's
        # failed allocation under a memory limit (numba's compiler): a resource, in one line
        line = _resource_line(exc)
        if line is None:
            raise
        print(line, file=sys.stderr)
        return 2, at_once
    except (OSError, ImportError) as exc:
        memory = _memory_line(exc)
        if memory is not None:
            print(memory, file=sys.stderr)
            return 2, at_once
        if isinstance(exc, ImportError):
            raise
        if exc.errno in _START_ERRORS:
            print(_resource_line(exc), file=sys.stderr)
            return 2, at_once
        if exc.errno not in _OUTPUT_ERRORS:
            raise
        # standard output on a full disk, a failed device, or closed (>&-)
        flush_warnings(show=False)
        print(f"rvsim: error: cannot write the output ({exc.strerror or exc})", file=sys.stderr)
        return 1, at_once
    finally:
        flush_warnings()                 # the command ran (or stopped): its warnings


#: errors of a write to standard output that end the command with one line
_OUTPUT_ERRORS = frozenset({errno.ENOSPC, errno.EIO, errno.EBADF, errno.EDQUOT, errno.EFBIG})


#: errors of fork / thread start that a resource limit gives (RLIMIT_NPROC, RLIMIT_AS)
_START_ERRORS = frozenset({errno.EAGAIN, errno.ENOMEM})
#: words of an exception raised where a thread or an allocation was refused
_RESOURCE_WORDS = ("can't start new thread", "out of memory", "cannot allocate memory",
                   "bad_alloc", "failed to allocate")


def _resource_line(exc: BaseException) -> str | None:
    """The one line of a resource limit behind ``exc`` (None: not one)."""
    said = " ".join(str(exc).split())
    if isinstance(exc, OSError) and exc.errno in _START_ERRORS or \
            "can't start new thread" in said.lower():
        return (f"rvsim: error: resource limit: cannot start a process or thread ({said}): "
                "raise the process limit (ulimit -u) or the memory limit")
    if any(word in said.lower() for word in _RESOURCE_WORDS):
        return (f"rvsim: error: out of memory ({said}): raise the memory limit (ulimit -v) "
                "or use a coarser finite-element mesh")
    return None


def _memory_line(exc: BaseException) -> str | None:
    """The one line of a compiled library that could not be loaded under a memory limit
    (ulimit -v: llvmlite's shared object under 200 MB said "could not find/load shared
    object" in a 25-line traceback); None without a limit or for another error."""
    import resource

    limit = resource.getrlimit(resource.RLIMIT_AS)[0]
    said = " ".join(str(exc).split()).lower()
    if limit == resource.RLIM_INFINITY or getattr(exc, "errno", None) is not None or not any(
            word in said for word in ("shared object", "load", "cannot allocate memory")):
        return None
    return (f"rvsim: error: out of memory: a compiled library could not be loaded under the "
            f"memory limit of {limit / 1e6:.0f} MB (ulimit -v): raise the limit (rvsim needs "
            "about 1 GB of address space)")


class _ClosedOutput(io.TextIOBase):
    """Standard output when the process was started with it closed (Python then has None)."""

    def write(self, text: str) -> int:
        raise OSError(errno.EBADF, "standard output is closed")


# Commands that start no processes of their own.  Once they have returned, every file they
# write is closed (written atomically), so their process can end without the interpreter's
# teardown of numba, LLVM and the BLAS threads (see docs/benchmarks.md, start-up).
_NO_TEARDOWN = frozenset({"simulate", "ltca", "hysteresis", "efficiency", "sensitivity",
                          "profile", "params"})


# Commands that run on a worker pool: on the local one (no --scheduler) its workers are
# stopped and reaped, its store closed and its files written atomically before they return.
_LOCAL_POOL = frozenset({"study", "tolerance", "allocate", "grid"})


def _ends_at_once(command: str | None, args: argparse.Namespace) -> bool:
    """Whether the process may end without the interpreter's teardown once ``command`` has
    returned: the commands of :data:`_NO_TEARDOWN`, and those of :data:`_LOCAL_POOL` on the
    local worker pool (0.6-0.9 s of teardown after a paper study, docs/benchmarks.md).  On a
    Dask scheduler they end normally, the client closed by the interpreter."""
    if command in _NO_TEARDOWN:
        return True
    return command in _LOCAL_POOL and getattr(args, "scheduler", None) is None


def run() -> None:
    """The ``rvsim`` executable: :func:`main` on ``sys.argv``, then end the process.

    After Ctrl-C the process always ends with code 130: CPython ends a process with SIGINT
    instead when a KeyboardInterrupt once passed through an ``exec`` of a string (dataclasses
    and numba create functions that way), even though rvsim caught it.
    """
    if sys.stdout is None:
        sys.stdout = _ClosedOutput()
    code, at_once = _main(sys.argv[1:])
    if code in (130, 143) or at_once:
        _flush_and_exit(code)
    sys.exit(code)


def _flush_and_exit(code: int) -> None:
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (BrokenPipeError, ValueError, OSError):
            pass
    os._exit(code)


if __name__ == "__main__":
    run()
