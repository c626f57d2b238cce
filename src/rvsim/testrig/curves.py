"""Bench curves a calibration fits besides encoder recordings (issue 33 item 5): a
torque-reversal loop (:func:`read_loop`) and efficiency points (:func:`read_efficiency`).

Loop CSV, one row per sample in the order of the test (what :func:`loop_table` writes from
:func:`rvsim.quasistatic.hysteresis`, and ``rvsim hysteresis --csv``):

* ``torque_nm`` [N*m] torque applied to the output, input locked;
* ``twist_arcmin`` [arcmin] output angle (any zero: each fit removes its mean);
* ``branch`` (optional) +1 where the torque rose to the sample, -1 where it fell to it; it must
  agree with the torques (it is what they say).

The torque goes in strictly monotone ramps between its reversals, each ramp from one side of
zero to the other (the first from anywhere, the last to anywhere), and the recording holds at
least one rising and one falling ramp across zero: one loop.

Efficiency CSV, one row per operating point (what ``rvsim efficiency --csv`` writes):

* ``input_speed_rpm`` [rpm], ``output_torque_nm`` [N*m], ``efficiency`` [-] output power /
  input power as a fraction (0 < efficiency <= 1);
* ``input_torque_nm`` (optional, read and not used), ``temperature_c`` (optional) [degC]
  the lubricant's temperature at the point (operating.temperature of the model's run).

CSV or Parquet, read by :mod:`rvsim.testrig.recording`'s reader.  Every problem is a
:class:`~rvsim.errors.ParameterError` naming the option, the file and the column.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from ..errors import InputFileError, ParameterError
from ..units import ARCMIN

__all__ = ["LoopCurve", "EfficiencyPoints", "read_loop", "read_efficiency", "loop_table",
           "check_efficiency_points", "LOOP_COLUMNS", "EFFICIENCY_COLUMNS"]

#: column -> (required, unit)
LOOP_COLUMNS = {"torque_nm": (True, "N*m"), "twist_arcmin": (True, "arcmin"),
                "branch": (False, "-")}
EFFICIENCY_COLUMNS = {"input_speed_rpm": (True, "rpm"), "output_torque_nm": (True, "N*m"),
                      "efficiency": (True, "-"), "input_torque_nm": (False, "N*m"),
                      "temperature_c": (False, "degC")}


@dataclasses.dataclass
class LoopCurve:
    """A torque-reversal loop in SI: torque [N*m], angle [rad], branch +-1, per sample."""

    path: Path
    torque: np.ndarray
    angle: np.ndarray
    branch: np.ndarray


@dataclasses.dataclass
class EfficiencyPoints:
    """Efficiency points: input speed [rpm], output torque [N*m], efficiency [-] and the
    lubricant temperature [degC] (None: the parameter set's)."""

    path: Path
    speed_rpm: np.ndarray
    torque: np.ndarray
    efficiency: np.ndarray
    temperature: np.ndarray | None


def _table(path, option: str, columns: dict) -> dict:
    """{column: float array} of the file, its columns checked against ``columns``."""
    import pandas as pd

    from .recording import _read_table

    path = Path(path)
    try:
        frame = _read_table(path)
    except InputFileError as exc:
        raise ParameterError(option, str(exc)) from None
    unknown = [c for c in frame.columns if c not in columns]
    if unknown:
        raise ParameterError(option, f"{path}: unknown column '{unknown[0]}' (known: "
                             f"{', '.join(f'{c} [{u}]' for c, (_, u) in columns.items())})")
    missing = [c for c, (required, _) in columns.items() if required and c not in frame]
    if missing:
        raise ParameterError(option, f"{path}: no column '{missing[0]}' (the file has "
                             f"{', '.join(map(str, frame.columns)) or 'none'})")
    out = {}
    for c in frame.columns:
        values = pd.to_numeric(frame[c], errors="coerce").to_numpy(dtype=float)
        bad = np.flatnonzero(~np.isfinite(values))
        if bad.size:
            raise ParameterError(option, f"{path}: column '{c}' data row {bad[0] + 1}: "
                                 f"'{frame[c].iloc[bad[0]]}' is not a finite number")
        out[c] = values
    return out


def read_loop(path, option: str = "--loop") -> LoopCurve:
    """The loop CSV at ``path`` (module docstring), checked: one loop of monotone ramps."""
    from ..analysis.catalogue import sweep_branches

    columns = _table(path, option, LOOP_COLUMNS)
    torque = columns["torque_nm"]
    where = f"{Path(path)}: torque_nm"
    if torque.size < 4:
        raise ParameterError(option, f"{where}: {torque.size} rows are fewer than a loop")
    step = np.sign(np.diff(torque))
    if np.any(step == 0):
        row = int(np.flatnonzero(step == 0)[0]) + 2
        raise ParameterError(option, f"{where}: data row {row} repeats the torque of the row "
                             "before (a ramp must be strictly monotone)")
    branch = sweep_branches(torque)
    turns = np.flatnonzero(np.diff(step) != 0) + 1        # the reversal samples
    ends = np.r_[0, turns, torque.size - 1]
    for k in range(1, len(ends) - 2):                     # the ramps between two reversals
        a, b = torque[ends[k]], torque[ends[k + 1]]
        if a * b >= 0:
            raise ParameterError(option, f"{where}: the ramp from data row {ends[k] + 1} "
                                 f"({a:g} N*m) turns back at data row {ends[k + 1] + 1} "
                                 f"({b:g} N*m) before crossing zero: the torque ramps are "
                                 "not monotone between the loop's reversals")
    crossing = [np.any(torque[ends[k]:ends[k + 1] + 1] > 0)
                and np.any(torque[ends[k]:ends[k + 1] + 1] < 0) for k in range(len(ends) - 1)]
    rising = [c for k, c in enumerate(crossing) if step[ends[k]] > 0]
    falling = [c for k, c in enumerate(crossing) if step[ends[k]] < 0]
    if not (any(rising) and any(falling)):
        raise ParameterError(option, f"{where}: fewer than a loop (it needs a rising and a "
                             "falling ramp that each cross zero)")
    if "branch" in columns:
        given = columns["branch"]
        wrong = np.flatnonzero(given != branch)
        if wrong.size:
            row = int(wrong[0]) + 1
            raise ParameterError(option, f"{Path(path)}: branch: data row {row} says "
                                 f"{given[wrong[0]]:g}, but the torque "
                                 f"{'rose' if branch[wrong[0]] > 0 else 'fell'} to it "
                                 "(+1: rose, -1: fell)")
    return LoopCurve(Path(path), torque, columns["twist_arcmin"] * ARCMIN, branch)


def read_efficiency(path, option: str = "--efficiency") -> EfficiencyPoints:
    """The efficiency CSV at ``path`` (module docstring), checked."""
    columns = _table(path, option, EFFICIENCY_COLUMNS)
    eff = columns["efficiency"]
    where = Path(path)
    for name, ok, what in (("input_speed_rpm", columns["input_speed_rpm"] > 0, "positive"),
                           ("output_torque_nm", columns["output_torque_nm"] > 0, "positive"),
                           ("efficiency", (eff > 0) & (eff <= 1), "a fraction 0 < eta <= 1 "
                                                                   "(not percent)")):
        if not np.all(ok):
            row = int(np.flatnonzero(~ok)[0])
            raise ParameterError(option, f"{where}: {name}: data row {row + 1} "
                                 f"({columns[name][row]:g}) must be {what}")
    return EfficiencyPoints(where, columns["input_speed_rpm"], columns["output_torque_nm"], eff,
                            columns.get("temperature_c"))


def check_efficiency_points(points: EfficiencyPoints, reducer, option: str = "--efficiency"):
    """Refuse, naming ``option``, the file, the column and the data row, a point the model
    cannot run: an input speed above the efficiency map's limit, a lubricant temperature
    outside the reducer's viscosity law (``rvsim.friction.lubricant_viscosity``)."""
    from ..friction import lubricant_viscosity
    from ..parameters import with_values
    from ..quasistatic.efficiency import MAX_SPEED_RPM

    fast = np.flatnonzero(points.speed_rpm > MAX_SPEED_RPM)
    if fast.size:
        raise ParameterError(option, f"{points.path}: input_speed_rpm: data row {fast[0] + 1} "
                             f"({points.speed_rpm[fast[0]]:g}) is above the model's "
                             f"{MAX_SPEED_RPM:g} rpm")
    if points.temperature is None:
        return
    for t in np.unique(points.temperature):
        try:
            lubricant_viscosity(with_values(reducer, {"operating.temperature": float(t)}))
        except ParameterError as exc:
            row = int(np.flatnonzero(points.temperature == t)[0]) + 1
            raise ParameterError(option, f"{points.path}: temperature_c: data row {row}: "
                                 f"{exc.reason}") from None


def loop_table(result):
    """A torque-reversal result (:func:`rvsim.quasistatic.hysteresis`) as the loop CSV's
    columns (pandas DataFrame; its converged points)."""
    import pandas as pd

    ok = result.converged
    return pd.DataFrame({"torque_nm": result.torque[ok],
                         "twist_arcmin": result.angle[ok] / ARCMIN,
                         "branch": result.branch[ok].astype(int)})
