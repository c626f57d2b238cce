"""Tolerance studies: which errors are toleranced, how they are distributed, and realisations.

A tolerance study file (or the built-in ``rv40e-tolerances``) reads::

    name = "my tolerances"
    params = "RV-40E"          # optional: a built-in set's name or a reducer TOML file
    samples = 1000             # Monte Carlo reducers (rvsim tolerance --samples overrides)
    seed = 1                   # realisations are reproducible from it
    positions = 360            # optional: input positions over one output revolution
    [set]                      # nominal values (user units) for every reducer
    "clearances.crank_arm_bushing" = 0.005
    [tolerances.pin_radius]    # a per-part error (FEATURES) or any numeric parameter
    tolerance = 0.003          # mm (arcmin for the phases; a parameter's own unit)
    distribution = "normal"    # "uniform" (default), or "normal" with the tolerance at 3 sigma
    per = "part"               # "part" (default: each pin its own draw) or "feature" (one draw)

Every reducer is a vector of independent uniform numbers in (0, 1) (one per random variable:
a part's error, or a feature's), mapped through the distribution's inverse CDF and scaled by
the tolerance.  Sample i's vector comes from ``numpy.random.default_rng([seed, i])``, so a
sample does not depend on how many are drawn; the tolerances only scale it (common random
numbers: the allocation's search is smooth in them).  docs/tolerances.md gives the sources of
the built-in tolerances.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
from pathlib import Path

import numpy as np

from ..errors import InputFileError, ParameterError
from ..parameters import (BUILT_IN_SETS, RV40E, SPECS, PartErrors, Reducer, get_value,
                          load_toml, resolve_name, with_values)
from ..units import TO_SI

__all__ = ["FEATURES", "DISTRIBUTIONS", "Tolerance", "ToleranceStudy", "load_tolerance_study",
           "rv40e_tolerances", "cycloid_drive_tolerances", "BUILT_IN_TOLERANCE_STUDIES",
           "MAX_SAMPLES", "is_tolerance_file"]

#: most Monte Carlo samples one command may ask for
MAX_SAMPLES = 1_000_000
DISTRIBUTIONS = ("uniform", "normal")
PER = ("part", "feature")

#: per-part errors: name -> (user unit, description)
FEATURES = {
    "pin_radial": ("mm", "each pin centre's radial position"),
    "pin_tangential": ("mm", "each pin centre's position along the pin circle"),
    "pin_radius": ("mm", "each pin's radius"),
    "disc_pitch": ("mm", "each disc tooth's cumulative pitch deviation (along the pin circle)"),
    "disc_phase": ("arcmin", "each disc's teeth turned relative to its crank holes"),
    "profile_form": ("mm", "amplitude of each profile form harmonic of each disc "
                           "(orders: key 'orders', default [2, zc])"),
    "eccentricity": ("mm", "each crank eccentric's eccentricity"),
    "eccentric_phase": ("arcmin", "each crank eccentric's angular position"),
    "disc_holes": ("mm", "each crank hole's position in each disc (x and y)"),
    "carrier_holes": ("mm", "each crank's bore position in the carrier (radial, tangential)"),
}
_KEYS = {"tolerance", "distribution", "per", "orders"}
#: the largest per-part tolerance accepted, by unit: far beyond any reducer that assembles
#: (part errors of a precision reducer are microns); a tolerance meant in um is refused
FEATURE_LIMITS = {"mm": 1.0, "arcmin": 60.0}


def largest_tolerance(name: str) -> float:
    """The largest tolerance of error ``name``: per-part errors by their unit; a parameter's
    has none here (its drawn values are validated as the reducer's)."""
    return FEATURE_LIMITS[FEATURES[name][0]] if name in FEATURES else math.inf


@dataclasses.dataclass(frozen=True)
class Tolerance:
    """One toleranced error: ``name`` is a FEATURES key or a dotted parameter name."""

    name: str
    tolerance: float               # user unit
    distribution: str = "uniform"
    per: str = "part"
    orders: tuple = ()             # profile_form only

    def __post_init__(self):
        # checked here, so that one built in Python is checked as a study file's is (a
        # misspelled distribution was drawn as normal, a NaN tolerance drew NaN parts)
        for field, value in zip(("name", "tolerance", "distribution", "per", "orders"),
                                _checked(self)):
            object.__setattr__(self, field, value)

    @property
    def is_parameter(self) -> bool:
        return self.name not in FEATURES

    @property
    def unit(self) -> str:
        return SPECS[self.name].unit if self.is_parameter else FEATURES[self.name][0]

    def with_tolerance(self, value: float) -> "Tolerance":
        return dataclasses.replace(self, tolerance=float(value))


def _deviation(unit: np.ndarray, distribution: str) -> np.ndarray:
    """Deviation in units of the tolerance from uniform numbers in (0, 1): uniform on
    [-1, 1], or normal with sigma 1/3 truncated at +-1 (3 sigma: parts outside the tolerance
    are rejected at inspection)."""
    unit = np.clip(unit, 1e-12, 1.0 - 1e-12)
    if distribution == "uniform":
        return 2.0 * unit - 1.0
    from scipy.special import ndtr, ndtri

    edge = ndtr(-3.0)                    # the inverse CDF of the normal truncated at +-3 sigma
    return ndtri(edge + unit * (1.0 - 2.0 * edge)) / 3.0


@dataclasses.dataclass(frozen=True)
class ToleranceStudy:
    """A tolerance study: nominal reducer, toleranced errors, sample count, seed."""

    name: str
    tolerances: tuple[Tolerance, ...]
    base: Reducer = RV40E
    fixed: tuple = ()
    samples: int = 1000
    seed: int = 0
    positions: int = 360
    params: str = "RV-40E"
    #: the file's [cost.NAME] tables for the allocation: ((name, ((key, value), ...)), ...)
    cost: tuple = ()
    #: measured profile deviations of every reducer (PartErrors.profile_points; a study
    #: file's ``profile_csv``, rvsim.geometry.deviations.read_profile_csv)
    profile_points: tuple = ()

    def __post_init__(self) -> None:
        seen = set()
        for t in self.tolerances:
            if t.name in seen:
                raise ParameterError(f"tolerances.{t.name}", "given twice")
            seen.add(t.name)
        if not self.tolerances:
            raise ParameterError("tolerances", "needs at least one [tolerances.NAME] table")
        check_samples(self.samples)
        if not (isinstance(self.positions, int) and 8 <= self.positions <= 100_000):
            raise ParameterError("positions", f"must be a whole number from 8 to 100000 "
                                 f"(got {self.positions!r})")
        from ..analysis.sampling import check_positions

        # the pin order and every profile form order drawn, unaliased
        orders = [o for t in self.tolerances if t.name == "profile_form"
                  for o in self.orders(t)]
        check_positions(self.base, self.positions, "positions", orders,
                        order_field="tolerances.profile_form.orders")

    @property
    def nominal(self) -> Reducer:
        """The nominal reducer: the base set with the [set] values and the measured profile
        deviations (validated)."""
        r = with_values(self.base, dict(self.fixed), check=not self.profile_points)
        if self.profile_points:
            from ..parameters import validate

            r = validate(dataclasses.replace(r, parts=PartErrors(
                profile_points=self.profile_points)))
        return r

    def largest_load(self) -> tuple[float, str]:
        """(the largest output torque a reducer of the study is loaded with [N*m], the field
        that sets it): the nominal load, plus its tolerance when it is toleranced (both
        distributions are bounded at one tolerance)."""
        load = abs(self.nominal.operating.load_torque)
        for t in self.tolerances:
            if t.name == "operating.load_torque":
                return load + t.tolerance, f"tolerances.{t.name}"
        return load, "operating.load_torque"

    def part_counts(self) -> dict[str, int]:
        """Parts (values) of each per-part error of the base reducer."""
        r = self.base
        zp, zc = r.cycloid.pin_count, r.cycloid.disc_teeth
        discs = r.layout.disc_count if r.layout.single_stage else 2
        cranks = 1 if r.layout.single_stage else 2
        return {"pin_radial": zp, "pin_tangential": zp, "pin_radius": zp,
                "disc_pitch": discs * zc, "disc_phase": discs,
                "eccentricity": 2 * cranks, "eccentric_phase": 2 * cranks,
                "disc_holes": discs * cranks * 2, "carrier_holes": cranks * 2}

    def sizes(self) -> list[int]:
        """Random variables of each tolerance (columns of the unit vector)."""
        r = self.base
        discs = r.layout.disc_count if r.layout.single_stage else 2
        per_part = self.part_counts()
        out = []
        for t in self.tolerances:
            if t.name == "profile_form":
                out.append(2 * len(self.orders(t)) * (discs if t.per == "part" else 1))
            elif t.is_parameter or t.per == "feature":
                out.append(1)
            else:
                out.append(per_part[t.name])
        return out

    def orders(self, t: Tolerance) -> tuple:
        return t.orders or (2, self.base.cycloid.disc_teeth)

    @property
    def dimension(self) -> int:
        return sum(self.sizes())

    def unit_sample(self, index: int) -> np.ndarray:
        """Sample ``index``'s uniform numbers (reproducible from the seed)."""
        return np.random.default_rng([self.seed, index]).random(self.dimension)

    def realise(self, unit: np.ndarray, tolerances: dict | None = None,
                nominal: Reducer | None = None) -> Reducer:
        """The reducer of one vector of uniform numbers; ``tolerances`` (name -> value in
        user units) overrides the study's.  Not validated: a sample may bind on assembly."""
        r = nominal or self.nominal
        values, parts = {}, {}
        discs = r.layout.disc_count if r.layout.single_stage else 2
        counts = self.part_counts()
        start = 0
        for t, size in zip(self.tolerances, self.sizes()):
            u = np.asarray(unit[start:start + size])
            start += size
            tol = float(tolerances.get(t.name, t.tolerance) if tolerances else t.tolerance)
            if t.is_parameter:
                spec = SPECS[t.name]
                scale = TO_SI[spec.unit]
                value = get_value(r, t.name) + tol * float(_deviation(u, t.distribution)[0])
                if spec.minimum is not None:
                    value = max(value, spec.minimum / scale)
                values[t.name] = value
                continue
            si = tol * TO_SI[t.unit]
            if t.name == "profile_form":
                orders = self.orders(t)
                pairs = u.reshape(-1, 2)
                rows = []
                for disc in range(discs):
                    for k, order in enumerate(orders):
                        a, phase = pairs[k if t.per == "feature" else disc * len(orders) + k]
                        amplitude = si * float(_deviation(np.array([a]), t.distribution)[0])
                        rows.append((disc, int(order), amplitude, 2.0 * math.pi * float(phase)))
                parts["profile_harmonics"] = tuple(rows)
                continue
            dev = si * _deviation(u, t.distribution)
            n = counts[t.name]
            if t.per == "feature":
                dev = np.full(n, dev[0])
            dev = tuple(float(x) for x in dev)
            if t.name in ("disc_pitch", "disc_holes"):
                width = n // discs
                dev = tuple(dev[k * width:(k + 1) * width] for k in range(discs))
            parts[t.name] = dev
        if values:
            r = with_values(r, values, check=False)
        if parts:
            r = dataclasses.replace(r, parts=dataclasses.replace(r.parts, **parts))
        return r

    def definition(self) -> dict:
        """What identifies the study's samples (study.json; the run keys hash it)."""
        return {"name": self.name, "kind": "tolerance", "params": self.params,
                "profile_points": len(self.profile_points) and
                hashlib.sha256(repr(self.profile_points).encode()).hexdigest(),
                "seed": self.seed, "positions": self.positions,
                "fixed": [[k, v] for k, v in self.fixed],
                "tolerances": [dataclasses.asdict(t) for t in self.tolerances]}

    def sample_key(self, label: str, index: int, tolerances: dict | None = None) -> str:
        """Store key of one sample: the study, the design it belongs to, its index, the
        tolerances it was drawn with and the model's source code."""
        from .._fingerprint import model_fingerprint

        payload = {"study": self.definition(), "design": label, "index": int(index),
                   "tolerances": tolerances or {}, "model": model_fingerprint(),
                   "reducer": _reducer_digest(self.base)}
        return hashlib.sha256(json.dumps(payload, sort_keys=True, default=str).encode()
                              ).hexdigest()


def _reducer_digest(r: Reducer) -> str:
    return hashlib.sha256(json.dumps(dataclasses.asdict(r), sort_keys=True, default=str
                                     ).encode()).hexdigest()


def check_samples(samples) -> int:
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) \
            or not 2 <= samples <= MAX_SAMPLES:
        raise ParameterError("samples", f"must be a whole number from 2 to {MAX_SAMPLES} "
                             f"(got {samples!r})")
    return int(samples)


