"""Start-up time of the command line (issue 8, item 8).

Times whole ``rvsim`` processes, as a user waits for them: ``--version``, ``--help``,
``simulate --help``, and ``simulate --json`` on a short run, where the process time above the
solver's own ``wall_s`` (from the JSON) is the start-up and shutdown overhead.  Each figure
is the median of ``--repeat`` runs after one warm-up (numba's on-disk cache warm).

Usage:  python benchmarks/bench_startup.py [--repeat 7] [--duration 2]
"""

from __future__ import annotations

import argparse
import json
import shutil
import statistics
import subprocess
import sys
import time

from _timing import machine


def _rvsim() -> list[str]:
    exe = shutil.which("rvsim")
    return [exe] if exe else [sys.executable, "-m", "rvsim"]


def _timed(args: list[str]) -> tuple[float, str]:
    start = time.perf_counter()
    done = subprocess.run(_rvsim() + args, capture_output=True, text=True, check=True)
    return time.perf_counter() - start, done.stdout


def _median(args: list[str], repeat: int) -> dict:
    _timed(args)  # warm-up: page cache, numba cache
    walls = [_timed(args)[0] for _ in range(repeat)]
    return {"median_s": round(statistics.median(walls), 3),
            "min_s": round(min(walls), 3), "max_s": round(max(walls), 3)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=7)
    parser.add_argument("--duration", type=float, default=2.0,
                        help="simulated time of the simulate run [s] (default 2)")
    args = parser.parse_args()

    figures = {name: _median(cmd, args.repeat) for name, cmd in (
        ("rvsim --version", ["--version"]),
        ("rvsim --help", ["--help"]),
        ("rvsim simulate --help", ["simulate", "--help"]),
    )}
    sim = ["simulate", "--json", "--duration", f"{args.duration:g}"]
    _timed(sim)
    overheads, totals = [], []
    for _ in range(args.repeat):
        total, out = _timed(sim)
        totals.append(total)
        overheads.append(total - json.loads(out)["wall_s"])
    figures[f"rvsim simulate --duration {args.duration:g} (whole process)"] = {
        "median_s": round(statistics.median(totals), 3)}
    figures["simulate: process time above the solver's wall_s"] = {
        "median_s": round(statistics.median(overheads), 3),
        "min_s": round(min(overheads), 3), "max_s": round(max(overheads), 3)}
    print(json.dumps({
        "machine": machine(),
        "date": time.strftime("%Y-%m-%d"), "repeat": args.repeat, "figures": figures,
    }, indent=2))


if __name__ == "__main__":
    main()
