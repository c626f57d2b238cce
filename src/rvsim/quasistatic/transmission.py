"""Quasi-static transmission error of the loaded reducer over an output revolution: :func:`ltca`.

The input turns in one direction in equal steps; at each step the whole reducer is solved for
static equilibrium under the output torque (:mod:`rvsim.quasistatic._solver`), each position
continued from the previous one.  docs/model.md, "Quasi-static analysis".
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping

import numpy as np

from .._cache_guard import RunClock
from .._display import Headline, draw, figure, number, without_status
from .._stopping import check_stop
from ..errors import ParameterError, SimulationError, check_type
from ..parameters import Reducer, check_reducer, validate
from ..physics._status import STATUS_NOT_CONVERGED, STATUS_OK, STATUS_SINGULAR, STATUS_TEXT
from ..units import ARCMIN

__all__ = ["ltca", "LtcaResult", "solve_path", "PathSolution", "TOLERANCE", "MAX_ITERATIONS",
           "CHUNK"]

#: converged when every residual force (torques over their lever) is below this fraction of
#: rated torque / centre distance (412 N*m / 45 mm x 1e-7 = 9e-4 N for the RV-40E; the force
#: elements' own round-off is ~1e-4 N)
TOLERANCE = 1e-7
#: Newton iterations allowed per position
MAX_ITERATIONS = 200
#: points solved per call of the compiled sweep: between calls Python sees a Ctrl-C (a compiled
#: loop cannot be interrupted), ~0.5 s of work for the RV-40E; a longer path restarts the
#: contact foot points and the tangent predictor at each chunk (same equilibria, to the
#: tolerance; paths up to this length are solved in one call)
CHUNK = 4000


@dataclasses.dataclass
class PathSolution:
    """Equilibria along a path of (input angle, output torque) points (SI)."""

    q: np.ndarray                  # (n, 17) generalised coordinates
    pin_forces: np.ndarray         # (n, 2, zp)
    contact_stress: np.ndarray     # (n, 2, zp)
    channels: np.ndarray           # (n, N_CHANNELS) force channels of the dynamic layout
    mesh_state: np.ndarray         # (n, 2, 2) (stiffness, deflection) per mesh
    torsional_stiffness: np.ndarray  # (n,)
    iterations: np.ndarray         # (n,)
    input_torque: np.ndarray       # (n,)
    status_codes: np.ndarray       # (n,) physics._status codes, -1 not reached
    status: str
    wall_s: float
    force_resolution: float = 0.0  # [N] the residual tolerance: smaller forces are not resolved
    output_pin_forces: np.ndarray = None  # (n, 2, n_w) single-stage output pins (n_w = 0: RV)
    #: (n, 17) generalised friction forces of each equilibrium (None: frictionless model)
    friction_forces: np.ndarray = None


def _finite(name: str, value: float) -> float:
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise ParameterError(name, f"must be a number (got {value!r})") from None
    if not math.isfinite(value):
        raise ParameterError(name, f"must be a finite number (got {value})")
    return value


#: the quasi-static engine's friction velocity [m/s]: friction follows the direction of travel
#: (Coulomb); any sliding faster than this carries the full friction force
QS_FRICTION_VELOCITY = 1e-9


def solve_path(reducer: Reducer, input_angle, torque, *, q_start=None, input_speed=None,
               carrier_rate=None, stiffen=None) -> PathSolution:
    """Static equilibria at the points (input_angle[k] [rad], torque[k] [N*m]) in order, each
    started from the previous one (the first from the ideal pose at its input angle, or
    ``q_start``).  Stops at the first point that does not converge; its status is returned.

    Friction (a reducer with any friction element) follows the direction of travel at each
    point: the kinematic motion at ``input_speed[k]`` [rad/s] plus the elastic motion at the
    output speed ``carrier_rate[k]`` [rad/s] with the input held (docs/model.md section 15);
    without them, or without friction, the frictionless model is solved.

    ``stiffen`` (element name -> factor; :func:`rvsim.physics.stiffening.stiffen`): those
    elements give that many times their force at every approach, for the compliance budget
    (None: the model as it is, P untouched).  A point of such a path that does not converge
    is solved again by continuation in the factor (:func:`_continued`) and the path goes on
    from there.  The contact stresses stay those of the unstiffened pin contact law at the
    solved forces."""
    from ..physics import _layout as L
    from ..physics.compliance import effective_modulus
    from ..dynamics.model import build_model
    from . import _solver as S

    validate(reducer)
    angle = np.ascontiguousarray(input_angle, dtype=float)
    load = np.ascontiguousarray(torque, dtype=float)
    if angle.ndim != 1 or load.shape != angle.shape or angle.size == 0:
        # the compiled sweep reads torque[k] for every angle: a shorter array was read past
        raise ParameterError("torque", f"needs one torque per input angle, both 1-D and not "
                             f"empty (got {load.shape} and {angle.shape})")
    if not (np.all(np.isfinite(angle)) and np.all(np.isfinite(load))):
        raise ParameterError("torque", "the input angles and torques must be finite")
    check_type(stiffen, (Mapping, type(None)), "stiffen", "a dict of element names to "
               "factors (rvsim.physics.stiffening.elements_in) or None")
    model = build_model(reducer, 1e-5)
    factors = dict(stiffen or {})
    P = model.P
    n, zp = len(angle), reducer.cycloid.pin_count
    scale = np.ones(L.N_DOF)
    # rotations times a length of their body: the crank circle and planet base radius (RV),
    # the output pin circle (the pin circle with the ring as output) and the eccentric's
    # radius (single-stage)
    single = reducer.layout.single_stage
    scale[L.CARRIER] = ((P[L.RG] if reducer.layout.ring_output else P[L.OUT_RADIUS]) if single
                        else P[L.CENTRE_DIST])
    for j in range(2):
        scale[L.CRANK0 + L.CRANK_STRIDE * j + 4] = (reducer.crank.eccentric_radius if single
                                                    else P[L.RB2])
    for d in range(2):
        scale[L.DISC0 + L.DISC_STRIDE * d + 2] = P[L.RG]
    m = reducer.materials
    from ..friction import has_friction

    moving = np.zeros(n) if input_speed is None else np.broadcast_to(
        np.asarray(input_speed, dtype=float), (n,)).copy()
    turning = np.zeros(n) if carrier_rate is None else np.broadcast_to(
        np.asarray(carrier_rate, dtype=float), (n,)).copy()
    problem = _Problem(model=model, scale=scale,
                       tol=TOLERANCE * reducer.rating.rated_torque / scale[L.CARRIER],
                       hertz=np.array([effective_modulus(m.cycloid_disc, m.pin),
                                       reducer.cycloid.disc_width]),
                       angle=angle, load=load, moving=moving, turning=turning,
                       friction=has_friction(reducer) and bool(moving.any() or turning.any()))
    if q_start is None:
        q_start = np.zeros(L.N_DOF)
        S.kinematic_pose(P, angle[0], model.holes, q_start)
    out = _new_solution(n, zp, int(P[L.OUT_COUNT]))
    if problem.friction:
        out.friction_forces = np.zeros((n, L.N_DOF))
    constants = _constants(model, factors, 1.0, problem.friction)
    clock = RunClock()      # the solve's wall time, without numba compiling the solver
    q0 = np.asarray(q_start, dtype=float)
    solved, continued = 0, {}
    while solved < n:
        part = slice(solved, min(solved + CHUNK, n))
        done = _sweep(problem, constants, q0, part, out, part)
        solved += done
        check_stop()        # a Ctrl-C or SIGTERM whose exception was swallowed on its way
        failed = done < part.stop - part.start or out.status_codes[solved - 1] != STATUS_OK
        k = solved - 1
        if failed and factors and k not in continued and out.status_codes[k] != STATUS_SINGULAR:
            q, iterations, code = _continued(problem, factors, out.q[k - 1] if k else q0, k)
            continued[k] = iterations
            if q is not None:
                solved, q0 = k, q
                continue
            if code == STATUS_SINGULAR:          # the reason the continuation stopped
                out.status_codes[k] = code
        if failed:
            break
        q0 = out.q[solved - 1].copy()
    for k, iterations in continued.items():
        out.iterations[k] += iterations
    out.wall_s, _ = clock.split()
    out.force_resolution = problem.tol
    worst = int(out.status_codes[solved - 1]) if solved else STATUS_NOT_CONVERGED
    out.status = STATUS_TEXT[worst]
    return out


@dataclasses.dataclass
class _Problem:
    """What every part of one path solves: the model, the coordinates' scales, the force
    tolerance [N], (E*, disc width) for the Hertz pressures and the path's points."""

    model: object
    scale: np.ndarray
    tol: float
    hertz: np.ndarray
    angle: np.ndarray
    load: np.ndarray
    moving: np.ndarray             # input speed of each point [rad/s]
    turning: np.ndarray            # output speed of each point [rad/s]
    friction: bool                 # the friction follows the direction of travel