def _tolerance(name: str, spec, path) -> Tolerance:
    where = f"tolerances.{name}"
    if not isinstance(spec, dict):
        raise ParameterError(where, "must be a table with 'tolerance' (and optionally "
                             "'distribution', 'per')")
    unknown = set(spec) - _KEYS
    if unknown:
        raise ParameterError(where, f"unknown key(s) {', '.join(sorted(unknown))} (known: "
                             f"{', '.join(sorted(_KEYS))})")
    name = _error_name(name)
    where = f"tolerances.{name}"
    if "tolerance" not in spec:
        raise ParameterError(f"{where}.tolerance", "missing (the tolerance of the error, in "
                             "its unit)")
    return Tolerance(name, spec.get("tolerance"), spec.get("distribution", "uniform"),
                     spec.get("per", "part"), spec.get("orders", []))


def _error_name(name) -> str:
    """A FEATURES key, or the dotted name of a numeric parameter (its letter alias resolved)."""
    if name in FEATURES:
        return name
    try:
        resolved = resolve_name(name) if isinstance(name, str) else None
    except ParameterError:
        resolved = None
    if resolved is None or resolved not in SPECS or SPECS[resolved].kind != "float":
        raise ParameterError(f"tolerances.{name}", f"unknown error (per-part errors: "
                             f"{', '.join(FEATURES)}; or a numeric parameter of "
                             "'rvsim params')")
    return resolved


