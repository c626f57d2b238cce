"""Study definitions: factors mapped to reducer parameters, a design, fixed settings.

A study is a frozen dataclass; :func:`paper_l36` is the paper's Table 2 / Table 3 study and
:func:`load_study` reads a TOML file such as::

    name = "pin tolerances"
    design = "L9"             # any orthogonal array, "full", "lhs" or "sobol"
    samples = 32              # lhs / sobol only
    seed = 1
    params = "my_reducer.toml"   # optional; default: the built-in RV-40E
    engine = "quasi-static"   # optional; default "dynamic" (rvsim.doe.engines)
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
import tomllib
from pathlib import Path

import numpy as np
import pandas as pd

from ..errors import InputFileError, ParameterError
from ..parameters import (RV40E, TABLE2_FACTORS, Reducer, load_toml, resolve_name,
                          with_values)
from . import designs

__all__ = ["StudyFactor", "Study", "paper_l36", "load_study", "BUILT_IN_STUDIES"]


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

    @property
    def is_sampling(self) -> bool:
        return self.design in ("lhs", "sobol")

    def table(self) -> pd.DataFrame:
        """The runs: column ``run`` and one column per factor (level number or value)."""
        labels = [f.label for f in self.factors]
        if self.is_sampling:
            n = self.samples or 0
            if n < 2:
                raise ParameterError("samples", f"the {self.design} design needs samples >= 2")
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
    """The paper's study: Table 2 factors A-O on L36(2^4 x 3^11), as in Table 3."""
    factors = tuple(StudyFactor(letter, spec.parameter, spec.levels)
                    for letter, spec in TABLE2_FACTORS.items())
    return Study(name="paper-l36", factors=factors, design="L36")


BUILT_IN_STUDIES = {"paper-l36": paper_l36}


def load_study(path: str | Path) -> Study:
    """Read a study TOML file (see module docstring)."""
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise InputFileError(f"{path}: file not found") from None
    except tomllib.TOMLDecodeError as exc:
        raise InputFileError(f"{path}: not valid TOML ({exc})") from None
    known = {"name", "design", "samples", "seed", "params", "set", "factors", "time_step",
             "engine", "hysteresis"}  # issue 9: engine, hysteresis
    extra = set(data) - known
    if extra:
        raise InputFileError(f"{path}: unknown key(s) {', '.join(sorted(extra))}")
    base = RV40E
    if "params" in data:
        base = load_toml((path.parent / data["params"]).resolve())
    design = str(data.get("design", "L36"))
    sampling = design in ("lhs", "sobol")
    raw_factors = data.get("factors")
    if not isinstance(raw_factors, dict) or not raw_factors:
        raise InputFileError(f"{path}: needs at least one [factors.X] table")
    factors = []
    for label, spec in raw_factors.items():
        if not isinstance(spec, dict) or "parameter" not in spec:
            raise InputFileError(f"{path}: factor {label} needs a 'parameter'")
        parameter = resolve_name(spec["parameter"])
        if sampling:
            bounds = spec.get("range")
            if not (isinstance(bounds, list) and len(bounds) == 2):
                raise ParameterError(f"factors.{label}.range", "needs [low, high] for "
                                     f"the {design} design")
            factors.append(StudyFactor(label, parameter, low=float(bounds[0]),
                                       high=float(bounds[1])))
        else:
            levels = spec.get("levels")
            if not (isinstance(levels, list) and len(levels) >= 2):
                raise ParameterError(f"factors.{label}.levels", "needs a list of at least 2 "
                                     "levels")
            factors.append(StudyFactor(label, parameter, tuple(levels)))
    fixed = tuple((resolve_name(k), v) for k, v in data.get("set", {}).items())
    from .engines import engine_options  # issue 9: quasi-static engine

    engine, hysteresis = engine_options(data, path)
    study = Study(name=str(data.get("name", path.stem)), factors=tuple(factors), design=design,
                  base=base, fixed=fixed, samples=data.get("samples"),
                  seed=int(data.get("seed", 0)), time_step=data.get("time_step"),
                  engine=engine, hysteresis=hysteresis)
    study.reducers()  # validate every run now
    return study