def _new_solution(n: int, zp: int, n_out: int) -> PathSolution:
    """An unsolved path of ``n`` points (every status -1)."""
    from ..physics import _layout as L

    return PathSolution(q=np.zeros((n, L.N_DOF)), pin_forces=np.zeros((n, 2, zp)),
                        contact_stress=np.zeros((n, 2, zp)),
                        channels=np.zeros((n, L.N_CHANNELS)), mesh_state=np.zeros((n, 2, 2)),
                        torsional_stiffness=np.full(n, np.nan),
                        iterations=np.zeros(n, dtype=np.int64), input_torque=np.zeros(n),
                        status_codes=np.full(n, -1, dtype=np.int64), status="ok", wall_s=0.0,
                        output_pin_forces=np.zeros((n, 2, n_out)))


def _constants(model, factors: dict, power: float, friction: bool) -> tuple:
    """(P, FE disc tables, friction constants) of ``model`` with each element of ``factors``
    stiffened factor ** ``power`` times (``factors`` empty: the model's own arrays, not
    copied); the friction constants are an empty vector for the frictionless model."""
    from ..physics import _layout as L

    P, fe_tables = model.P, model.fe
    if factors:
        from ..physics.stiffening import stiffen as stiffened

        P, fe_tables = stiffened(P, fe_tables, {name: s if power == 1.0 else s ** power
                                                for name, s in factors.items()})
    P_fric = np.zeros(0)                  # frictionless (S.sweep)
    if friction:
        P_fric = P.copy()
        P_fric[L.ZETA] = 0.0
        P_fric[L.V_FRIC] = QS_FRICTION_VELOCITY
    return P, fe_tables, P_fric