def _checked(tolerance: "Tolerance") -> tuple:
    """The fields of a Tolerance, checked (a study file's and one built in Python alike)."""
    name = _error_name(tolerance.name)
    where = f"tolerances.{name}"
    tol, distribution, per, orders = (tolerance.tolerance, tolerance.distribution,
                                       tolerance.per, tolerance.orders)
    if isinstance(tol, bool) or not isinstance(tol, (int, float)) or not math.isfinite(tol):
        raise ParameterError(f"{where}.tolerance", f"needs a finite number (got {tol!r})")
    if tol < 0:
        raise ParameterError(f"{where}.tolerance", f"must not be negative (got {tol:g})")
    if tol > largest_tolerance(name):
        raise ParameterError(f"{where}.tolerance", f"must be at most "
                             f"{largest_tolerance(name):g} {FEATURES[name][0]} (got {tol:g})")
    if distribution not in DISTRIBUTIONS:
        raise ParameterError(f"{where}.distribution", f"unknown distribution {distribution!r} "
                             f"(known: {', '.join(DISTRIBUTIONS)})")
    if per not in PER:
        raise ParameterError(f"{where}.per", f"must be 'part' or 'feature' (got {per!r})")
    if orders and (name != "profile_form" or not isinstance(orders, (list, tuple)) or not all(
            isinstance(o, int) and not isinstance(o, bool) and o >= 1 for o in orders)):
        raise ParameterError(f"{where}.orders", "profile_form only: a list of whole numbers "
                             ">= 1")
    return name, float(tol), distribution, per, tuple(orders)


