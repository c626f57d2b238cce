"""Reducer parameter sets: dataclasses (SI inside), the paper's RV-40E, TOML and overrides."""

from ._types import (Bearings, Clearances, ContactModel, Crankshaft, CycloidStage, Errors,
                     Flexibility, Friction, GearStage, Material, Materials, Operating, PartErrors,
                     Rating, Reducer, Stiffness)
from .rv40e import (CITATION, RV40E, TABLE2_FACTORS, FactorSpec, paper_l36_scheme,
                    paper_run_values)
from ._io import (BUILT_IN_SETS, SPECS, check_reducer, get_value, load_toml, parameter_table,
                  parse_assignment, plain_number, resolve_name, validate, with_values)

__all__ = [
    "Reducer", "Bearings", "GearStage", "CycloidStage", "Crankshaft", "Errors", "Clearances",
    "Flexibility", "Operating", "ContactModel", "Rating", "Friction", "Material", "Materials",
    "PartErrors", "Stiffness", "RV40E", "CITATION",
    "TABLE2_FACTORS",
    "FactorSpec", "paper_l36_scheme", "paper_run_values", "plain_number", "BUILT_IN_SETS", "SPECS", "get_value", "load_toml", "parameter_table",
    "parse_assignment", "resolve_name", "validate", "with_values", "check_reducer",
]
