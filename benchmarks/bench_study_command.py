"""The paper's study as a user runs it, `rvsim study paper-l36`, timed by phase (issue 14,
item 2).

Each repeat starts the whole command in a fresh process (warm numba cache: run it once
first) into a fresh folder, for each ``--variant`` in turn (round robin, so that a change of
the machine's load falls on every variant alike).  The process is the command line itself,
started through ``rvsim.__main__.main`` with one addition: the study runner's local pool
(``rvsim.doe.runner.run_local``) is wrapped so that it prints when it starts and ends.  So
each command's wall time splits into

* ``before``: from the process's start to the pool (Python, imports, the 36 reducers
  validated);
* ``runs``: the pool, first dispatch to last result (the analysis imports inside it, in the
  last runs' spare core);
* ``after``: from the last result to the process's end (analysis, figures, files, report);

and ``cpu`` is the CPU time of the command and its worker processes.  The runs phase is
split further from each run's own times (the worker's call wrapped, the store's ``put``
timed in the parent): ``kernel`` is the larger of the two workers' sums of the runs'
``wall_s`` (the simulations themselves), ``per_run_overhead`` the median of a run's time in
its worker beyond its ``wall_s`` (model set-up, summary, history compaction), ``gaps`` the
larger worker's total wait between a result and its next run (the parent's store write and
dispatch), ``end_idle`` the time one worker waits for the other's last run, ``store`` the
parent's time in the store's writes.  Prints one JSON line per command, then per variant
the median and range of each figure.

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
import json, os, sys, time
import rvsim.doe.runner as runner
import rvsim.doe.store as store
runs = []
evaluate = runner.evaluate_task
def evaluate_timed(key, *args, **kwargs):
    start = time.time()
    key, outcome = evaluate(key, *args, **kwargs)
    outcome['_timing'] = (os.getpid(), start, time.time())
    return key, outcome
runner.evaluate_task = evaluate_timed         # run_local hands it to the forked workers
put = store.ResultStore.put
def put_timed(self, key, outcome):
    pid, start, end = outcome.pop('_timing', (0, 0.0, 0.0))
    begin = time.time()
    put(self, key, outcome)
    runs.append((pid, start, end, outcome.get('wall_s') or 0.0, time.time() - begin))
store.ResultStore.put = put_timed
pool = runner.run_local
def timed(*args, **kwargs):
    print(f"PHASE start {time.time():.6f}", file=sys.stderr, flush=True)
    try:
        return pool(*args, **kwargs)
    finally:
        print(f"PHASE end {time.time():.6f}", file=sys.stderr, flush=True)
        print("RUNS " + json.dumps(runs), file=sys.stderr, flush=True)
runner.run_local = timed
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
    runs = next(json.loads(line[5:]) for line in done.stderr.splitlines()
                if line.startswith("RUNS "))
    return {"variant": variant, "wall_s": round(end - start, 2),
            "before_s": round(pool_start - start, 2), "runs_s": round(pool_end - pool_start, 2),
            "after_s": round(end - pool_end, 2),
            # children's user + system time: the command and the workers it has reaped
            "cpu_s": round(after[2] + after[3] - before[2] - before[3], 1),
            **_split(runs, pool_end), "load_average_1min": round(os.getloadavg()[0], 2)}


def _split(runs: list, pool_end: float) -> dict:
    """The runs phase by worker: see the module's text."""
    by_worker: dict[int, list] = {}
    for pid, start, end, wall, _ in runs:
        by_worker.setdefault(pid, []).append((start, end, wall))
    kernel, gaps, ends = [], [], []
    for rows in by_worker.values():
        rows.sort()
        kernel.append(sum(wall for _, _, wall in rows))
        gaps.append(sum(rows[i + 1][0] - rows[i][1] for i in range(len(rows) - 1)))
        ends.append(pool_end - rows[-1][1])
    overhead = [end - start - wall for _, start, end, wall, _ in runs]
    return {"kernel_s": round(max(kernel), 2),
            "per_run_overhead_s": round(statistics.median(overhead), 3),
            "gaps_s": round(max(gaps), 2),
            "end_idle_s": round(max(ends) - min(ends), 2),
            "store_s": round(sum(r[4] for r in runs), 3)}


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
        for phase in ("wall_s", "before_s", "runs_s", "after_s", "cpu_s", "kernel_s",
                      "per_run_overhead_s", "gaps_s", "end_idle_s", "store_s"):
            values = [r[phase] for r in mine]
            summary[phase] = {"median": round(statistics.median(values), 3),
                              "range": [min(values), max(values)]}
        print(json.dumps(summary))


if __name__ == "__main__":
    main()