def is_tolerance_file(path: str | Path) -> bool:
    """Whether a TOML study file has a [tolerances] table (False if it cannot be read)."""
    from .._files import read_toml       # the one reader (bounded, a BOM stripped)
    from ..errors import RvsimError

    try:
        return "tolerances" in read_toml(path)
    except RvsimError:
        return False


def load_tolerance_study(path: str | Path) -> ToleranceStudy:
    """Read a tolerance study TOML file (module docstring); errors name the key at fault."""
    from .._files import read_study_toml

    path = Path(path)
    data = read_study_toml(path)
    known = {"name", "params", "samples", "seed", "positions", "set", "tolerances", "cost",
             "profile_csv"}
    extra = set(data) - known
    if extra:
        raise InputFileError(f"{path}: unknown key(s) {', '.join(sorted(extra))} (a tolerance "
                             f"study knows {', '.join(sorted(known))})")
    params = data.get("params", "RV-40E")
    if not isinstance(params, str) or not params.strip():
        raise InputFileError(f"{path}: 'params' must be a set's name or a file name")
    file = (path.parent / params).resolve()
    base = (BUILT_IN_SETS[params] if params in BUILT_IN_SETS and not file.exists()
            else load_toml(file))
    raw = data.get("tolerances")
    if not isinstance(raw, dict) or not raw:
        raise InputFileError(f"{path}: needs at least one [tolerances.NAME] table")
    tolerances = tuple(_tolerance(name, spec, path) for name, spec in raw.items())
    fixed = _fixed(data.get("set", {}), path)
    seed = data.get("seed", 0)
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise ParameterError("seed", f"must be a whole number >= 0 (got {seed!r})")
    name = data.get("name", path.stem)
    if not isinstance(name, str) or not name.strip():
        raise InputFileError(f"{path}: 'name' must be a non-empty text string")
    study = ToleranceStudy(name=name, tolerances=tolerances, base=base, fixed=fixed,
                           samples=data.get("samples", 1000), seed=seed,
                           positions=data.get("positions", 360), params=params,
                           cost=_cost(data.get("cost", {}), path),
                           profile_points=_profile(data.get("profile_csv"), base, path))
    study.nominal     # the nominal reducer must be valid
    return study


