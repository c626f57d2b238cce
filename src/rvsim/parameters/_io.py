"""Reading, overriding, validating and listing reducer parameters (user units at this edge).

* ``rvsim params`` lists every dotted name with its unit (:func:`parameter_table`).
* A TOML file mirrors the dataclass tree (``[cycloid] eccentricity = 1.5``), values in the
  listed user units; fields it omits keep the values of the base set (``base = "RV-40E"``).
* ``--set name=value`` overrides one value; Table 2 factor letters (``H=0.02``) are accepted as
  aliases of the parameters they set.
"""

from __future__ import annotations

import dataclasses
import math
import numbers
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from .._files import read_toml
from ..errors import ParameterError, check_type
from ..units import TO_SI, si_from_text
from ._schema import FieldSpec, field_specs
from ._types import Reducer
from .cycloid_drive import CYCLOID_DRIVE
from .rv40e import RV40E, TABLE2_FACTORS
from .friction_values import TYPICAL_FRICTION
from .rv40e_bearings import RV40E_ROLLING

__all__ = ["SPECS", "parameter_table", "get_value", "with_values", "parse_assignment",
           "load_toml", "validate", "resolve_name", "BUILT_IN_SETS", "toml_string", "toml_text",
           "plain_number", "check_reducer"]

#: every leaf parameter of :class:`Reducer`, by dotted name
SPECS: dict[str, FieldSpec] = {s.name: s for s in field_specs(Reducer)}

#: named parameter sets shipped with rvsim
BUILT_IN_SETS: dict[str, Reducer] = {"RV-40E": RV40E, "cycloid-drive": CYCLOID_DRIVE}

_TRUE = {"true", "yes", "y", "1", "on"}
_FALSE = {"false", "no", "n", "0", "off"}


def resolve_name(name: str) -> str:
    """Dotted parameter name for ``name`` (a dotted name or a Table 2 factor letter)."""
    name = name.strip()
    if name in SPECS:
        return name
    if name.upper() in TABLE2_FACTORS and len(name) == 1:
        return TABLE2_FACTORS[name.upper()].parameter
    raise ParameterError(name, "unknown parameter (run 'rvsim params' for the list)")


def get_value(reducer: Reducer, name: str, *, user_units: bool = True) -> Any:
    """Value of parameter ``name``, in its user unit unless ``user_units`` is False."""
    name = resolve_name(name)
    obj: Any = reducer
    for part in name.split("."):
        obj = getattr(obj, part)
    spec = SPECS[name]
    if spec.kind == "float" and user_units:
        return obj / TO_SI[spec.unit]
    return obj


def _coerce(spec: FieldSpec, raw: Any) -> Any:
    """Turn a user-supplied value (str, number, bool) into the field's SI value."""
    if spec.kind == "choice":
        text = str(raw).strip().lower()
        if isinstance(raw, bool) or text not in spec.options:
            raise ParameterError(spec.name, f"'{raw}' is not one of {', '.join(spec.options)}")
        return text
    if spec.kind == "bool":
        if isinstance(raw, bool):
            return raw
        text = str(raw).strip().lower()
        if text in _TRUE:
            return True
        if text in _FALSE:
            return False
        raise ParameterError(spec.name, f"'{raw}' is not a yes/no value (use true or false)")
    if isinstance(raw, bool):
        raise ParameterError(spec.name, f"'{raw}' is not a number")
    try:
        value = plain_number(raw)
    except (TypeError, ValueError):
        si = _with_unit(spec, raw)
        if si is None:
            raise ParameterError(spec.name, f"'{raw}' is not a number") from None
        if not math.isfinite(si):
            raise ParameterError(spec.name, f"'{raw}' is not a finite number") from None
        return si
    if not math.isfinite(value):
        raise ParameterError(spec.name, f"'{raw}' is not a finite number")
    if spec.kind == "int":
        if value != int(value):
            raise ParameterError(spec.name, f"'{raw}' is not a whole number")
        return int(value)
    return value * TO_SI[spec.unit]


