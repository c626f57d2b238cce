"""Efficiency map, no-load running torque and starting torque: :func:`efficiency`.

Each point of the map is a quasi-static sweep of the loaded reducer over one revolution of the
cranks relative to the carrier (the period of the cycloid stage's loads), the friction
following the input turning forwards at the point's speed (docs/model.md section 15;
docs/decisions.md, "Efficiency: the quasi-static engine").  Efficiency = output power / input
power = T_out / (i * mean T_in); shared/design/catalogue_tests.md gives the definitions.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from .._cache_guard import RunClock
from .._display import Headline, draw, figure, number, without_status
from ..errors import ParameterError, SimulationError
from ..parameters import Reducer, validate
from ..units import from_si
from .transmission import TOLERANCE

__all__ = ["efficiency", "efficiency_points", "EfficiencyResult", "DEFAULT_SPEEDS_RPM",
           "DEFAULT_TORQUE_FRACTIONS", "POSITIONS", "STARTING_SPEED_RPM", "MAX_SPEED_RPM", "RESOLVED_TORQUE_FRACTION"]

RPM = 2.0 * math.pi / 60.0
#: input speeds of the default map [rpm] (RV-40E, i = 121: output 4 to 25 rpm)
DEFAULT_SPEEDS_RPM = (500.0, 1000.0, 1500.0, 2000.0, 3000.0)
#: output torques of the default map, as fractions of the rated torque
DEFAULT_TORQUE_FRACTIONS = (0.2, 0.4, 0.6, 0.8, 1.0)
#: equilibria per point, equally spaced over one crank revolution relative to the carrier
POSITIONS = 24
#: fastest input speed accepted [rpm]: above any servo motor (Palmgren's viscous law and the
#: quasi-static engine have no meaning far beyond a reducer's rated speed)
MAX_SPEED_RPM = 100_000.0
#: smallest output torque of a map, as a fraction of the rated torque: the quasi-static
#: solver converges to 1e-7 of the rated torque (transmission.TOLERANCE), so the input torque
#: of a point at this torque carries up to about 0.1 % of error (an output torque of 1e-5
#: N*m gave an efficiency of 4239, 1e-3 N*m 1.07, 1e-2 N*m 0.920 against 0.922 at rated)
RESOLVED_TORQUE_FRACTION = 1e-4
#: creep speed at which the starting torque is taken [input rpm]: Coulomb friction and
#: Palmgren's low-speed viscous torque, i.e. the torque to keep the input moving at all
STARTING_SPEED_RPM = 1.0


@dataclasses.dataclass(repr=False)
class EfficiencyResult(Headline):
    """Efficiency over input speed and output torque (SI).  Shown as its headline figures
    (:meth:`headline`); ``plot()`` draws the map."""

    input_speed: np.ndarray        # (s,) [rad/s]
    output_torque: np.ndarray      # (t,) [N*m]
    efficiency: np.ndarray         # (s, t) output power / input power
    input_torque: np.ndarray       # (s, t) [N*m] mean input torque
    no_load_running_torque: np.ndarray  # (s,) [N*m] mean input torque at zero output torque
    starting_torque: float         # [N*m] largest input torque at zero load at creep speed
    ratio: float
    positions: int
    friction: bool                 # False: the reducer has no friction (efficiency 1)
    status: str
    wall_s: float
    temperature: float = 40.0      # [degC] operating temperature of the lubricant
    oil_viscosity: float = 0.0     # [m^2/s] its kinematic viscosity there (ASTM D341)
    seal_torque_input: float = 0.0   # [N*m] input seals' drag torque
    seal_torque_output: float = 0.0  # [N*m] output seals' drag torque
    rated_torque: float = math.nan   # [N*m] the reducer's (reducer.rating.rated_torque)
    torque_resolution: float = 0.0   # [N*m] input torques below it were round-off: shown as 0

    def speeds_rpm(self) -> np.ndarray:
        """The input speeds [rpm] as given (the rad/s round trip left 1500.0000000000002)."""
        return np.array([float(f"{n:.12g}") for n in self.input_speed / RPM])

    def summary(self) -> dict:
        """The JSON keys of ``rvsim efficiency`` (speeds in rpm, torques in N*m; efficiency a
        fraction under ``efficiency``, as since its first version, and in % under
        ``efficiency_pct``, the unit of the console and the report)."""
        rpm = self.speeds_rpm()
        return {
            "efficiency": [{"input_speed_rpm": float(n), "output_torque_nm": float(t),
                            "efficiency": float(self.efficiency[i, j]),
                            "efficiency_pct": 100.0 * float(self.efficiency[i, j])}
                           for i, n in enumerate(rpm) for j, t in enumerate(self.output_torque)],
            "no_load_running_torque_nm": float(self.no_load_running_torque[0]),
            "no_load_running_torque": [{"input_speed_rpm": float(n), "torque_nm": float(t)}
                                       for n, t in zip(rpm, self.no_load_running_torque)],
            "starting_torque_nm": float(self.starting_torque),
            "starting_speed_rpm": STARTING_SPEED_RPM,
            "ratio": self.ratio,
            "positions": self.positions,
            "friction": self.friction,
            "temperature_c": self.temperature,
            "oil_viscosity_mm2_s": from_si(self.oil_viscosity, "mm^2/s"),
            "seal_torque_input_nm": self.seal_torque_input,
            "seal_torque_output_nm": self.seal_torque_output,
            "input_torque_resolution_nm": self.torque_resolution,
            "wall_s": self.wall_s,
            "status": self.status,
        }

    def headline(self) -> tuple[str, list[tuple]]:
        """Status, the map's size and the report's opening rows
        (:func:`rvsim.analysis.headline.efficiency_rows`): the repr."""
        from ..analysis.headline import efficiency_rows

        rated = self.rated_torque if math.isfinite(self.rated_torque) \
            else float(np.max(self.output_torque))
        rows = without_status(efficiency_rows(self.to_frame(), self.summary(), rated))
        if not self.friction:            # the report's note: 1 by construction, not a figure
            rows.insert(0, ("friction", "none in this parameter set: efficiency 1, no running "
                            "or starting torque (set contact.friction_coefficient, friction.*)"))
        return (f"Efficiency map: {self.status}, {len(self.input_speed)} speeds x "
                f"{len(self.output_torque)} torques ({number(self.wall_s, 's', 3)} wall)", rows)

    def plot(self, ax=None):
        """The efficiency map (:func:`rvsim._efficiency_report.efficiency_plot`); returns the
        first panel's Axes."""
        return draw(figure("rvsim._efficiency_report", "efficiency_plot"), ax, self,
                    panels=True)

    def percent_table(self):
        """Efficiency [%] to 0.01, output torques [N*m] as rows by input speeds [rpm] as columns
        (the console's and the report's table)."""
        frame = self.to_frame()
        return (100.0 * frame.pivot(index="output_torque_nm", columns="input_speed_rpm",
                                    values="efficiency")).round(2)

    def to_frame(self):
        """One row per (input speed, output torque) point."""
        import pandas as pd

        rpm = self.speeds_rpm()
        rows = [{"input_speed_rpm": rpm[i],
                 "output_torque_nm": self.output_torque[j],
                 "input_torque_nm": self.input_torque[i, j],
                 "efficiency": self.efficiency[i, j]}
                for i in range(len(self.input_speed)) for j in range(len(self.output_torque))]
        return pd.DataFrame(rows)


