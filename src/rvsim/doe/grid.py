"""TE over input speed and output torque, as benches record it (issue 33 item 4).

:func:`run_grid` simulates every point of speeds x torques (x temperatures) on the dynamic
engine, each for one output revolution in its steady window (:func:`grid_duration`), and gives
at each point the ATE (:func:`rvsim.analysis.catalogue.angular_transmission_error`), the
largest orders of the TE over that revolution (:func:`rvsim.analysis.catalogue.order_spectrum`),
the mean twist (mean TE) and the output's torsional natural frequency at the point's torque
(:func:`rvsim.quasistatic.modes.torsional_mode`), with the frequency of each named order of the
reducer (:func:`rvsim.analysis.catalogue.reducer_orders`) at the point's speed beside it.

The points are a study's runs: stored as they finish in the folder's results store
(:class:`rvsim.doe.store.ResultStore`, keyed by the point's whole parameter set), evaluated by
the study's local workers (:func:`rvsim.doe.runner.run_local`); a second call skips the
points already stored, and a grid with more speeds or torques reuses them.
"""

from __future__ import annotations

import math
import re
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

from .._files import atomic_write_text
from .._json import to_json_safe
from ..errors import ParameterError
from ..parameters import Reducer, with_values
from ..units import ARCMIN, TO_SI
from .store import run_key

__all__ = ["grid_duration", "grid_points", "evaluate_point", "run_grid", "grid_table",
           "REVOLUTION_MARGIN", "MAIN_ORDERS", "GRID_NAME"]

#: the steady window covers one output revolution and this fraction more: the ATE's
#: revolution is counted on the output's own angle, which lags the nominal one by the twist's
#: variation and the sampling (docs/decisions.md, issue 33 item 4)
REVOLUTION_MARGIN = 0.01
#: the largest orders of the TE reported at each point
MAIN_ORDERS = 3
#: the name in a grid folder's study.json
GRID_NAME = "speed-torque grid"


def grid_duration(reducer: Reducer) -> float:
    """The shortest run [s] whose steady window holds one output revolution at the reducer's
    input speed: ``operating.steady_start`` plus (1 + :data:`REVOLUTION_MARGIN`) output
    revolutions, 2 pi |i| / omega_in each."""
    revolution = 2.0 * math.pi * abs(reducer.ratio) / reducer.operating.input_speed
    return reducer.operating.steady_start + (1.0 + REVOLUTION_MARGIN) * revolution


def grid_points(base: Reducer, speeds_rpm, torques, temperatures=None) -> list[dict]:
    """The grid's points in order (speed, then torque, then temperature), each
    ``{input_speed_rpm, output_torque_nm, temperature_c, reducer}`` with its run length set by
    :func:`grid_duration`; a point the parameter checks refuse raises ParameterError on the
    option that gave it."""
    temps = list(temperatures) if temperatures else [None]
    points = []
    for speed in speeds_rpm:
        for torque in torques:
            for temp in temps:
                values = {"operating.input_speed": f"{speed!r}rpm",
                          "operating.load_torque": repr(float(torque))}
                if temp is not None:
                    values["operating.temperature"] = repr(float(temp))
                reducer = _point_reducer(base, values)
                # the run length only: the point was validated above, and the dynamic
                # engine's check_run_options checks the length (half the time of a point)
                reducer = with_values(reducer, {"operating.duration":
                                                repr(grid_duration(reducer))}, check=False)
                points.append({"input_speed_rpm": float(speed), "output_torque_nm": float(torque),
                               "temperature_c": reducer.operating.temperature,
                               "reducer": reducer})
    return points


_OPTIONS = {"operating.input_speed": "--speeds", "operating.load_torque": "--torques",
            "operating.temperature": "--temperatures"}


def _point_reducer(base: Reducer, values: dict) -> Reducer:
    """``base`` with the point's ``values``, validated, the lubricant's viscosity law at its
    temperature included (:func:`rvsim.friction.check_losses`, as every command checks it)."""
    from ..friction import check_losses

    try:
        return check_losses(with_values(base, values))
    except ParameterError as exc:       # the option's value, not the parameter file's
        option = _OPTIONS.get(exc.field)
        if option is None:
            raise
        raise ParameterError(option, f"{exc.reason} ({exc.field})") from None


def _slug(name: str) -> str:
    return re.sub(r"[^a-z0-9]+", "_", name.lower()).strip("_")


