"""The library's parameter tables (``swcl_model_parameters``, issue 24).

Each model declares its parameters once, in the C++ library: key, C field,
type, default, valid range, unit, doc and the paper's reference.  The Python
model classes take their scalar fields from these rows (names, defaults,
docs) instead of writing each one again; the structured fields (noise
objects, goals, meshes) stay hand-written.
"""

from __future__ import annotations

import dataclasses
import json
from functools import lru_cache
from typing import Any, Dict, Iterable, List, Optional

import numpy as np

from ._native import ffi, lib

__all__ = ["model_parameters", "parameter_doc", "scalar_fields", "copy_scalars_to_c"]

_PY_TYPES = {"float": float, "uint32": int, "uint64": int, "bool": bool}


@lru_cache(maxsize=None)
def _rows(model: Optional[str]) -> str:
    out = ffi.new("const char**")
    status = lib.swcl_model_parameters(model.encode() if model is not None else ffi.NULL, out)
    if status != 0:
        raise ValueError(ffi.string(lib.swcl_last_error()).decode("utf-8", "replace"))
    return ffi.string(out[0]).decode("utf-8")


def model_parameters(model: Optional[str] = None) -> Any:
    """The rows of ``model``'s table ("field", "noise", ...) as a list of
    dicts; with no model, a dict of every model's rows.  ValueError names the
    known models for an unknown one."""
    return json.loads(_rows(model))


def _f32(v: float) -> float:
    return float(str(np.float32(v)))


def _default(row: Dict[str, Any]):
    d = row["default"]
    if row["type"] == "float":
        return _f32(d)
    return _PY_TYPES[row["type"]](d)


def _line(row: Dict[str, Any]) -> str:
    unit = f" [{row['unit']}]" if row["unit"] else ""
    return f"{row['c_field']}{unit}: {row['doc']} (valid {row['range']}; {row['ref']})"


def scalar_rows(model: str, skip: Iterable[str] = ()) -> List[Dict[str, Any]]:
    """The rows of ``model`` that are plain scalars of its C descriptor (not
    nested in a struct, not in ``skip``)."""
    skip = set(skip)
    return [r for r in model_parameters(model)
            if "." not in r["c_field"] and r["c_field"] not in skip and r["type"] in _PY_TYPES]


def scalar_fields(model: str, skip: Iterable[str] = ()) -> list:
    """``dataclasses.make_dataclass`` fields for the scalar rows: the C field's
    name, its Python type, the table's default."""
    return [(r["c_field"], _PY_TYPES[r["type"]], dataclasses.field(default=_default(r)))
            for r in scalar_rows(model, skip)]


def parameter_doc(model: str, skip: Iterable[str] = ()) -> str:
    """One line per scalar parameter: name, unit, doc, valid range, paper."""
    return "\n".join("    " + _line(r) for r in scalar_rows(model, skip))


def copy_scalars_to_c(obj: Any, desc, model: str, skip: Iterable[str] = ()) -> None:
    """Copies ``obj``'s scalar parameters into the C descriptor ``desc``; a
    value of the wrong kind is a TypeError naming the parameter (the library
    checks the ranges)."""
    for r in scalar_rows(model, skip):
        name = r["c_field"]
        v = getattr(obj, name)
        try:
            setattr(desc, name, int(bool(v)) if r["type"] == "bool" else _PY_TYPES[r["type"]](v))
        except (TypeError, ValueError, OverflowError):
            raise TypeError(f"{type(obj).__name__}.{name} must be a {r['type']} in {r['range']}, got {v!r}") from None