def _profile(name, base: Reducer, path) -> tuple:
    if name is None:
        return ()
    if not isinstance(name, str) or not name.strip():
        raise InputFileError(f"{path}: 'profile_csv' must be a file name")
    from ..geometry.deviations import read_profile_csv

    discs = base.layout.disc_count if base.layout.single_stage else 2
    return read_profile_csv(Path(path).parent / name, discs)


def _cost(raw, path) -> tuple:
    if not isinstance(raw, dict) or not all(isinstance(v, dict) for v in raw.values()):
        raise InputFileError(f"{path}: 'cost' must hold [cost.NAME] tables")
    return tuple((name, tuple(spec.items())) for name, spec in raw.items())


def _fixed(raw, path) -> tuple:
    if not isinstance(raw, dict):
        raise InputFileError(f"{path}: 'set' must be a table of parameter = value")
    fixed = []
    for key, value in raw.items():
        if isinstance(value, (dict, list)):
            raise ParameterError(f"set.{key}", "must be a single value")
        fixed.append((resolve_name(key), value))
    return tuple(fixed)


# features toleranced alike in both built-in studies (values and sources: docs/tolerances.md)
_PRECISION_FIXED = (("errors.equidistant_modification", 0.010),
                    ("clearances.crank_arm_bushing", 0.005),
                    ("errors.pin_hole_clearance", 0.004))
_PRECISION_PINS_AND_DISC = (
    Tolerance("pin_radius", 0.002, "normal"),
    Tolerance("pin_radial", 0.003, "normal"),
    Tolerance("pin_tangential", 0.003, "normal"),
    Tolerance("disc_pitch", 0.005, "normal"),
    Tolerance("profile_form", 0.002, "normal"),
    Tolerance("eccentricity", 0.002, "normal"),
)
_PRECISION_CLEARANCES = (
    Tolerance("errors.pin_hole_clearance", 0.002, "normal"),
    Tolerance("clearances.crank_arm_bushing", 0.003, "normal"),
)


def rv40e_tolerances() -> ToleranceStudy:
    """The built-in tolerance study: the RV-40E with ten toleranced features typical of a
    precision reducer (values and sources: docs/tolerances.md)."""
    return ToleranceStudy(
        name="rv40e-tolerances", params="RV-40E", base=RV40E, samples=1000, seed=1,
        fixed=(("operating.load_torque", 412.0),) + _PRECISION_FIXED,    # rated torque
        tolerances=_PRECISION_PINS_AND_DISC + (
            Tolerance("disc_holes", 0.003, "normal"),
            Tolerance("carrier_holes", 0.003, "normal"),
        ) + _PRECISION_CLEARANCES)


def cycloid_drive_tolerances() -> ToleranceStudy:
    """The single-stage cycloid drive (built-in set ``cycloid-drive``) with the same kind of
    tolerances (docs/tolerances.md)."""
    from ..parameters import BUILT_IN_SETS as SETS

    return ToleranceStudy(
        name="cycloid-drive-tolerances", params="cycloid-drive", base=SETS["cycloid-drive"],
        samples=1000, seed=1,
        fixed=(("operating.load_torque", 200.0),) + _PRECISION_FIXED       # rated torque
        + (("layout.output_pin_clearance", 0.010),),
        tolerances=_PRECISION_PINS_AND_DISC + _PRECISION_CLEARANCES + (
            Tolerance("layout.output_pin_clearance", 0.005, "normal"),
        ))


BUILT_IN_TOLERANCE_STUDIES = {"rv40e-tolerances": rv40e_tolerances,
                              "cycloid-drive-tolerances": cycloid_drive_tolerances}