def main_orders(result, count: int = MAIN_ORDERS) -> dict:
    """The ``count`` largest orders of the TE over the first output revolution of ``result``'s
    steady window (mean left out) and their amplitudes [arcmin]: the TE resampled (linearly) at
    equally spaced nominal output angles, input angle / ratio, as many as the revolution has
    samples, then :func:`rvsim.analysis.catalogue.order_spectrum` (rectangular window: integer
    orders are exact bins)."""
    from ..analysis.catalogue import order_spectrum

    out = {}
    for k in range(1, count + 1):
        out[f"order{k}"], out[f"order{k}_arcmin"] = float("nan"), float("nan")
    window = result.time >= result.steady_start - 1e-12
    nominal = result.theta_in[window] / result.ratio
    te = result.te[window] / ARCMIN
    if nominal.size < 8 or not (np.all(np.isfinite(nominal)) and np.all(np.isfinite(te))):
        return out
    travel = np.abs(nominal - nominal[0])
    if travel[-1] < 2.0 * math.pi:
        return out
    n = int(np.count_nonzero(travel < 2.0 * math.pi))
    grid = np.arange(n) * (2.0 * math.pi / n)
    sign = 1.0 if nominal[-1] >= nominal[0] else -1.0
    orders, amplitude = order_spectrum(nominal[0] + sign * grid, np.interp(grid, travel, te))
    top = np.argsort(amplitude[1:])[::-1][:count] + 1
    for k, index in enumerate(top, start=1):
        out[f"order{k}"], out[f"order{k}_arcmin"] = float(orders[index]), float(amplitude[index])
    return out


def evaluate_point(reducer: Reducer, *, time_step: float, scheme: str = "explicit", **_) -> dict:
    """One grid point: the dynamic run's outcome ``{status, metrics, error, wall_s}`` as a
    study's row has it (:func:`rvsim.doe.engines.evaluate_dynamic`; never raises), its
    metrics with the main orders and the torsional mode at its torque; status
    ``no_revolution`` if the window holds no whole output revolution."""
    from ..dynamics import simulate
    from .modes import torsional_mode

    try:
        result = simulate(reducer, time_step=time_step, raise_on_failure=False, scheme=scheme)
        outcome = {"status": result.status, "wall_s": result.wall_s, "metrics": {}}
        if result.status != "ok":         # as a study's row says it (doe.engines)
            outcome["error"] = f"simulation {result.status.replace('_', ' ')} at step " \
                               f"{result.steps}"
            return outcome
        outcome["metrics"] = {**result.summary(), **main_orders(result),
                              **torsional_mode(reducer).summary()}
    except Exception as exc:  # noqa: BLE001 - a failed point must not stop the grid
        return {"status": "error", "error": f"{type(exc).__name__}: {exc}", "metrics": {}}
    if not math.isfinite(outcome["metrics"].get("ate_arcmin", math.nan)):
        outcome["status"] = "no_revolution"
        outcome["error"] = outcome["metrics"].get("ate_note", "no ATE")
    return outcome


#: the local workers' kernel check (rvsim.doe.runner.kernel_ready): the dynamic engine's
evaluate_point.kernel_engine = "dynamic"


def _digest() -> str:
    """The source of what evaluates a point beyond the model (this file and ``modes.py``):
    part of each point's key, outside the model fingerprint."""
    from .._fingerprint import fingerprint_files

    here = Path(__file__).resolve().parent
    return fingerprint_files([here / "grid.py", here / "modes.py"])[:16]


def _definition(base: Reducer, time_step: float, scheme: str) -> dict:
    """What a grid folder is for: the grid's name, engine, step and scheme (not the points:
    a grid with more points resumes the same folder)."""
    return {"name": GRID_NAME, "engine": "dynamic", "time_step": time_step, "scheme": scheme,
            "reducer": base.name}


def run_grid(base: Reducer, points: list[dict], folder: str | Path, *, time_step: float,
             scheme: str = "explicit", workers: int | None = None,
             progress=None) -> pd.DataFrame:
    """Evaluate ``points`` (:func:`grid_points`) into ``folder``; return :func:`grid_table`.

    Points already in the folder's store are not run again.  ``progress(line)``, if given, is
    called with one line per finished point.  Ctrl-C, SIGTERM and SIGHUP stop the workers and
    keep every finished point (KeyboardInterrupt, or Terminated, is raised)."""
    from .runner import run_local, study_folder, to_run

    folder = Path(folder)
    definition = _definition(base, time_step, scheme)
    keys = [run_key(p["reducer"], f"grid {time_step} {scheme} {_digest()}") for p in points]
    with study_folder(folder, definition, _dumps(definition)) as (store, done):
        todo = to_run(keys, [p["reducer"] for p in points], done)
        by_key = dict(zip(keys, points))
        total, count = len(set(keys)), [len(set(keys)) - len(todo)]
        if progress:
            progress(f"grid: {total} points, {count[0]} stored, {len(todo)} to run")
        start = time.monotonic()

        def store_result(key: str, outcome: dict) -> None:
            store.put(key, outcome)
            count[0] += 1
            if progress:
                progress(_progress_line(by_key[key], outcome, count[0], total,
                                        time.monotonic() - start))

        if todo:
            run_local(todo, (time_step, evaluate_point, False, 360, scheme), workers,
                      store_result)
        done = store.get_many(keys)
    return grid_table(points, keys, done)


