"""Records (lists of dicts, as the reports serialise them) as dicts of 1-D numpy columns."""

from __future__ import annotations

import math
from typing import Any, Dict, List

import numpy as np


def _is_number(x: Any) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def _flatten(d: Dict[str, Any], prefix: str = "") -> Dict[str, Any]:
    out: Dict[str, Any] = {}
    for k, v in d.items():
        name = f"{prefix}{k}"
        if isinstance(v, dict):
            out.update(_flatten(v, name + "_"))
        elif isinstance(v, (list, tuple)) and len(v) == 3 and all(_is_number(x) for x in v):
            out.update({f"{name}_x": v[0], f"{name}_y": v[1], f"{name}_z": v[2]})
        elif isinstance(v, (list, tuple)) and len(v) == 2 and all(_is_number(x) for x in v):
            out.update({f"{name}_lo": v[0], f"{name}_hi": v[1]})
        else:
            out[name] = v
    return out


def _column(values: List[Any]) -> Any:
    if values and all(isinstance(v, bool) for v in values):
        return np.array(values, dtype=bool)
    if values and all(isinstance(v, int) and not isinstance(v, bool) for v in values):
        return np.array(values, dtype=np.int64)
    if values and all(v is None or _is_number(v) for v in values) and any(v is not None for v in values):
        return np.array([math.nan if v is None else float(v) for v in values], dtype=np.float64)
    if values and all(isinstance(v, str) for v in values):
        return np.array(values, dtype=str)
    return values


def columns(records: List[Dict[str, Any]]) -> Dict[str, Any]:
    """Flatten nested records (``a_b`` for nested keys, ``_x/_y/_z`` for 3-vectors, ``_lo/_hi``
    for pairs) and return one numpy column per key (ints, floats with NaN for missing values,
    bools, strings; anything else stays a list)."""
    flat = [_flatten(r) for r in records]
    keys: List[str] = []
    for f in flat:
        for k in f:
            if k not in keys:
                keys.append(k)
    return {k: _column([f.get(k) for f in flat]) for k in keys}
