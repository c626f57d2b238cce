"""The paper's study as a user runs it, `rvsim study paper-l36`, timed by phase (issue 14,
item 2).

Each repeat starts the whole command in a fresh process (warm numba cache: run it once
first) into a fresh folder, for each ``--variant`` in turn (round robin, so that a change of
the machine's load falls on every variant alike).  The process is the command line itself,
started through ``rvsim.__main__.main`` with one addition: the study runner's local pool
(``rvsim.doe.runner._run_local``) is wrapped so that it prints when it starts and ends.  So
each command's wall time splits into

* ``before``: from the process's start to the pool (Python, imports, the 36 reducers
  validated);
* ``runs``: the pool, first dispatch to last result (the analysis imports inside it, in the
  last runs' spare core);
* ``after``: from the last result to the process's end (analysis, figures, files, report);

and ``cpu`` is the CPU time of the command and its worker processes.  Prints one JSON line
per command, then per variant the median and range of each phase.

Usage:  python benchmarks/bench_study_command.py [--repeat 3]
                                                 [--variant ""] [--variant "--time-step 2.5e-5"]
"""

from __future__ import annotations

import argparse
import json
import os
import shlex
import statistics
import subprocess
import sys
import tempfile
import time

from _timing import machine

#: the command, with the pool's start and end printed to stderr as "PHASE name time"
_CHILD = """
import sys, time
import rvsim.doe.runner as runner
pool = runner._run_local
def timed(*args, **kwargs):
    print(f"PHASE start {time.time():.6f}", file=sys.stderr, flush=True)
    try:
        return pool(*args, **kwargs)
    finally:
        print(f"PHASE end {time.time():.6f}", file=sys.stderr, flush=True)
runner._run_local = timed
from rvsim.__main__ import main
sys.argv = ["rvsim"] + sys.argv[1:]
main()
"""


def _command(folder: str, variant: str) -> dict:
    args = ["study", "paper-l36", "--out", folder, "--no-progress", *shlex.split(variant)]
    before = os.times()
    start = time.time()
    done = subprocess.run([sys.executable, "-c", _CHILD, *args], capture_output=True,
                          text=True)
    end = time.time()
    after = os.times()
    if done.returncode != 0:
        raise SystemExit(f"the command failed (exit {done.returncode}): {done.stderr[-500:]}")
    marks = dict(line.split()[1:] for line in done.stderr.splitlines()
                 if line.startswith("PHASE "))
    pool_start, pool_end = float(marks["start"]), float(marks["end"])
    return {"variant": variant, "wall_s": round(end - start, 2),
            "before_s": round(pool_start - start, 2), "runs_s": round(pool_end - pool_start, 2),
            "after_s": round(end - pool_end, 2),
            # children's user + system time: the command and the workers it has reaped
            "cpu_s": round(after[2] + after[3] - before[2] - before[3], 1),
            "load_average_1min": round(os.getloadavg()[0], 2)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--variant", action="append", default=None,
                        help="extra options of the command (repeatable; default: none)")
    args = parser.parse_args()
    if args.repeat < 1:
        parser.error("--repeat: at least 1")
    variants = args.variant or [""]
    if any("--scheduler" in v for v in variants):
        parser.error("--variant: the phases are those of the local worker pool (no --scheduler)")
    rows = []
    for _ in range(args.repeat):
        for variant in variants:
            with tempfile.TemporaryDirectory() as folder:
                row = _command(os.path.join(folder, "study"), variant)
            print(json.dumps(row), flush=True)
            rows.append(row)
    for variant in variants:
        mine = [r for r in rows if r["variant"] == variant]
        summary = {"variant": variant, "machine": machine(), "date": time.strftime("%Y-%m-%d"),
                   "commands": len(mine)}
        for phase in ("wall_s", "before_s", "runs_s", "after_s", "cpu_s"):
            values = [r[phase] for r in mine]
            summary[phase] = {"median": round(statistics.median(values), 2),
                              "range": [min(values), max(values)]}
        print(json.dumps(summary))


if __name__ == "__main__":
    main()