def _with_unit(spec: FieldSpec, raw: Any) -> float | None:
    """The SI value of a text typed with a unit ("1000rpm", "5 um"), None for a text that is
    no number with a unit; a unit of another quantity is refused naming the field's unit."""
    if not isinstance(raw, str):
        return None
    try:
        return si_from_text(raw, spec.unit)
    except ValueError as exc:
        raise ParameterError(spec.name, str(exc)) from None


def plain_number(raw) -> float:
    """``float(raw)``, except that a text with digit groups is no number (ValueError): Python
    reads "1_0" as 10, a grouping no data file or command line means.  The one check of every
    number read from text (--set, files, the command line's options and lists)."""
    if isinstance(raw, str) and "_" in raw:
        raise ValueError(raw)
    return float(raw)


def _replace_path(obj: Any, parts: list[str], value: Any) -> Any:
    if len(parts) == 1:
        return dataclasses.replace(obj, **{parts[0]: value})
    child = getattr(obj, parts[0])
    return dataclasses.replace(obj, **{parts[0]: _replace_path(child, parts[1:], value)})


def with_values(reducer: Reducer, values: dict[str, Any], *, check: bool = True) -> Reducer:
    """A copy of ``reducer`` with parameters set from user-unit ``values``, validated."""
    check_reducer(reducer)
    check_type(values, Mapping, "values", "a dict of parameter names (or factor letters) to "
               "values in user units, e.g. {\"H\": 0.02}")
    for raw_name, raw in values.items():
        name = resolve_name(raw_name)
        reducer = _replace_path(reducer, name.split("."), _coerce(SPECS[name], raw))
    if check:
        validate(reducer)
    return reducer


def parse_assignment(text: str) -> tuple[str, str]:
    """Split ``name=value`` as given to ``--set``."""
    name, sep, value = text.partition("=")
    if not sep or not name.strip():
        raise ParameterError(text, "expected name=value")
    if not value.strip():
        raise ParameterError(name.strip(), "no value after '='")
    return resolve_name(name), value.strip()


_TOML_ESCAPES = {'"': '\\"', "\\": "\\\\", "\b": "\\b", "\t": "\\t", "\n": "\\n",
                 "\f": "\\f", "\r": "\\r"}


def toml_string(text: str) -> str:
    """``text`` as a TOML basic string (quoted; quotes, backslashes and control characters
    escaped), which :mod:`tomllib` reads back unchanged."""
    out = []
    for ch in text:
        if ch in _TOML_ESCAPES:
            out.append(_TOML_ESCAPES[ch])
        elif ord(ch) < 0x20 or ord(ch) == 0x7F:
            out.append(f"\\u{ord(ch):04X}")
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


def _flatten(table: dict, prefix: str = "") -> dict[str, Any]:
    flat: dict[str, Any] = {}
    for key, value in table.items():
        name = f"{prefix}{key}"
        if isinstance(value, dict):
            flat.update(_flatten(value, name + "."))
        else:
            flat[name] = value
    return flat


def load_toml(path: str | Path, base: Reducer | None = None) -> Reducer:
    """Read a reducer from a TOML file in user units (see module docstring)."""
    check_type(path, (str, os.PathLike), "path", "the path of a TOML file")
    path = Path(path)
    data = read_toml(path, "reducer TOML file")
    base_name = data.pop("base", None)
    for key, value in (("base", base_name), ("name", data.get("name"))):
        if value is not None and not (isinstance(value, str) and value.strip()):
            raise ParameterError(key, f"must be a non-empty text string in {path.name} "
                                 f"(got {value!r})")
    if base is None:
        base_name = base_name or "RV-40E"
        if base_name not in BUILT_IN_SETS:
            raise ParameterError("base", f"unknown parameter set '{base_name}' "
                                 f"(built in: {', '.join(BUILT_IN_SETS)})")
        base = BUILT_IN_SETS[base_name]
    name = data.pop("name", None)
    if name is not None:
        base = dataclasses.replace(base, name=str(name))
    values = _flatten(data)
    for key in values:
        if key not in SPECS:
            raise ParameterError(key, f"unknown parameter in {path.name} "
                                 "(run 'rvsim params' for the list)")
    return with_values(base, values)


