"""Field descriptors shared by the parameter dataclasses.

Each numeric field carries its user unit, a one-line description and its admissible range in
``dataclasses.field`` metadata.  Values are stored in SI; :func:`quantity` takes the default in
SI as well.  ``rvsim params`` and the TOML / ``--set`` readers are driven by this metadata.
"""

from __future__ import annotations

import dataclasses
import typing
from typing import Any

__all__ = ["quantity", "count", "flag", "choice", "FieldSpec", "field_specs"]


def quantity(default: float, unit: str, doc: str, *, minimum: float | None = 0.0,
             positive: bool = False, maximum: float | None = None) -> Any:
    """A real-valued field stored in SI, shown to users in ``unit``.

    ``minimum`` is inclusive unless ``positive`` is set (then the value must exceed it).
    """
    return dataclasses.field(default=default, metadata={
        "kind": "float", "unit": unit, "doc": doc, "minimum": minimum,
        "positive": positive, "maximum": maximum})


def count(default: int, doc: str, *, minimum: int = 1, maximum: int | None = None) -> Any:
    """A whole-number field (tooth counts, numbers of parts)."""
    return dataclasses.field(default=default, metadata={
        "kind": "int", "unit": "count", "doc": doc, "minimum": minimum,
        "positive": False, "maximum": maximum})


def flag(default: bool, doc: str) -> Any:
    """A yes/no switch (flexible body on/off, load fluctuation on/off)."""
    return dataclasses.field(default=default, metadata={
        "kind": "bool", "unit": "flag", "doc": doc, "minimum": None,
        "positive": False, "maximum": None})


def choice(default: str, options: tuple[str, ...], doc: str) -> Any:
    """A field that takes one of a few named ``options`` (a text value)."""
    return dataclasses.field(default=default, metadata={
        "kind": "choice", "unit": "choice", "doc": f"{doc} ({' | '.join(options)})",
        "minimum": None, "positive": False, "maximum": None, "options": tuple(options)})


@dataclasses.dataclass(frozen=True)
class FieldSpec:
    """Description of one leaf parameter, addressed by its dotted ``name``."""

    name: str
    kind: str
    unit: str
    doc: str
    minimum: float | None
    positive: bool
    maximum: float | None
    options: tuple[str, ...] = ()


def field_specs(cls: type, prefix: str = "") -> list[FieldSpec]:
    """All leaf fields of a (nested) parameter dataclass, depth first."""
    specs: list[FieldSpec] = []
    hints = typing.get_type_hints(cls)
    for f in dataclasses.fields(cls):
        name = f"{prefix}{f.name}"
        if dataclasses.is_dataclass(hints[f.name]):
            specs.extend(field_specs(hints[f.name], prefix=name + "."))
        elif "kind" in f.metadata:
            m = f.metadata
            specs.append(FieldSpec(name, m["kind"], m["unit"], m["doc"], m["minimum"],
                                   m["positive"], m["maximum"], m.get("options", ())))
    return specs