def _sweep(problem: _Problem, constants: tuple, q0: np.ndarray, points: slice,
           out: PathSolution, rows: slice) -> int:
    """The compiled sweep of the path's ``points`` from ``q0`` into ``out``'s ``rows`` with
    the model's ``constants`` (:func:`_constants`); returns the number of points solved."""
    from . import _solver as S

    P, fe_tables, P_fric = constants
    model, p = problem.model, points
    friction = (out.friction_forces[rows] if out.friction_forces is not None
                else np.zeros((rows.stop - rows.start, len(q0))))
    try:
        return S.sweep(P, problem.hertz, q0, problem.angle[p], problem.load[p], problem.scale,
                       problem.tol, MAX_ITERATIONS, model.pins, model.holes,
                       model.crank_angles, model.mesh_phase, out.q[rows], out.pin_forces[rows],
                       out.contact_stress[rows], out.channels[rows], out.mesh_state[rows],
                       out.torsional_stiffness[rows], out.status_codes[rows],
                       out.iterations[rows], out.input_torque[rows],
                       out.output_pin_forces[rows], P_fric, problem.moving[p],
                       problem.turning[p], friction, fe_tables)
    except np.linalg.LinAlgError:
        # stiffnesses that span too many decades (stiffness.pins = 1e8 on the RV-40E) make
        # the condensed stiffness singular in double precision: the point reached fails
        # with the budget's status word (it was a LinAlgError traceback)
        codes = out.status_codes[rows]
        k = int(np.argmax(codes == -1))
        codes[k] = STATUS_SINGULAR
        return k + 1


