"""Benchmark the FE disc's condensation against ``flexibility.fe_segments_per_tooth``.

For each segment count, a fresh process meshes the RV-40E disc (default element size) and
condenses it onto its contact segments; it reports the degrees of freedom, the condensation's
CPU time (median of ``--repeat`` solves in that process) and the process's peak memory
(``ru_maxrss``, which includes the imports, the mesh and the factor).  BLAS threads are one.

Usage:  python benchmarks/bench_fe_segments.py [--segments 8 16 32 64] [--repeat 3]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

CHILD = """
import json, resource, sys
sys.path.insert(0, {here!r})
from _timing import one_thread, timed
one_thread()
from rvsim.fe.disc import disc_body, disc_geometry
from rvsim.parameters import RV40E, with_values

reducer = with_values(RV40E, {{"flexibility.fe_segments_per_tooth": {n}}})
body, supported, loads = disc_body(disc_geometry(reducer, 0))
wall, cpu = timed(lambda: body.compliance(loads, supported), {repeat})
print(json.dumps({{"segments_per_tooth": {n}, "columns": int(loads.shape[1]),
                  "dofs": int(body.n_dofs), "condense_cpu_s": round(cpu, 2),
                  "condense_wall_s": round(wall, 2),
                  "peak_memory_mb": round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
                                          / 1024)}}))
"""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--segments", type=int, nargs="+", default=[8, 16, 32, 64])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    sys.path.insert(0, str(Path(__file__).parent))
    from _timing import machine

    rows = []
    for n in args.segments:
        code = CHILD.format(here=str(Path(__file__).parent), n=n, repeat=args.repeat)
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                             check=True)
        rows.append(json.loads(out.stdout.splitlines()[-1]))
        print(json.dumps(rows[-1]), file=sys.stderr)
    print(json.dumps({"machine": machine(), "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "rows": rows}, indent=2))


if __name__ == "__main__":
    main()
