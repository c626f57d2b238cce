"""Strict JSON: NaN and infinities become null, numpy scalars plain numbers."""

from __future__ import annotations

import json
import math
from typing import Any

__all__ = ["to_json_safe", "dumps"]


def to_json_safe(value: Any) -> Any:
    """``value`` with non-finite floats replaced by None (JSON null), recursively."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: to_json_safe(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [to_json_safe(v) for v in value]
    if hasattr(value, "tolist") and callable(value.tolist):  # numpy scalar or array
        return to_json_safe(value.tolist())
    return value


def dumps(value: Any, **kwargs) -> str:
    """JSON text any strict reader accepts (``allow_nan=False`` after cleaning)."""
    return json.dumps(to_json_safe(value), allow_nan=False, **kwargs)
