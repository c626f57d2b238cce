"""Timing shared by the benchmark scripts (run as ``python benchmarks/bench_*.py``)."""

import statistics
import time


def samples(function, repeat: int) -> tuple[list[float], list[float]]:
    """Wall times and CPU times (s, this process) of ``repeat`` calls of ``function()``."""
    walls, cpus = [], []
    for _ in range(repeat):
        wall, cpu = time.perf_counter(), time.process_time()
        function()
        walls.append(time.perf_counter() - wall)
        cpus.append(time.process_time() - cpu)
    return walls, cpus


def timed(function, repeat: int) -> tuple[float, float]:
    """Median wall time and median CPU time (s) of ``repeat`` calls of ``function()``."""
    walls, cpus = samples(function, repeat)
    return statistics.median(walls), statistics.median(cpus)
