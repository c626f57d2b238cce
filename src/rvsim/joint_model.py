"""A reducer as a robot joint: the JSON file ``rvsim hysteresis --export`` writes.

The file (schema ``rvsim-joint-model``, :data:`SCHEMA_VERSION`) holds what a robot simulator or
controller needs to model the reducer as a compliant joint with free play and a position
error: the torque-angle loop of the torque-reversal test (both branches), the torsional
rigidity and the local stiffness, backlash, lost motion, hysteresis loss, and the harmonics of
the transmission error over one output revolution at rated torque.  Units are SI and are part
of every field name (``_rad``, ``_nm``, ``_nm_per_rad``).  docs/joint_model.md shows how to
use it; :data:`JOINT_MODEL_SCHEMA` is the JSON Schema (draft 2020-12) of the file.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from ._files import atomic_write_text
from .errors import InputFileError

__all__ = ["SCHEMA_NAME", "SCHEMA_VERSION", "JOINT_MODEL_SCHEMA", "joint_model",
           "write_joint_model", "load_joint_model", "local_stiffness"]

SCHEMA_NAME = "rvsim-joint-model"
SCHEMA_VERSION = 1

_NUMBERS = {"type": "array", "items": {"type": "number"}, "minItems": 2}
_CURVE = {"type": "object", "required": ["torque_nm", "angle_rad"],
          "properties": {"torque_nm": _NUMBERS, "angle_rad": _NUMBERS}}
_NUMBER = {"type": "number"}

JOINT_MODEL_SCHEMA = {
    "$schema": "https://json-schema.org/draft/2020-12/schema",
    "title": "rvsim joint model",
    "type": "object",
    "required": ["schema", "schema_version", "generator", "reducer", "conventions",
                 "torque_angle", "stiffness", "backlash_rad", "lost_motion_rad",
                 "lost_motion_fraction_of_rated", "hysteresis_loss_rad", "transmission_error"],
    "properties": {
        "schema": {"const": SCHEMA_NAME},
        "schema_version": {"const": SCHEMA_VERSION},
        "generator": {"type": "string"},
        "reducer": {"type": "object", "required": ["name", "ratio", "rated_torque_nm"],
                    "properties": {"name": {"type": "string"}, "ratio": _NUMBER,
                                   "rated_torque_nm": _NUMBER}},
        "conventions": {"type": "object"},
        "torque_angle": {"type": "object", "required": ["loading", "unloading"],
                         "properties": {"loading": _CURVE, "unloading": _CURVE}},
        "stiffness": {
            "type": "object",
            "required": ["torsional_rigidity_nm_per_rad", "rigidity_interval_fraction_of_rated",
                         "local"],
            "properties": {
                "torsional_rigidity_nm_per_rad": _NUMBER,
                "rigidity_interval_fraction_of_rated": {"type": "array",
                                                        "items": _NUMBER, "minItems": 2,
                                                        "maxItems": 2},
                "local": {"type": "object", "required": ["torque_nm", "stiffness_nm_per_rad"],
                          "properties": {"torque_nm": _NUMBERS,
                                         "stiffness_nm_per_rad": _NUMBERS,
                                         "method": {"type": "string"}}}}},
        "backlash_rad": _NUMBER,
        "lost_motion_rad": _NUMBER,
        "lost_motion_fraction_of_rated": _NUMBER,
        "hysteresis_loss_rad": _NUMBER,
        "main_bearings": {
            "type": "object",
            "required": ["radial_stiffness_n_per_m", "axial_stiffness_n_per_m",
                         "tilting_stiffness_nm_per_rad"],
            "properties": {"radial_stiffness_n_per_m": _NUMBER,
                           "axial_stiffness_n_per_m": _NUMBER,
                           "tilting_stiffness_nm_per_rad": _NUMBER,
                           "source": {"type": "string"}}},
        "transmission_error": {
            "type": "object",
            "required": ["torque_nm", "mean_rad", "peak_to_peak_rad", "harmonics"],
            "properties": {
                "torque_nm": _NUMBER, "mean_rad": _NUMBER, "peak_to_peak_rad": _NUMBER,
                "harmonics": {"type": "array", "items": {
                    "type": "object", "required": ["order", "amplitude_rad", "phase_rad"],
                    "properties": {"order": _NUMBER, "amplitude_rad": _NUMBER,
                                   "phase_rad": _NUMBER}}}}},
    },
}

_CONVENTIONS = {
    "angle_rad": "output rotation with the input shaft locked, positive in the direction of "
                 "positive torque, zero at the assembled (centred) state",
    "torque_nm": "torque applied to the output",
    "loading": "the torque-reversal branch with torque increasing (-rated -> +rated)",
    "unloading": "the branch with torque decreasing (+rated -> -rated)",
    "transmission_error": "te(theta_out) = mean_rad + sum(amplitude_rad * cos(order * "
                          "theta_out + phase_rad)); TE = theta_in / ratio - theta_out; order "
                          "= per output revolution; theta_out = theta_in / ratio (nominal)",
    "source": "rvsim quasi-static engine; definitions GB/T 35089-2018 (docs/catalogue_tests.md)",
}


def local_stiffness(torque: np.ndarray, angle: np.ndarray, branch: np.ndarray,
                    stiffness: np.ndarray | None = None):
    """dT/dtheta along the loading parts of the loop [N*m/rad]: the increasing branch above
    zero torque and the decreasing branch below it.  ``stiffness`` (one value per sample,
    e.g. the engine's local stiffness) is used where given, else centred differences of the
    curve.  Returns (torque, stiffness) sorted by torque."""
    from .analysis.catalogue import loop_branches

    (t_up, a_up), (t_down, a_down) = loop_branches(torque, angle, branch)
    if stiffness is not None:
        (_, a_up), (_, a_down) = loop_branches(torque, stiffness, branch)
    parts_t, parts_k = [], []
    for t, a, sign in ((t_up, a_up, 1.0), (t_down, a_down, -1.0)):
        keep = sign * t > 0
        if keep.sum() >= 2:
            parts_t.append(t[keep])
            parts_k.append(a[keep] if stiffness is not None else np.gradient(t[keep], a[keep]))
    if not parts_t:
        return np.zeros(0), np.zeros(0)
    t, k = np.concatenate(parts_t), np.concatenate(parts_k)
    order = np.argsort(t)
    return t[order], k[order]


def _floats(values) -> list[float]:
    return [float(v) for v in np.asarray(values, dtype=float)]


def joint_model(hysteresis, ltca, reducer, *, harmonics: int = 24) -> dict:
    """The joint model of ``reducer`` from a torque-reversal result and an LTCA result (at
    rated torque): a JSON-ready dict following :data:`JOINT_MODEL_SCHEMA`.

    ``harmonics``: how many TE orders to keep, the largest amplitudes above 1e-9 of the
    largest (round-off); order 0, the mean, is stored separately.
    """
    from . import __version__
    from .analysis import catalogue as cat

    t, a, b, stiffness = cat.loop_arrays(hysteresis)
    rated = hysteresis.rated_torque
    (t_up, a_up), (t_down, a_down) = cat.loop_branches(t, a, b)
    k_torque, k_local = local_stiffness(t, a, b, stiffness)
    orders, amplitude, phase = cat.order_spectrum(ltca.input_angle / ltca.ratio, ltca.te,
                                                  with_phase=True)
    chosen = np.argsort(amplitude[1:])[::-1][:harmonics] + 1
    floor = 1e-9 * float(amplitude[1:].max(initial=0.0))      # round-off lines left out
    chosen = np.sort(chosen[amplitude[chosen] > floor])
    model = {
        "schema": SCHEMA_NAME,
        "schema_version": SCHEMA_VERSION,
        "generator": f"rvsim {__version__}",
        "reducer": {"name": reducer.name, "ratio": float(reducer.ratio),
                    "rated_torque_nm": float(rated)},
        "conventions": _CONVENTIONS,
        "torque_angle": {"loading": {"torque_nm": _floats(t_up), "angle_rad": _floats(a_up)},
                         "unloading": {"torque_nm": _floats(t_down),
                                       "angle_rad": _floats(a_down)}},
        "stiffness": {"torsional_rigidity_nm_per_rad": cat.torsional_rigidity(t, a, rated,
                                                                              branch=b),
                      "rigidity_interval_fraction_of_rated": [0.5, 1.0],
                      "local": {"torque_nm": _floats(k_torque),
                                "stiffness_nm_per_rad": _floats(k_local),
                                "method": "finite differences of the curve" if stiffness is None
                                else "engine (dT/dtheta at each equilibrium)"}},
        "backlash_rad": cat.backlash(t, a, b),
        "lost_motion_rad": cat.lost_motion(t, a, b, rated),
        "lost_motion_fraction_of_rated": cat.LOST_MOTION_FRACTION,
        "hysteresis_loss_rad": cat.hysteresis_loss(t, a, b),
        "transmission_error": {
            "torque_nm": float(ltca.torque), "mean_rad": float(np.mean(ltca.te)),
            "peak_to_peak_rad": cat.transmission_error_pp(ltca.te),
            "harmonics": [{"order": float(orders[i]), "amplitude_rad": float(amplitude[i]),
                           "phase_rad": float(phase[i])} for i in chosen]},
    }
    if not reducer.layout.single_stage:
        # the carrier's main bearings carry the arm's moment: a robot model needs their
        # tilting stiffness beside the torsional curve (not in the planar engines)
        from .bearings import main_bearing_stiffness

        main = main_bearing_stiffness(reducer)
        model["main_bearings"] = {
            "radial_stiffness_n_per_m": float(main.radial),
            "axial_stiffness_n_per_m": float(main.axial),
            "tilting_stiffness_nm_per_rad": float(main.tilting),
            "source": "rvsim.bearings.main_bearing_stiffness: Hertz point contact of the "
                      "preloaded angular-contact ball pair (bearings.main_*), estimated sizes "
                      "(docs/parameters.md)"}
    return model


def write_joint_model(path: str | Path, model: dict) -> Path:
    """Write ``model`` as indented JSON, atomically."""
    return atomic_write_text(path, json.dumps(model, indent=1, allow_nan=False) + "\n")


def _require(data: dict, keys, where: str, path) -> None:
    missing = [k for k in keys if k not in data]
    if missing:
        raise InputFileError(f"{path}: not a joint model ({where} lacks {', '.join(missing)})")


def load_joint_model(path: str | Path) -> dict:
    """Read a joint model file, checking its schema name, version and required fields."""
    path = Path(path)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise InputFileError(f"{path}: file not found") from None
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise InputFileError(f"{path}: not valid JSON ({exc})") from None
    if not isinstance(data, dict) or data.get("schema") != SCHEMA_NAME:
        raise InputFileError(f"{path}: not a joint model (schema is not '{SCHEMA_NAME}')")
    if data.get("schema_version") != SCHEMA_VERSION:
        raise InputFileError(f"{path}: joint model schema version "
                             f"{data.get('schema_version')!r}, this rvsim reads "
                             f"{SCHEMA_VERSION}")
    _require(data, JOINT_MODEL_SCHEMA["required"], "the file", path)
    for name in ("loading", "unloading"):
        _require(data["torque_angle"], [name], "torque_angle", path)
        curve = data["torque_angle"][name]
        _require(curve, ["torque_nm", "angle_rad"], f"torque_angle.{name}", path)
        if len(curve["torque_nm"]) != len(curve["angle_rad"]) or len(curve["torque_nm"]) < 2:
            raise InputFileError(f"{path}: torque_angle.{name}: torque_nm and angle_rad need "
                                 "the same length, at least 2")
    return data