#: stiffening factor gained per step of the continuation of :func:`_continued` (a decade: one
#: step of it moves an equilibrium by a few trust radii, docs/model.md section 12)
CONTINUATION_STEP = 10.0


def _continued(problem: _Problem, factors: dict, q_before: np.ndarray, k: int):
    """(equilibrium of point ``k`` with the elements stiffened by ``factors``, iterations, 0),
    or (None, iterations, the failed step's status code) where a step fails, by continuation
    in the factor: the point solved first with the model's own laws from the previous
    point's equilibrium ``q_before``, then with the factors raised a decade at a time
    (:data:`CONTINUATION_STEP`), each from the last.  Where the point's equilibrium lies
    across a clearance from ``q_before`` (the torque-reversal test's first point past zero
    torque), a stiffened element turns the crossing into hundreds of rejected trust-region
    steps against its contact; the model's own laws cross it as every test does, and each
    decade then moves the bodies by a fraction of their deflection (docs/decisions.md, issue
    30/32 fourth session)."""
    decades = max(abs(math.log(s) / math.log(CONTINUATION_STEP)) for s in factors.values())
    steps = max(1, math.ceil(decades - 1e-9))
    from ..physics import _layout as L

    scratch = _new_solution(1, problem.model.pins.shape[0], int(problem.model.P[L.OUT_COUNT]))
    if problem.friction:
        scratch.friction_forces = np.zeros((1, len(q_before)))
    q, iterations = np.array(q_before, dtype=float), 0
    for step in range(steps + 1):
        constants = _constants(problem.model, factors, step / steps, problem.friction)
        _sweep(problem, constants, q, slice(k, k + 1), scratch, slice(0, 1))
        iterations += int(scratch.iterations[0])
        if scratch.status_codes[0] != STATUS_OK:
            return None, iterations, int(scratch.status_codes[0])
        q = scratch.q[0].copy()
    return q, iterations, 0