#: largest magnitude of any quantity in SI units (a Young's modulus is 2e11 Pa, the stiffest
#: element a few 1e10 N/m): beyond it a value is a unit error, refused before the geometry's
#: formulas overflow on it (a module of 1e308 mm raised OverflowError)
SI_CEILING = 1e15
#: largest count (teeth, pins, rollers, holes): a count beyond it would only exhaust memory
COUNT_CEILING = 100_000


def validate(reducer: Reducer, *, assembly: bool = True) -> Reducer:
    """Check ranges and the physical consistency of ``reducer``; return it unchanged.

    Raises :class:`ParameterError` naming the first offending field.  ``assembly=False``
    leaves out the check that the parts do not overlap at the assembled pose (a tolerance
    study counts such reducers as binding, not as invalid).

    The value checks (:func:`check_values`) live here; the checks that need the geometry
    (profile, gear stage, layout, play, element sizes, parts, assembly) live in
    :func:`rvsim.geometry.checks.check_geometry`, imported lazily: this forwarder is the one
    import of ``parameters`` from a higher layer (issue 31 step 4, docs/decisions.md), kept so
    that the public ``rvsim.parameters.validate`` and ``load_toml`` refuse a bad geometry.
    """
    check_values(reducer)
    from ..geometry.checks import check_geometry   # the allowed upward import (lazy)

    check_geometry(reducer, assembly=assembly)
    return reducer


def check_reducer(reducer, field: str = "reducer") -> Reducer:
    """``reducer`` if it is a parameter set, else the one ParameterError of every entry point
    (a name such as "RV-40E" is no set: BUILT_IN_SETS[name] or load_toml(path) is)."""
    return check_type(reducer, Reducer, field, "a parameter set (rvsim.parameters.Reducer: "
                      "rvsim.RV40E, rvsim.BUILT_IN_SETS[name], rvsim.load_toml(path))")


def check_values(reducer: Reducer) -> Reducer:
    """The checks that need no geometry: every field's type and range, then the consistency
    of fields with each other (counts, stages, axial stations, the load schedule).  Raises
    :class:`ParameterError` naming the first offending field; returns ``reducer``."""
    check_reducer(reducer)
    for spec in SPECS.values():
        try:
            value = get_value(reducer, spec.name, user_units=False)
        except AttributeError:     # a group replaced by something else (dataclasses.replace)
            raise ParameterError(spec.name, "missing: its group is not a parameter group")
        if spec.kind == "choice":
            if not isinstance(value, str) or value not in spec.options:
                raise ParameterError(spec.name, f"'{value}' is not one of "
                                     f"{', '.join(spec.options)}")
            continue
        # a value set in Python (dataclasses.replace) has not been through _coerce: its type
        # is checked here ("no" for a flag was taken as true)
        is_flag = isinstance(value, bool) or type(value).__name__ == "bool_"   # numpy's too
        if spec.kind == "bool":
            if not is_flag:
                raise ParameterError(spec.name, f"must be true or false (got {value!r})")
            continue
        if is_flag or not isinstance(value, numbers.Real):
            raise ParameterError(spec.name, f"must be a number (got {value!r})")
        if spec.kind == "int" and not isinstance(value, numbers.Integral):
            raise ParameterError(spec.name, f"must be a whole number (got {value!r})")
        if not math.isfinite(value):
            raise ParameterError(spec.name, "must be a finite number")
        unit = TO_SI[spec.unit]
        if spec.minimum is not None:
            if spec.positive and value <= spec.minimum:
                raise ParameterError(spec.name, f"must be greater than {spec.minimum / unit:g} "
                                     f"{spec.unit} (got {value / unit:g})")
            if not spec.positive and value < spec.minimum:
                raise ParameterError(spec.name, f"must not be negative (got {value / unit:g})"
                                     if spec.minimum == 0 else
                                     f"must be at least {spec.minimum / unit:g} (got "
                                     f"{value / unit:g})")
        if spec.maximum is not None and value > spec.maximum:
            shown = "" if spec.unit in ("-", "count") else f" {spec.unit}"
            raise ParameterError(spec.name, f"must not exceed {spec.maximum / unit:g}{shown} "
                                 f"(got {value / unit:g})")
        # a seed is a whole number but no count: any value up to the general ceiling
        counted = spec.kind == "int" and not spec.name.endswith("_seed")
        ceiling = COUNT_CEILING if counted else SI_CEILING
        if abs(value) > ceiling:          # before any formula overflows on it
            shown = "" if spec.unit in ("-", "count") else f" {spec.unit}"
            size = f"{value:.0f}" if spec.kind == "int" and abs(value) < 1e18 else \
                f"{value / unit:.3g}"
            raise ParameterError(spec.name, f"{size}{shown} is beyond any reducer "
                                 f"(at most {ceiling / unit:g}{shown})")
    _check_consistency(reducer)
    return reducer


