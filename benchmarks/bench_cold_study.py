"""A 2-worker study from an empty numba cache, and the same study warm (issue 35 item 3).

Runs ``rvsim study`` on a small dynamic design (L4, 0.5 s runs) in a fresh process with
``NUMBA_CACHE_DIR`` pointed at an empty folder (cold: the kernel is compiled), then ``--repeat``
times again into fresh output folders with that cache (warm).  Prints, per process, the wall
time, the CPU time of the process and its workers, and the compile notices on stderr.  Give
``--src`` to time another checkout's sources (e.g. main's, for the "before" figure).

Usage:  python benchmarks/bench_cold_study.py [--src src] [--repeat 3] [--workers 2]
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

STUDY = """name = "small"
design = "L4"
[set]
"operating.duration" = 0.5
"operating.steady_start" = 0.3
[factors.H]
parameter = "H"
levels = [0.0, 0.01]
[factors.I]
parameter = "I"
levels = [0.0, 0.01]
"""


def _study(folder: Path, env: dict, out: str, workers: int) -> tuple[float, float, int]:
    """(wall s, CPU s of the process and its workers, compile notices) of one study process."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "rvsim", "study", "small.toml", "--out", out,
                           "--workers", str(workers), "--no-report", "--json"], cwd=folder,
                          env=env, capture_output=True, text=True, check=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, done.stderr.count("rvsim: compiling")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--src", default=str(Path(__file__).resolve().parents[1] / "src"))
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    folder = Path(tempfile.mkdtemp(prefix="rvsim-cold-study-"))
    (folder / "small.toml").write_text(STUDY)
    env = {**os.environ, "NUMBA_CACHE_DIR": str(folder / "numba-cache"),
           "PYTHONPATH": args.src}
    print(f"sources {args.src}, {args.workers} workers, load average {os.getloadavg()[0]:.1f}")
    wall, cpu, notices = _study(folder, env, "cold", args.workers)
    print(f"cold: wall {wall:.1f} s, CPU {cpu:.1f} s, compile notices {notices}")
    warm = [_study(folder, env, f"warm{i}", args.workers) for i in range(args.repeat)]
    walls = [w for w, _, _ in warm]
    print(f"warm: wall median {statistics.median(walls):.2f} s (range {min(walls):.2f}-"
          f"{max(walls):.2f}), CPU median {statistics.median([c for _, c, _ in warm]):.2f} s, "
          f"compile notices {sum(n for _, _, n in warm)}; load average "
          f"{os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