def _values(name: str, values, *, allow_zero: bool) -> np.ndarray:
    try:
        array = np.asarray(values, dtype=float).ravel()
    except (TypeError, ValueError):
        raise ParameterError(name, f"must be numbers (got {values!r})") from None
    if array.size == 0:
        raise ParameterError(name, "needs at least one value")
    if not np.all(np.isfinite(array)):
        raise ParameterError(name, "every value must be a finite number")
    if np.any(array < 0) or (not allow_zero and np.any(array == 0)):
        raise ParameterError(name, "every value must be positive")
    if len(np.unique(array)) != array.size:
        raise ParameterError(name, "a value is given twice")
    return array


def _crank_period(reducer: Reducer) -> float:
    """Input angle of one revolution of the eccentrics relative to the carrier [rad]."""
    if reducer.layout.single_stage:
        return 2.0 * math.pi
    return 2.0 * math.pi * abs(reducer.ratio) / reducer.cycloid.pin_count


def _mean_input_torque(reducer, speed, torque, angles):
    from .transmission import solve_path

    path = solve_path(reducer, angles, np.full(len(angles), torque),
                      input_speed=math.copysign(speed, reducer.ratio))
    if path.status != "ok":
        raise SimulationError(path.status, f"efficiency point at {speed / RPM:g} rpm, "
                              f"{torque:g} N*m: {path.status.replace('_', ' ')}")
    return path.input_torque


def _point_efficiency(reducer, speed, torque, angles) -> tuple[float, float]:
    """(efficiency, mean input torque [N*m]) at input ``speed`` [rad/s], output ``torque``."""
    mean = float(np.mean(_mean_input_torque(reducer, speed, torque, angles)))
    return torque / (reducer.ratio * mean), mean


def _angles(reducer: Reducer, positions: int) -> np.ndarray:
    """Input angles of one point's sweep, forwards (the input turns in the sense that turns
    the output forwards), ``positions`` over one crank revolution relative to the carrier."""
    from ..analysis.sampling import MAX_POSITIONS

    if isinstance(positions, bool) or not isinstance(positions, (int, np.integer)) \
            or not 2 <= positions <= MAX_POSITIONS:
        # 10**9 asked numpy for 7.45 GiB
        raise ParameterError("positions", f"must be an integer from 2 to {MAX_POSITIONS} "
                             f"(got {positions!r})")
    return math.copysign(1.0, reducer.ratio) * np.arange(positions) \
        * _crank_period(reducer) / positions