@dataclasses.dataclass(repr=False)
class LtcaResult(Headline):
    """Loaded tooth contact analysis over an output revolution (SI; contract of issue 9).
    Shown as its headline figures (:meth:`headline`); ``plot()`` draws the TE over the
    revolution."""

    input_angle: np.ndarray        # (n,) [rad]
    output_angle: np.ndarray       # (n,) [rad] carrier at equilibrium
    te: np.ndarray                 # (n,) [rad] input_angle / ratio - output_angle
    torque: float                  # [N*m]
    ratio: float
    pin_count: int
    disc_teeth: int
    pin_forces: np.ndarray         # (n, discs, zp) [N] (discs: 2, or 1 for a one-disc drive)
    contact_stress: np.ndarray     # (n, discs, zp) [Pa] maximum Hertz pressure
    arm_forces: np.ndarray         # (n, 2, 2) [N] (crank, disc)
    support_forces: np.ndarray     # (n, 2, 2) [N] (crank, lower/upper)
    mesh_forces: np.ndarray        # (n, 2) [N]
    mesh_stiffness: np.ndarray     # (n, 2) [N/m]
    torsional_stiffness: np.ndarray  # (n,) [N*m/rad] local dT/dtheta_out, input held
    status: str
    wall_s: float
    converged: np.ndarray          # (n,) bool
    iterations: np.ndarray         # (n,) Newton iterations per position
    force_resolution: float = 0.0  # [N] pin forces up to this are below the solver's tolerance
    #: (n, discs, n_w) [N] output pins in the discs' holes (single-stage drive; n_w = 0: RV)
    output_pin_forces: np.ndarray = None
    rated_torque: float | None = None  # [N*m] the reducer's (reducer.rating.rated_torque)
    #: [Pa] the reducer's rating.static_contact_stress (ISO 76's static limit)
    static_contact_stress: float | None = None

    @property
    def te_relative(self) -> np.ndarray:
        """TE relative to the loaded, clearance-taken-up state: te minus its mean [rad] (what a
        rig that zeroes its encoders while running measures)."""
        return self.te - np.mean(self.te[self.converged]) if self.converged.any() else self.te

    @property
    def pins_in_contact(self) -> np.ndarray:
        """(n, discs) number of loaded pins of each disc: forces above the solver's force
        resolution (at zero torque the round-off forces of touching pins are no contact)."""
        return np.count_nonzero(self.pin_forces > self.force_resolution, axis=2)

    def summary(self) -> dict:
        """The issue's JSON keys (TE in arcmin, forces in N, stress in MPa; pins in contact
        counted per disc; stiffness: mean of the local stiffness over the revolution)."""
        from ..analysis.catalogue import transmission_error_pp

        ok = self.converged
        te = self.te[ok] / ARCMIN
        contacts = self.pins_in_contact[ok]
        empty = not ok.any()
        nan = float("nan")
        ate, revolutions = self.ate()
        return {
            "te_mean_arcmin": nan if empty else float(np.mean(te)),
            "te_pp_arcmin": nan if te.size < 2 else transmission_error_pp(te),
            "ate_arcmin": ate,
            "te_window_revolutions": revolutions,
            "max_pin_force_n": nan if empty else float(self.pin_forces[ok].max()),
            "pins_in_contact_min": -1 if empty else int(contacts.min()),
            "pins_in_contact_max": -1 if empty else int(contacts.max()),
            "max_contact_stress_mpa": nan if empty else float(self.contact_stress[ok].max()
                                                               / 1e6),
            "torsional_stiffness_nm_per_arcmin": nan if empty else float(
                np.mean(self.torsional_stiffness[ok]) * ARCMIN),
            "torque_nm": self.torque,
            "positions": int(len(self.te)),
            "wall_s": self.wall_s,
            "status": self.status,
            **self._contact_stress_verdict(),
        }

    def _stress_check(self) -> tuple[str, str | None] | None:
        """(verdict, warning text or None) of the largest contact stress against the static
        limit (rvsim.parameters.rating.contact_stress_verdict); None without a limit."""
        if self.static_contact_stress is None:
            return None
        from ..parameters.rating import contact_stress_verdict

        ok = self.converged
        stress = float(self.contact_stress[ok].max()) if ok.any() else float("nan")
        return contact_stress_verdict(stress, self.static_contact_stress)

    def _contact_stress_verdict(self) -> dict:
        """``static_contact_stress_mpa`` and ``contact_stress_verdict`` of the summary (none
        without a limit)."""
        check = self._stress_check()
        if check is None:
            return {}
        return {"static_contact_stress_mpa": self.static_contact_stress / 1e6,
                "contact_stress_verdict": check[0]}

    def contact_stress_warning(self) -> str | None:
        """The warning line's text when the largest contact stress is above the static limit
        (else None)."""
        check = self._stress_check()
        return None if check is None else check[1]

    def headline(self) -> tuple[str, list[tuple]]:
        """Status, torque and the report's opening rows
        (:func:`rvsim.analysis.headline.ltca_rows`), stiffness and contacts: the repr."""
        from ..analysis.headline import ltca_rows

        m = self.summary()
        rows = without_status(ltca_rows(m, self.rated_torque))
        rows += [("torsional stiffness (mean)", number(m["torsional_stiffness_nm_per_arcmin"],
                                                       "N*m/arcmin")),
                 ("largest pin force", number(m["max_pin_force_n"], "N")),
                 ("pins in contact per disc", f"{m['pins_in_contact_min']} to "
                                              f"{m['pins_in_contact_max']}"
                  if m["pins_in_contact_min"] >= 0 else number(None))]
        return (f"LTCA at {number(m['torque_nm'], 'N*m')}: {m['status']}, {m['positions']} "
                f"positions ({number(m['wall_s'], 's', 3)} wall)", rows)

    def plot(self, ax=None):
        """TE [arcmin] over the output revolution, absolute and minus its mean
        (:func:`rvsim.plots.te_revolution_plot`); returns the first panel's Axes."""
        return draw(figure("rvsim.plots", "te_revolution_plot"), ax, self, panels=True)

    def ate(self) -> tuple[float, float]:
        """(ATE [arcmin], output revolutions covered): the angular transmission error, the
        peak-to-peak TE over one output revolution (the largest over complete ones,
        :func:`rvsim.analysis.catalogue.angular_transmission_error`) at the nominal output
        angles input_angle / ratio; NaN when the positions cover less than a revolution or one
        of its positions did not converge (docs/decisions.md, issue 33)."""
        from ..analysis.catalogue import angular_transmission_error

        te = np.where(self.converged, self.te, 0.0) / ARCMIN     # as te_pp_arcmin, to the bit
        ate, revolutions = angular_transmission_error(self.input_angle / self.ratio, te)
        return (ate if self.converged.all() else float("nan")), revolutions

    def to_frame(self):
        """One row per position, SI with the unit in each column name: angles [rad], TE
        [rad and arcmin], stiffness [N*m/rad], forces [N], stress [Pa]."""
        import pandas as pd

        frame = {
            "input_angle_rad": self.input_angle, "output_angle_rad": self.output_angle,
            "te_rad": self.te, "te_arcmin": self.te / ARCMIN,
            "te_relative_arcmin": self.te_relative / ARCMIN,
            "torsional_stiffness_nm_per_rad": self.torsional_stiffness,
        }
        for d in range(self.pin_forces.shape[1]):
            frame[f"pins_in_contact_disc{d + 1}"] = self.pins_in_contact[:, d]
        frame["max_pin_force_n"] = self.pin_forces.max(axis=(1, 2))
        frame["max_contact_stress_pa"] = self.contact_stress.max(axis=(1, 2))
        if self.output_pin_forces is not None and self.output_pin_forces.shape[2]:
            frame["max_output_pin_force_n"] = self.output_pin_forces.max(axis=(1, 2))
        for j in range(2):
            frame[f"mesh_force_{j + 1}_n"] = self.mesh_forces[:, j]
            frame[f"mesh_stiffness_{j + 1}_n_per_m"] = self.mesh_stiffness[:, j]
            for d in range(2):
                frame[f"arm_force_{j + 1}{d + 1}_n"] = self.arm_forces[:, j, d]
            for s, name in enumerate(("lower", "upper")):
                frame[f"support_force_{j + 1}_{name}_n"] = self.support_forces[:, j, s]
        frame["converged"] = self.converged
        return pd.DataFrame(frame)

    def spectrum(self):
        """Amplitude of the TE against orders of the output revolution [arcmin]."""
        import pandas as pd

        from ..analysis.catalogue import order_spectrum

        # the nominal output angle: equally spaced over whole revolutions, as order_spectrum
        # needs (the equilibrium output angle carries the TE itself)
        orders, amplitude = order_spectrum(self.input_angle / self.ratio, self.te)
        return pd.DataFrame({"order": orders, "amplitude_arcmin": np.asarray(amplitude)
                             / ARCMIN})


