"""Benchmark the analysis of a bench recording (issue 12, item 6).

Target: analysing a recording of 10^6 samples <= 2 s.  A synthetic TE recording (the RV-40E's
quasi-static TE, forward and backward, encoder quantisation and noise) of ``--samples`` rows
is written as CSV and as Parquet; the figures are the median, min and max (wall-clock and
CPU time of this process, which a shared machine inflates less) of ``--repeat`` runs of
:func:`rvsim.testrig.analyse_path` (read + analyse, the numbers ``rvsim testrig`` prints),
and separately of the analysis alone on the loaded recording.  BLAS threads limited to one.

Usage:  python benchmarks/bench_testrig.py [--samples 1000000] [--repeat 5]
"""

from __future__ import annotations

import os

from _timing import one_thread

one_thread()

import argparse  # noqa: E402
import json  # noqa: E402
import statistics  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

from _timing import machine, samples  # noqa: E402


def _median(function, repeat):
    """Wall-clock and CPU time (this process) of ``repeat`` calls: median, min, max of each."""
    wall, cpu = samples(function, repeat)
    return {"wall_s": [statistics.median(wall), min(wall), max(wall)],
            "cpu_s": [statistics.median(cpu), min(cpu), max(cpu)]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=1_000_000)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()

    from rvsim.parameters import RV40E
    from rvsim.testrig import analyse_path, synthetic
    from rvsim.testrig.bench import PointResult, analyse_recording
    from rvsim.testrig.model import point_summary
    from rvsim.testrig.recording import read_recording

    per_rev = args.samples // 2 / 1.05
    frame, _ = synthetic.te_recording(RV40E, backward=True, revolutions=1.05,
                                      samples_per_revolution=int(per_rev))
    figures = {"samples": len(frame)}
    with tempfile.TemporaryDirectory() as folder:
        for suffix in ("csv", "parquet"):
            path = Path(folder) / f"run_300Nm.{suffix}"
            (frame.to_csv(path, index=False) if suffix == "csv"
             else frame.to_parquet(path))

            def whole(path=path):
                for point in analyse_path(path, RV40E):
                    point_summary(point, RV40E)

            whole()                                   # warm-up (imports)
            figures[f"read_and_analyse_{suffix}"] = _median(whole, args.repeat)
        recording = read_recording(path)

        def analysis_only():
            point_summary(PointResult({}, [analyse_recording(recording, {}, RV40E)]), RV40E)

        figures["analysis_only"] = _median(analysis_only, args.repeat)
    figures.update(machine=machine(), date=time.strftime("%Y-%m-%d %H:%M"),
                   load=os.getloadavg()[0])
    print(json.dumps(figures, indent=2))


if __name__ == "__main__":
    main()
