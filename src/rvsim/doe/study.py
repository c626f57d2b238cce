"""Study definitions: factors mapped to reducer parameters, a design, fixed settings.

A study is a frozen dataclass; :func:`paper_l36` is the paper's Table 2 / Table 3 study and
:func:`load_study` reads a TOML file such as::

    name = "pin tolerances"
    design = "L9"             # any orthogonal array, "full", "lhs" or "sobol"
    samples = 32              # lhs / sobol only
    seed = 1
    params = "my_reducer.toml"   # optional; default: the built-in RV-40E; or a built-in
                                 # set's name ("cycloid-drive")
    engine = "quasi-static"   # optional; default "dynamic" (rvsim.doe.engines)
    scheme = "implicit-bearings"   # optional, dynamic engine; default "explicit"
                                   # (rvsim.simulate's integration scheme)
    hysteresis = true         # quasi-static only: add the torque-reversal test
    [set]                     # fixed values for every run (user units)
    "operating.load_torque" = 300
    [factors.H]
    parameter = "errors.pin_circle_radius"
    levels = [0.01, 0.02, 0.03]
    [factors.I]
    parameter = "errors.equidistant_modification"
    range = [0.0, 0.05]       # lhs / sobol: uniform between the bounds

Every run's reducer is built and validated before anything is simulated, so an unknown
parameter or a level outside the valid range stops the study at once with a clear error.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pandas as pd

from .._files import read_study_toml
from ..errors import InputFileError, ParameterError
from ..parameters import (BUILT_IN_SETS, RV40E, TABLE2_FACTORS, Reducer, load_toml, resolve_name,
                          with_values)
from ..analysis._table import RESULT_COLUMNS   # the columns besides the factors (re-exported)
from . import designs

__all__ = ["StudyFactor", "Study", "paper_l36", "load_study", "study_from_data",
           "BUILT_IN_STUDIES", "MAX_RUNS", "RESULT_COLUMNS"]

#: most runs a study may have: beyond this the design table alone strains memory and the runs
#: would take weeks (docs/decisions.md)
MAX_RUNS = 100_000


@dataclasses.dataclass(frozen=True)
class StudyFactor:
    """One factor: a column label, the parameter it sets, and its levels or range."""

    label: str
    parameter: str
    levels: tuple = ()
    low: float | None = None
    high: float | None = None


@dataclasses.dataclass(frozen=True)
class Study:
    """A design of experiments on the dynamic model."""

    name: str
    factors: tuple[StudyFactor, ...]
    design: str = "L36"
    base: Reducer = RV40E
    fixed: tuple[tuple[str, object], ...] = ()
    samples: int | None = None
    seed: int = 0
    time_step: float | None = None
    # issue 9: the model that evaluates each run (rvsim.doe.engines)
    engine: str = "dynamic"
    hysteresis: bool = False
    # issue 14: the dynamic engine's integration scheme (rvsim.simulate)
    scheme: str = "explicit"
    # issue 33 item 2: noise factors (rvsim.tolerance.robust.Noise): every run is then built
    # noise.samples times with drawn part errors; doe uses only its protocol (definition(),
    # evaluator(study), columns(study)) and never imports the package that makes it
    noise: object = None

    def __post_init__(self) -> None:
        seen_labels: set[str] = set()
        by_parameter: dict[str, str] = {}
        for f in self.factors:
            if not f.label.strip():
                kind = "blank" if f.label else "empty"
                raise ParameterError("factors", f"a factor's label is {kind} ({f.label!r}): "
                                     "give it a name, e.g. [factors.H]")
            if f.label != f.label.strip() or "," in f.label:
                raise ParameterError(f"factors.{f.label}", "a label must not start or end with "
                                     "a space or contain a comma (it is a column name)")
            if f.label.lower() in RESULT_COLUMNS or \
                    f.label.lower().startswith("te_"):
                raise ParameterError(f"factors.{f.label}", "this label is a column of "
                                     "results.csv (run, status, key, te_..., ...): choose "
                                     "another label")
            if f.label in seen_labels:
                raise ParameterError(f"factors.{f.label}", "label used twice")
            seen_labels.add(f.label)
            # the dotted name, whatever alias a Study built in Python gives (load_study
            # resolves them; "H" and "errors.pin_circle_radius" are one parameter)
            parameter = resolve_name(f.parameter)
            if parameter in by_parameter:
                raise ParameterError(f"factors.{f.label}", f"sets {parameter}, which factor "
                                     f"{by_parameter[parameter]} already varies")
            by_parameter[parameter] = f.label
        fixed_names: set[str] = set()
        for name, _ in self.fixed:
            name = resolve_name(name)
            if name in by_parameter:
                raise ParameterError(f"set.{name}", f"is also varied by factor "
                                     f"{by_parameter[name]}: remove one of them")
            if name in fixed_names:
                raise ParameterError(f"set.{name}", "set twice (a letter alias and its "
                                     "dotted name name the same parameter)")
            fixed_names.add(name)
        from ..dynamics.model import EXPLICIT
        from ..dynamics.simulate import MAX_TIME_STEP, check_scheme

        check_scheme(self.scheme)
        from .engines import ENGINES

        if self.engine not in ENGINES:
            raise ParameterError("engine", f"must be one of {', '.join(ENGINES)} (got "
                                 f"{self.engine!r})")
        if not isinstance(self.hysteresis, bool) or (self.hysteresis
                                                     and self.engine != "quasi-static"):
            raise ParameterError("hysteresis", "true or false, and true only with the "
                                 f"quasi-static engine (got {self.hysteresis!r})")
        if self.time_step is not None and self.engine != "dynamic":
            # it did nothing but enter the folder's identity, which the command line (that
            # refuses --time-step here) then could not match
            raise ParameterError("time_step", f"the study runs the {self.engine} engine, "
                                 "which takes no time step")
        if self.scheme != EXPLICIT and self.engine != "dynamic":
            raise ParameterError("scheme", f"the study runs the {self.engine} engine: the "
                                 "integration scheme is the dynamic engine's (set "
                                 "scheme = \"explicit\")")

        if self.time_step is not None and not (
                isinstance(self.time_step, (int, float)) and not isinstance(self.time_step, bool)
                and 0 < self.time_step <= MAX_TIME_STEP):
            raise ParameterError("time_step", f"must be a number of seconds in "
                                 f"(0, {MAX_TIME_STEP:g}] (got {self.time_step!r})")
        if self.is_sampling:
            if not (isinstance(self.samples, int) and 2 <= self.samples <= MAX_RUNS):
                raise ParameterError("samples", f"the {self.design} design needs a whole "
                                     f"number of samples from 2 to {MAX_RUNS} "
                                     f"(got {self.samples!r})")
        elif self.design == "full":
            runs = math.prod(len(f.levels) for f in self.factors)
            if runs > MAX_RUNS:
                raise ParameterError("design", f"the full factorial has {runs:.4g} runs, more "
                                     f"than the {MAX_RUNS} a study may have (use an orthogonal "
                                     "array, lhs or sobol)")

    @property
    def is_sampling(self) -> bool:
        return self.design in ("lhs", "sobol")

    def table(self) -> pd.DataFrame:
        """The runs: column ``run`` and one column per factor (level number or value)."""
        labels = [f.label for f in self.factors]
        if self.is_sampling:
            n = self.samples
            unit = (designs.latin_hypercube if self.design == "lhs" else designs.sobol)(
                n, len(self.factors), self.seed)
            values = np.column_stack([f.low + unit[:, i] * (f.high - f.low)
                                      for i, f in enumerate(self.factors)])
            frame = pd.DataFrame(values, columns=labels)
        else:
            counts = [len(f.levels) for f in self.factors]
            if self.design == "full":
                levels = designs.full_factorial(counts)
            else:
                levels = designs.assign_columns(designs.orthogonal_array(self.design), counts,
                                                self.design)
            frame = pd.DataFrame(levels, columns=labels)
        frame.insert(0, "run", np.arange(1, len(frame) + 1))
        return frame

    def values(self, row: pd.Series) -> dict[str, object]:
        """Parameter values (user units) of one design row, fixed settings included."""
        out: dict[str, object] = dict(self.fixed)
        for f in self.factors:
            value = row[f.label]
            out[f.parameter] = value if self.is_sampling else f.levels[int(value) - 1]
        return out

    def reducers(self) -> list[Reducer]:
        """The validated reducer of every run (raises before any simulation)."""
        table = self.table()
        out = []
        for _, row in table.iterrows():
            try:
                out.append(with_values(self.base, self.values(row)))
            except ParameterError as exc:
                raise ParameterError(exc.field, f"{exc.reason} (study run {int(row['run'])})"
                                     ) from None
        return out


def paper_l36() -> Study:
    """The paper's study: Table 2 factors A-O on L36(2^4 x 3^11), as in Table 3.

    It runs the integration scheme ``implicit-bearings`` (in about half the explicit scheme's
    time): on these 36 runs the study's index, the mean TE, agrees with the explicit scheme's
    to 7.2e-5 relative, and its analysis keeps the factor order, significant factors and
    optimum (ranges within 7.8e-5 arcmin, p-values within 0.006); the peak answers carry the
    scheme's bias of about 0.3 % (docs/decisions.md, "The paper's study runs
    implicit-bearings").  ``dataclasses.replace(paper_l36(), scheme="explicit")`` or
    ``--scheme explicit`` runs the reference scheme."""
    factors = tuple(StudyFactor(letter, spec.parameter, spec.levels)
                    for letter, spec in TABLE2_FACTORS.items())
    return Study(name="paper-l36", factors=factors, design="L36", scheme="implicit-bearings")


BUILT_IN_STUDIES = {"paper-l36": paper_l36}


def load_study(path: str | Path) -> Study:
    """Read a study TOML file (see module docstring); every error names the key at fault.
    A file with a [noise] section is a robust study: :func:`rvsim.tolerance.load_robust_study`
    reads it (and ``rvsim study``)."""
    path = Path(path)
    data = read_study_toml(path)
    if "noise" in data:
        raise InputFileError(f"{path}: has a [noise] section: a robust study, read by "
                             "rvsim.tolerance.load_robust_study (or 'rvsim study')")
    return study_from_data(data, path)


def study_from_data(data: dict, path: Path) -> Study:
    """The study of a study file's TOML ``data`` read from ``path`` (:func:`load_study`)."""
    known = {"name", "design", "samples", "seed", "params", "set", "factors", "time_step",
             "engine", "hysteresis", "scheme"}
    extra = set(data) - known
    if extra:
        raise InputFileError(f"{path}: unknown key(s) {', '.join(sorted(extra))}")
    base = RV40E
    if "params" in data:
        params = _string(data, "params", path)
        file = (path.parent / params).resolve()
        # a built-in set's name when no file of that name exists
        base = (BUILT_IN_SETS[params] if params in BUILT_IN_SETS and not file.exists()
                else load_toml(file))
    design = _string(data, "design", path, "L36")
    sampling = design in ("lhs", "sobol")
    raw_factors = data.get("factors")
    if not isinstance(raw_factors, dict) or not raw_factors:
        raise InputFileError(f"{path}: needs at least one [factors.X] table")
    factors = [_factor(label, spec, design, sampling, path)
               for label, spec in raw_factors.items()]
    raw_set = data.get("set", {})
    if not isinstance(raw_set, dict):
        raise InputFileError(f"{path}: 'set' must be a table of parameter = value")
    fixed = []
    for key, value in raw_set.items():
        if isinstance(value, (dict, list)):
            raise ParameterError(f"set.{key}", "must be a single value")
        fixed.append((resolve_name(key), value))
    samples = data.get("samples")
    if samples is not None and not _is_int(samples):
        raise ParameterError("samples", f"must be a whole number (got {samples!r})")
    seed = data.get("seed", 0)
    if not _is_int(seed) or seed < 0:
        raise ParameterError("seed", f"must be a whole number >= 0 (got {seed!r})")
    time_step = data.get("time_step")
    if time_step is not None and (isinstance(time_step, bool)
                                  or not isinstance(time_step, (int, float))):
        raise ParameterError("time_step", f"must be a number of seconds (got {time_step!r})")
    from .engines import engine_options

    engine, hysteresis = engine_options(data, path)
    scheme = _string(data, "scheme", path, "explicit")
    study = Study(name=_string(data, "name", path, path.stem), factors=tuple(factors),
                  design=design, base=base, fixed=tuple(fixed), samples=samples, seed=seed,
                  time_step=None if time_step is None else float(time_step), engine=engine,
                  hysteresis=hysteresis, scheme=scheme)
    for key in ("samples", "seed"):               # a key that would do nothing
        if key in data and not study.is_sampling:
            raise ParameterError(key, f"is for the lhs and sobol designs only (this "
                                 f"study's design is {study.design}: its runs are its "
                                 "table's)")
    study.reducers()  # validate every run now
    return study