def _progress_line(point: dict, outcome: dict, count: int, total: int, elapsed: float) -> str:
    metrics = outcome.get("metrics", {})
    what = (f"ATE {metrics['ate_arcmin']:.4g} arcmin, mean TE {metrics['te_mean_arcmin']:.4g} "
            f"arcmin" if outcome["status"] == "ok" else
            f"{outcome['status']}: {str(outcome.get('error', ''))[:120]}")
    temperature = f", {point['temperature_c']:g} degC"
    return (f"grid point {count}/{total}: {point['input_speed_rpm']:g} rpm, "
            f"{point['output_torque_nm']:g} N*m{temperature}: {what} ({elapsed:.0f} s)")


def _dumps(payload) -> str:
    import json

    return json.dumps(to_json_safe(payload), indent=2, allow_nan=False)


def grid_table(points: list[dict], keys: list[str], done: dict) -> pd.DataFrame:
    """One row per point: its coordinates, status, ATE, mean twist, main orders, the natural
    frequency and each named order's frequency at the point's speed, the order nearest the
    natural frequency and the orders inside its half-power band (``resonance``)."""
    from ..analysis.catalogue import reducer_orders

    rows = []
    for point, key in zip(points, keys):
        reducer = point["reducer"]
        outcome = done.get(key, {"status": "missing", "metrics": {}})
        metrics = outcome.get("metrics") or {}
        output_hz = point["input_speed_rpm"] * TO_SI["rpm"] / (2.0 * math.pi) / abs(reducer.ratio)
        row = {"input_speed_rpm": point["input_speed_rpm"],
               "output_torque_nm": point["output_torque_nm"],
               "temperature_c": point["temperature_c"],
               "status": outcome["status"], "error": outcome.get("error") or "",
               "output_speed_rpm": output_hz * 60.0}
        for name in ("ate_arcmin", "te_mean_arcmin", "te_pp_arcmin", "te_window_revolutions"):
            row[name] = metrics.get(name, math.nan)
        for k in range(1, MAIN_ORDERS + 1):
            row[f"order{k}"] = metrics.get(f"order{k}", math.nan)
            row[f"order{k}_arcmin"] = metrics.get(f"order{k}_arcmin", math.nan)
        for name in ("natural_frequency_hz", "natural_frequency_min_hz",
                     "natural_frequency_max_hz", "torsional_stiffness_nm_per_arcmin",
                     "output_inertia_kgm2"):
            row[name] = metrics.get(name, math.nan)
        row.update(_excitation(reducer_orders(reducer), output_hz, row["natural_frequency_hz"],
                               reducer.contact.damping_ratio))
        for name in ("speed_ratio", "energy_residual", "max_pin_force_n", "sim_time_s",
                     "steps", "wall_s"):
            row[name] = metrics.get(name, math.nan)
        rows.append(row)
    return pd.DataFrame(rows)


def _excitation(orders: dict, output_hz: float, natural_hz: float, zeta: float) -> dict:
    """Each named order's frequency [Hz] at ``output_hz``, the order nearest ``natural_hz``
    (its name and f / f_n) and the orders inside the half-power band f_n (1 -+ zeta)."""
    out = {f"f_{_slug(name)}_hz": order * output_hz for name, order in orders.items()}
    nearest, ratio, inside = "", math.nan, []
    if math.isfinite(natural_hz) and natural_hz > 0:
        ratios = {name: order * output_hz / natural_hz for name, order in orders.items()}
        nearest = min(ratios, key=lambda name: abs(math.log(ratios[name])))
        ratio = ratios[nearest]
        inside = [name for name, r in ratios.items() if abs(r - 1.0) <= zeta]
    out.update({"nearest_order": nearest, "nearest_order_ratio": ratio,
                "resonance": "; ".join(inside)})
    return out


def write_outputs(folder: Path, table: pd.DataFrame, summary: dict) -> None:
    """grid.csv (one row per point, units in the column names) and grid.json (the summary
    and the rows) into ``folder``, atomically."""
    atomic_write_text(folder / "grid.csv", table.to_csv(index=False))
    payload = {**summary, "points": table.to_dict(orient="records")}
    atomic_write_text(folder / "grid.json", _dumps(payload))


def progress_to_stderr(line: str) -> None:
    print(f"rvsim: {line}", file=sys.stderr, flush=True)
