"""Timing shared by the benchmark scripts (run as ``python benchmarks/bench_*.py``)."""

import os
import platform
import statistics
import tempfile
import time

#: a short schedule (0.3 s) for the warm-up run that loads the compiled kernel
SHORT = {"operating.duration": 0.3, "operating.speed_ramp_time": 0.1,
         "operating.load_start": 0.1, "operating.load_ramp_end": 0.2,
         "operating.steady_start": 0.2}


def one_thread(cache_prefix: str | None = None) -> None:
    """Limit BLAS and numba to one thread and, with ``cache_prefix``, point the FE cache at a
    fresh temporary folder; call before numpy is imported."""
    for name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS",
                 "NUMBA_NUM_THREADS"):
        os.environ.setdefault(name, "1")
    if cache_prefix is not None:
        os.environ["RVSIM_CACHE_DIR"] = tempfile.mkdtemp(prefix=cache_prefix)


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


def interleaved(functions: dict, repeat: int) -> dict:
    """Median wall and CPU times (s) of each named function, called in turn ``repeat`` times
    (round robin: a change of the machine's load falls on every case alike).  Returns
    {name: (wall, cpu)}."""
    walls = {name: [] for name in functions}
    cpus = {name: [] for name in functions}
    for _ in range(repeat):
        for name, function in functions.items():
            wall, cpu = time.perf_counter(), time.process_time()
            function()
            walls[name].append(time.perf_counter() - wall)
            cpus[name].append(time.process_time() - cpu)
    return {name: (statistics.median(walls[name]), statistics.median(cpus[name]))
            for name in functions}


def machine() -> str:
    """The machine a figure was measured on: architecture, processor, cores, Python."""
    processor = platform.processor()
    return (f"{platform.machine()}{' ' + processor if processor else ''}, {os.cpu_count()} cpu, "
            f"Python {platform.python_version()}")


def once(function):
    """(value, wall time, CPU time) of one call of ``function()`` (times in s, this process)."""
    wall, cpu = time.perf_counter(), time.process_time()
    value = function()
    return value, time.perf_counter() - wall, time.process_time() - cpu


def run_numbers(text: str) -> list[int]:
    """The paper runs of a list such as "1-3,7,30-36"."""
    out: list[int] = []
    for part in text.split(","):
        first, _, last = part.partition("-")
        out.extend(range(int(first), int(last or first) + 1))
    return out