def _is_int(value) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def _string(data: dict, key: str, path: Path, default: str | None = None) -> str:
    value = data.get(key, default)
    if not isinstance(value, str) or not value.strip():
        raise InputFileError(f"{path}: '{key}' must be a non-empty text string (got {value!r})")
    return value


def _level_value(parameter: str, level):
    """The level as the parameter's SI value (a text with a unit converted), to find a level
    given twice in two spellings; the level itself where it is no valid value (refused later,
    naming the run)."""
    from ..parameters._io import SPECS, _coerce

    try:
        return _coerce(SPECS[parameter], level)
    except (ParameterError, KeyError):
        return level


def _factor(label: str, spec, design: str, sampling: bool, path: Path) -> StudyFactor:
    if not isinstance(spec, dict):
        raise InputFileError(f"{path}: factors.{label} must be a table with 'parameter' and "
                             f"{'range' if sampling else 'levels'}")
    if not isinstance(spec.get("parameter"), str):
        raise ParameterError(f"factors.{label}.parameter", "needs a parameter name as text "
                             f"(got {spec.get('parameter')!r}; see 'rvsim params')")
    unknown = set(spec) - {"parameter", "levels", "range"}
    if unknown:
        raise ParameterError(f"factors.{label}", f"unknown key(s) {', '.join(sorted(unknown))}")
    parameter = resolve_name(spec["parameter"])
    if sampling:
        bounds = spec.get("range")
        if not (isinstance(bounds, list) and len(bounds) == 2 and all(map(_is_number, bounds))):
            raise ParameterError(f"factors.{label}.range", "needs [low, high], two finite "
                                 f"numbers, for the {design} design (got {bounds!r})")
        if not bounds[0] < bounds[1]:
            raise ParameterError(f"factors.{label}.range", f"low must be below high "
                                 f"(got {bounds!r})")
        return StudyFactor(label, parameter, low=float(bounds[0]), high=float(bounds[1]))
    levels = spec.get("levels")
    if not (isinstance(levels, list) and len(levels) >= 2):
        raise ParameterError(f"factors.{label}.levels", "needs a list of at least 2 levels")
    if any(isinstance(v, (dict, list)) for v in levels):
        raise ParameterError(f"factors.{label}.levels", "levels must be single values")
    values = [_level_value(parameter, v) for v in levels]   # "0um" and "0mm" are one level
    repeated = [(v, levels[values.index(values[i])]) for i, v in enumerate(levels)
                if values[i] in values[:i]]
    if repeated:
        level, first = repeated[0]
        same = "" if first == level else f" (as {first!r})"
        raise ParameterError(f"factors.{label}.levels", f"level {level!r} is given twice{same}")
    return StudyFactor(label, parameter, tuple(levels))