def ltca(reducer: Reducer, *, torque: float | None = None, positions: int = 360,
         revolutions: float = 1.0, raise_on_failure: bool = True,
         allow_aliasing: bool = False) -> LtcaResult:
    """TE and contact loads at ``positions`` equally spaced input angles over ``revolutions``
    output revolutions (input from 0 to revolutions * 2 pi * ratio, one direction) under the
    output ``torque`` [N*m] (default: reducer.operating.load_torque).

    ``positions / revolutions`` (per output revolution) must resolve the reducer's highest
    order (:func:`rvsim.analysis.sampling.check_positions`, the command line's check: 81 for the
    RV-40E's 40 pins), else a :class:`~rvsim.errors.ParameterError`; ``allow_aliasing=True``
    skips it for a probe of a few poses (its TE curve, peak-to-peak and spectrum are then
    aliased, not the reducer's).

    A position that does not converge stops the sweep: with ``raise_on_failure`` (default) a
    :class:`~rvsim.errors.SimulationError` names it, else the result carries the status and
    ``converged`` marks the positions solved.
    """
    check_reducer(reducer)
    torque = _finite("torque", reducer.operating.load_torque if torque is None else torque)
    if isinstance(positions, bool) or not isinstance(positions, (int, np.integer)) \
            or positions < 2:
        raise ParameterError("positions", f"must be an integer >= 2 (got {positions!r})")
    from ..analysis.sampling import MAX_POSITIONS

    if positions > MAX_POSITIONS:           # 1e9 asked numpy for 7.45 GiB (or the OOM killer)
        raise ParameterError("positions", f"must be at most {MAX_POSITIONS}, the most the "
                             f"command line takes (got {positions})")
    from ..parameters.rating import check_torque

    check_torque(reducer, torque, "torque")
    revolutions = _finite("revolutions", revolutions)
    if revolutions <= 0:
        raise ParameterError("revolutions", f"must be positive (got {revolutions:g})")
    if not allow_aliasing:
        from ..analysis.sampling import check_positions

        # per output revolution (the bench model's sweep: points + 1 over (points + 1) /
        # points revolutions, i.e. points per revolution)
        per_revolution = round(positions / revolutions, 9)
        # the count checked is per output revolution: over a part of one, what was typed
        given = "" if revolutions == 1.0 else (f" (positions {positions} over "
                                               f"{revolutions:g} output revolutions)")
        check_positions(reducer, int(per_revolution) if per_revolution.is_integer()
                        else per_revolution, "positions", given=given)
    from ..physics import _layout as L

    from ..geometry.layout import disc_count

    discs = disc_count(reducer)
    ratio = reducer.ratio
    input_angle = np.arange(positions) * (2.0 * math.pi * ratio * revolutions / positions)
    # friction follows the input turning forwards at the operating speed
    path = solve_path(reducer, input_angle, np.full(positions, torque),
                      input_speed=reducer.operating.input_speed)
    converged = path.status_codes == STATUS_OK
    ch = path.channels
    result = LtcaResult(
        input_angle=input_angle, output_angle=path.q[:, L.CARRIER].copy(),
        te=input_angle / ratio - path.q[:, L.CARRIER], torque=torque, ratio=ratio,
        pin_count=reducer.cycloid.pin_count, disc_teeth=reducer.cycloid.disc_teeth,
        pin_forces=path.pin_forces[:, :discs], contact_stress=path.contact_stress[:, :discs],
        arm_forces=ch[:, L.CH_ARM_F00:L.CH_ARM_F11 + 1].reshape(-1, 2, 2),
        support_forces=ch[:, L.CH_SUP_FL0:L.CH_SUP_FU1 + 1].reshape(-1, 2, 2),
        mesh_forces=ch[:, L.CH_MESH_F0:L.CH_MESH_F1 + 1].copy(),
        mesh_stiffness=path.mesh_state[:, :, 0].copy(),
        torsional_stiffness=path.torsional_stiffness, status=path.status, wall_s=path.wall_s,
        converged=converged, iterations=path.iterations,
        force_resolution=path.force_resolution,
        output_pin_forces=path.output_pin_forces[:, :discs],
        rated_torque=reducer.rating.rated_torque,
        static_contact_stress=reducer.rating.static_contact_stress)
    result.te[~converged] = np.nan
    if path.status != "ok" and raise_on_failure:
        k = int(np.argmax(path.status_codes != 0))
        raise SimulationError(path.status, f"quasi-static analysis stopped at position {k} "
                              f"(input angle {input_angle[k]:.6g} rad): "
                              f"{path.status.replace('_', ' ')}")
    return result
