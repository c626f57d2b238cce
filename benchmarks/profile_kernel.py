"""Where a dynamic run spends its time, by compiled function (issue 14).

Samples one paper L36 run with Linux ``perf`` and names the numba-compiled functions, which
perf cannot name by itself: the script compiles the kernel afresh in a temporary numba cache
(so that every callee has its own compiled overload to look up), writes their addresses to
``/tmp/perf-PID.map`` (perf's map of JIT code), then samples ``--seconds`` of a second run of
the same simulation and prints the shares of the functions, libm's included (``__sincos``,
``__ieee754_pow`` / ``log``) and Numba's reference counting (``NRT_incref`` / ``NRT_decref``).

Inlined functions count in their callers (the step loop inlines ``forces_with``), and code
the script cannot name (a compiled function without a dispatcher of its own) counts in the
named function below it in memory, since perf's map gives each name the span up to the
next: the shares by function are approximate, those of libm's functions exact.  Shares
are of the samples of the whole process over the window (a few % of Python's garbage
collector can show up: the profiling run itself leaves garbage).  Needs ``perf`` (Debian's
``linux-perf``) and permission to sample (root, or ``kernel.perf_event_paranoid`` <= 1).

``--scheme implicit-bearings`` profiles that integration scheme instead of the explicit one
(the profiled process repeats the run until the sampled window has passed).

Usage:  python benchmarks/profile_kernel.py [--run 3] [--seconds 2] [--top 25]
                                            [--scheme explicit]
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time


def _child(run: int, ready: str, scheme: str, seconds: float) -> None:
    """The profiled process: compile, map, signal, simulate (again until ``seconds`` have
    passed)."""
    from rvsim.dynamics import simulate
    from rvsim.parameters import RV40E, paper_run_values, with_values

    reducer = with_values(RV40E, paper_run_values(run))
    simulate(reducer, scheme=scheme)
    entries = {}
    for name, module in list(sys.modules.items()):
        if not (name.startswith("rvsim") or name.startswith("numba.core.runtime")):
            continue
        for attribute, value in list(vars(module).items()):
            if not (hasattr(value, "overloads") and hasattr(value, "py_func")):
                continue
            for result in value.overloads.values():
                engine = result.library._codegen._engine
                for symbol, label in ((result.fndesc.llvm_func_name, ""),
                                      (result.fndesc.llvm_cpython_wrapper_name, ".wrapper")):
                    try:
                        address = engine.get_function_address(symbol)
                    except Exception:       # pragma: no cover - not in this library
                        continue
                    if address:
                        short = name.rsplit(".", 1)[-1]
                        entries.setdefault(address, f"{short}.{attribute}{label}")
    try:        # Numba's reference counting is compiled at run time too
        from numba.core.runtime import nrt

        for symbol in ("NRT_incref", "NRT_decref"):
            address = nrt.rtsys.library.get_pointer_to_function(symbol)
            if address:
                entries.setdefault(address, symbol)
    except Exception:               # pragma: no cover - another Numba layout
        pass
    addresses = sorted(entries)
    with open(f"/tmp/perf-{os.getpid()}.map", "w") as out:
        for k, address in enumerate(addresses):
            size = addresses[k + 1] - address if k + 1 < len(addresses) else 4096
            out.write(f"{address:x} {min(size, 1 << 16):x} {entries[address]}\n")
    with open(ready, "w") as out:
        out.write(str(os.getpid()))
    start = time.perf_counter()
    while True:
        cpu = time.thread_time()
        simulate(reducer, scheme=scheme)
        print(f"profiled run: {time.thread_time() - cpu:.3f} s CPU", file=sys.stderr)
        if time.perf_counter() - start > seconds + 0.5:
            break


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--run", type=int, default=3, help="paper L36 run (default 3)")
    parser.add_argument("--seconds", type=float, default=2.0, help="sampled window [s]")
    parser.add_argument("--top", type=int, default=25, help="functions to list")
    parser.add_argument("--scheme", default="explicit",
                        choices=("explicit", "implicit-bearings"), help="integration scheme")
    parser.add_argument("--child", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        _child(args.run, args.child, args.scheme, args.seconds)
        return
    if shutil.which("perf") is None:
        print("profile_kernel: perf is not installed (Debian: apt-get install linux-perf)",
              file=sys.stderr)
        sys.exit(2)
    work = tempfile.mkdtemp(prefix="rvsim_profile_")
    ready = os.path.join(work, "ready")
    env = {**os.environ, "NUMBA_CACHE_DIR": os.path.join(work, "numba")}
    child = subprocess.Popen([sys.executable, __file__, "--run", str(args.run), "--scheme",
                              args.scheme, "--seconds", str(args.seconds), "--child", ready],
                             env=env)
    while not os.path.exists(ready) and child.poll() is None:
        time.sleep(0.2)
    if child.poll() is not None:
        sys.exit(f"profile_kernel: the profiled run ended early (exit {child.returncode})")
    data = os.path.join(work, "perf.data")
    subprocess.run(["perf", "record", "-q", "-F", "4000", "-p", str(child.pid), "-o", data,
                    "--", "sleep", str(args.seconds)], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    child.wait()
    report = subprocess.run(["perf", "report", "-i", data, "--no-children", "--sort", "sym",
                             "--stdio"], capture_output=True, text=True, check=True).stdout
    rows = [line for line in report.splitlines() if "%" in line and not line.startswith("#")]
    print(f"paper run {args.run} ({args.scheme}), {args.seconds:g} s sampled; share of "
          "samples, function:")
    for line in rows[:args.top]:
        print(line.strip())
    shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