def _check_consistency(r: Reducer) -> None:
    c, e, k, op = r.cycloid, r.errors, r.crank, r.operating
    if c.pin_count != c.disc_teeth + 1:
        raise ParameterError("cycloid.pin_count", f"must equal disc_teeth + 1 = "
                             f"{c.disc_teeth + 1} for a cycloid drive (got {c.pin_count})")
    if r.layout.stages not in (1, 2):
        raise ParameterError("layout.stages", f"must be 2 (RV reducer) or 1 (single-stage "
                             f"cycloid drive) (got {r.layout.stages})")
    if r.gears.planet_count != 2:
        raise ParameterError("gears.planet_count", "the dynamic model has exactly 2 crankshafts")
    if e.eccentricity >= c.eccentricity:
        raise ParameterError("errors.eccentricity", "must be smaller than the eccentricity")
    if e.pin_radius >= c.pin_radius:
        raise ParameterError("errors.pin_radius", "must be smaller than the pin radius")
    if not k.lower_support_z < k.disc1_z < k.disc2_z < k.upper_support_z:
        raise ParameterError("crank.disc1_z", "axial stations must satisfy lower_support_z < "
                             "disc1_z < disc2_z < upper_support_z")
    if op.load_ramp_end <= op.load_start:
        raise ParameterError("operating.load_ramp_end", "must be later than load_start")
    if op.steady_start >= op.duration:
        raise ParameterError("operating.steady_start", "must be earlier than duration")
    from .rating import check_rating     # rated <= allowable, for every command ('params' too)

    check_rating(r)


def parameter_table(reducer: Reducer) -> list[dict[str, Any]]:
    """Rows (name, value, unit, description) for every parameter, values in user units."""
    rows = []
    for spec in SPECS.values():
        value = get_value(reducer, spec.name)
        rows.append({"name": spec.name, "value": value, "unit": spec.unit, "description": spec.doc})
    return rows


def toml_text(reducer: Reducer) -> str:
    """Every parameter of ``reducer`` as a TOML file that :func:`load_toml` (``--params``)
    reads back: user units, one table per group, each line commented with unit and meaning."""
    lines = [f'base = "RV-40E"\nname = {toml_string(reducer.name)}']
    section = None
    for row in parameter_table(reducer):
        head, _, leaf = row["name"].rpartition(".")
        if head != section:
            lines.append(f"\n[{head}]")
            section = head
        value = row["value"]
        text = (("true" if value else "false") if isinstance(value, bool)
                else toml_string(value) if isinstance(value, str) else f"{value:.12g}")
        lines.append(f"{leaf} = {text}  # [{row['unit']}] {row['description']}")
    return "\n".join(lines) + "\n"


# RV-40E-bearings: the rolling bearings with the friction of a greased reducer
BUILT_IN_SETS["RV-40E-bearings"] = dataclasses.replace(
    with_values(RV40E_ROLLING, TYPICAL_FRICTION, check=False), name="RV-40E-bearings")