def _check_loads(reducer: Reducer, loads: np.ndarray, field: str) -> None:
    """Output torques from the resolved floor up to what the reducer may carry."""
    from ..parameters.rating import check_torque

    rated = reducer.rating.rated_torque
    floor = RESOLVED_TORQUE_FRACTION * rated
    if np.any(loads < floor * (1.0 - 1e-9)):     # the floor itself, as printed, is in
        raise ParameterError(field, f"output torques from {floor:.3g} N*m, "
                             f"{RESOLVED_TORQUE_FRACTION:g} of the rated {rated:g} N*m (got "
                             f"{loads.min():g}): below it the solver's tolerance is more than "
                             "0.1 % of the input torque")
    check_torque(reducer, float(np.max(loads)), field)


def efficiency_points(reducer: Reducer, speeds_rpm, torques, *,
                      positions: int = POSITIONS) -> np.ndarray:
    """Efficiency at each (input speed [rpm], output torque [N*m]) pair, the map's formula
    point by point (a calibration's points are not a grid); 1 for a reducer without
    friction.  Raises as :func:`efficiency`."""
    validate(reducer)
    speeds = np.asarray(speeds_rpm, dtype=float).ravel()
    loads = np.asarray(torques, dtype=float).ravel()
    if speeds.shape != loads.shape or speeds.size == 0:
        raise ParameterError("speeds", "one input speed per output torque, at least one")
    if not (np.all(np.isfinite(speeds)) and np.all(speeds > 0)
            and np.all(speeds <= MAX_SPEED_RPM)):
        raise ParameterError("speeds", f"input speeds must be positive, up to "
                             f"{MAX_SPEED_RPM:g} rpm")
    _check_loads(reducer, loads, "torques")
    from ..friction import has_friction, lubricant_viscosity

    lubricant_viscosity(reducer)                  # refuses a temperature outside its law
    if not has_friction(reducer):
        return np.ones(speeds.size)
    angles = _angles(reducer, positions)
    return np.array([_point_efficiency(reducer, n * RPM, t, angles)[0]
                     for n, t in zip(speeds, loads)])


def efficiency(reducer: Reducer, *, speeds_rpm=None, torques=None,
               positions: int = POSITIONS) -> EfficiencyResult:
    """Efficiency map at the input ``speeds_rpm`` [rpm] and output ``torques`` [N*m]
    (defaults: :data:`DEFAULT_SPEEDS_RPM`, :data:`DEFAULT_TORQUE_FRACTIONS` of the rated
    torque), the no-load running torque at each speed and the starting torque.

    A reducer without friction has efficiency 1 and zero running and starting torque (the
    result says so in ``friction``).  A point that does not converge raises
    :class:`~rvsim.errors.SimulationError`."""
    validate(reducer)
    speeds = _values("speeds", DEFAULT_SPEEDS_RPM if speeds_rpm is None else speeds_rpm,
                     allow_zero=False)
    if np.any(speeds > MAX_SPEED_RPM):
        raise ParameterError("speeds", f"input speeds up to {MAX_SPEED_RPM:g} rpm (got "
                             f"{speeds.max():g})")
    speeds = speeds * RPM
    rated = reducer.rating.rated_torque
    loads = _values("torques", np.array(DEFAULT_TORQUE_FRACTIONS) * rated if torques is None
                    else torques, allow_zero=False)
    _check_loads(reducer, loads, "torques")
    angles = _angles(reducer, positions)
    from ..friction import has_friction, lubricant_viscosity, seal_torques

    viscosity = lubricant_viscosity(reducer)      # refuses a temperature outside its law
    seal_in, seal_out = seal_torques(reducer)

    clock = RunClock()      # the map's wall time, without numba compiling the solver
    ratio = reducer.ratio
    eff = np.ones((len(speeds), len(loads)))
    t_in = np.zeros((len(speeds), len(loads)))
    no_load = np.zeros(len(speeds))
    for i, speed in enumerate(speeds):
        for j, load in enumerate(loads):
            eff[i, j], t_in[i, j] = _point_efficiency(reducer, speed, load, angles)
        no_load[i] = float(np.mean(_mean_input_torque(reducer, speed, 0.0, angles)))
    starting = float(np.max(np.abs(_mean_input_torque(reducer, STARTING_SPEED_RPM * RPM, 0.0,
                                                      angles))))
    friction = has_friction(reducer)
    if not friction:
        # exactly 1 and 0 by construction: what the sweeps left is the solver's round-off
        eff[:] = 1.0
        no_load[:] = 0.0
        starting = 0.0
    # the solver's residual (TOLERANCE of the rated torque on the output) seen on the input:
    # a running torque below it is round-off (1.95e-11 N*m with mesh friction only), not a result
    resolution = TOLERANCE * rated / abs(ratio)
    no_load[np.abs(no_load) < resolution] = 0.0
    starting = 0.0 if abs(starting) < resolution else starting
    return EfficiencyResult(input_speed=speeds, output_torque=loads, efficiency=eff,
                            input_torque=t_in, no_load_running_torque=no_load,
                            starting_torque=starting, ratio=ratio, positions=positions,
                            friction=friction, status="ok",
                            wall_s=clock.split()[0],
                            temperature=reducer.operating.temperature, oil_viscosity=viscosity,
                            seal_torque_input=seal_in, seal_torque_output=seal_out,
                            rated_torque=reducer.rating.rated_torque,
                            torque_resolution=resolution)
