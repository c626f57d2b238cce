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
from pathlib import Path
from typing import Any

from .._files import read_toml
from ..errors import ParameterError
from ..units import TO_SI
from ._schema import FieldSpec, field_specs
from ._types import Reducer
from .cycloid_drive import CYCLOID_DRIVE
from .rv40e import RV40E, TABLE2_FACTORS
from .friction_values import TYPICAL_FRICTION
from .rv40e_bearings import RV40E_ROLLING

__all__ = ["SPECS", "parameter_table", "get_value", "with_values", "parse_assignment",
           "load_toml", "validate", "resolve_name", "BUILT_IN_SETS", "toml_string", "toml_text",
           "plain_number"]

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
        raise ParameterError(spec.name, f"'{raw}' is not a number") from None
    if not math.isfinite(value):
        raise ParameterError(spec.name, f"'{raw}' is not a finite number")
    if spec.kind == "int":
        if value != int(value):
            raise ParameterError(spec.name, f"'{raw}' is not a whole number")
        return int(value)
    return value * TO_SI[spec.unit]


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
    """
    if not isinstance(reducer, Reducer):
        raise ParameterError("reducer", f"must be a parameter set (rvsim.parameters.Reducer; "
                             f"got {type(reducer).__name__})")
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
    _check_consistency(reducer, assembly)
    return reducer


def _check_consistency(r: Reducer, assembly: bool = True) -> None:
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
    from ..geometry.cycloid import check_profile

    check_profile(r)
    hole = k.eccentric_radius + k.arm_bushing_thickness
    root = c.pin_circle_radius - c.pin_radius - c.eccentricity
    if r.layout.single_stage:
        _check_single_stage(r, hole, root)
    else:
        _check_rv_layout(r, hole, root)
    _check_clearances(r)
    from ..fe.sizes import check_element_sizes

    check_element_sizes(r)   # the meshes' sizes: refused here, not after another body's mesh
    from ..geometry.validity import check_parts

    check_parts(r)           # every part can exist (pins, bores, rollers, carrier, gears)
    if assembly:
        from ..geometry.assembly import check_assembly

        check_assembly(r)  # every pin, bushing and mesh at the pose the dynamic model starts from


def _check_rv_layout(r: Reducer, hole: float, root: float) -> None:
    c = r.cycloid
    if r.layout.disc_count != 2:
        raise ParameterError("layout.disc_count", "the RV reducer model has 2 discs")
    if r.layout.ring_output:
        raise ParameterError("layout.ring_output", "applies to the single-stage drive only "
                             "(layout.stages = 1); the RV reducer's output is the carrier")
    from ..geometry.involute import check_gear_stage, gear_geometry

    check_gear_stage(r)
    crank_circle = gear_geometry(r).centre_distance
    if crank_circle + hole + c.eccentricity >= root:
        raise ParameterError("crank.eccentric_radius", "the crank holes cut through the disc's "
                             "tooth root (crank circle + hole radius >= root radius)")


#: largest accepted bearing preload (negative radial internal clearance) [m]: real preloads
#: are a few micrometres
MAX_PRELOAD = 0.02e-3

#: RV-only clearances that the single-stage drive replaces by layout.input_bearing_clearance
_RV_ONLY_CLEARANCES = ("support_flange", "support_carrier", "crank_support_bushing")


def _check_single_stage(r: Reducer, hole: float, root: float) -> None:
    """Geometry of the single-stage drive: central eccentric bore, output-pin holes between
    it and the tooth root, bridges between neighbouring holes (docs/model.md section 13)."""
    c, lay = r.cycloid, r.layout
    if lay.disc_count not in (1, 2):
        raise ParameterError("layout.disc_count", f"must be 1 or 2 (got {lay.disc_count})")
    if r.flexibility.model == "fe" and r.flexibility.cycloid_disc:
        # refused here, as the RV reducer's finite-element sizes are, not at the first run
        # (a study ran its other runs, a tolerance study all of its reducers, first)
        raise ParameterError("flexibility.model", "the finite-element disc is built for the "
                             "RV reducer only so far (use closed-form for the single-stage "
                             "drive)")
    for name in _RV_ONLY_CLEARANCES:
        if getattr(r.clearances, name) != 0.0:
            raise ParameterError(f"clearances.{name}", "does not apply to the single-stage "
                                 "drive (use layout.input_bearing_clearance)")
    out_hole = lay.output_pin_radius + c.eccentricity + lay.output_pin_clearance
    if lay.output_pin_circle_radius + out_hole >= root:
        raise ParameterError("layout.output_pin_circle_radius", "the output-pin holes cut "
                             "through the disc's tooth root (R_w + hole radius >= root radius)")
    if lay.output_pin_circle_radius - out_hole <= hole:
        raise ParameterError("layout.output_pin_circle_radius", "the output-pin holes cut "
                             "into the central eccentric bore (R_w - hole radius <= bore)")
    from ..geometry.layout import neighbour_distance

    if neighbour_distance(lay.output_pin_circle_radius, lay.output_pin_count) <= 2.0 * out_hole:
        raise ParameterError("layout.output_pin_count", "neighbouring output-pin holes "
                             "overlap (2 R_w sin(pi / n) <= 2 x hole radius)")


def _check_clearances(r: Reducer) -> None:
    """The bushing clearances between a disc and the housing must stay below the cycloid tooth
    height 2a: with that much play a disc can slip over the pins (docs/parameters.md)."""
    cl = r.clearances
    if r.layout.single_stage:
        play = cl.crank_arm_bushing + cl.disc_arm_bushing + r.layout.input_bearing_clearance
        if play >= 2.0 * r.cycloid.eccentricity:
            raise ParameterError("layout.input_bearing_clearance", f"the play of a disc, K + M "
                                 f"+ input bearing = {play * 1e3:g} mm, reaches the cycloid "
                                 f"tooth height 2a = {2e3 * r.cycloid.eccentricity:g} mm")
        return
    chain = {"clearances.crank_arm_bushing": cl.crank_arm_bushing,
             "clearances.disc_arm_bushing": cl.disc_arm_bushing,
             "clearances.crank_support_bushing": cl.crank_support_bushing,
             "clearances.support_flange": cl.support_flange,
             "clearances.support_carrier": cl.support_carrier}
    b = r.bearings
    for name in ("needle_clearance", "support_clearance"):
        if getattr(b, name) < -MAX_PRELOAD:
            raise ParameterError(f"bearings.{name}", f"a preload (negative clearance) of "
                                 f"{-getattr(b, name) * 1e3:g} mm is far beyond any bearing "
                                 f"preload (at most {MAX_PRELOAD * 1e3:g} mm accepted)")
    if b.arm_needles:
        chain["bearings.needle_clearance"] = 0.5 * max(b.needle_clearance, 0.0)
    if b.support_rollers:
        chain["bearings.support_clearance"] = 0.5 * max(b.support_clearance, 0.0)
    play = (cl.crank_arm_bushing + cl.disc_arm_bushing + cl.crank_support_bushing
            + max(cl.support_flange, cl.support_carrier)
            + chain.get("bearings.needle_clearance", 0.0)
            + chain.get("bearings.support_clearance", 0.0))
    tooth = 2.0 * r.cycloid.eccentricity
    if play >= tooth:
        largest = max(chain, key=chain.get)
        raise ParameterError(largest, f"the play of a disc, K + M + O + max(L, N) (+ half the "
                             f"bearings' internal clearances) = "
                             f"{play * 1e3:g} mm, reaches the cycloid tooth height 2a = "
                             f"{tooth * 1e3:g} mm (the disc could slip over the pins)")


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
