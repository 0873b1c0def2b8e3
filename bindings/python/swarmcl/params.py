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

__all__ = ["model_parameters", "parameter_doc", "scalar_fields", "scalar_defaults", "c_ordered_fields",
           "copy_scalars_to_c"]

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


def scalar_rows(model: str, skip: Iterable[str] = (), prefix: str = "") -> List[Dict[str, Any]]:
    """The rows of ``model`` that are plain scalars of its C descriptor (not
    nested in a struct, not in ``skip``).  With ``prefix`` ("weights."), the
    scalars of that nested struct instead (``skip`` then names fields of
    it)."""
    skip = set(skip)
    return [r for r in model_parameters(model)
            if r["c_field"].startswith(prefix) and "." not in r["c_field"][len(prefix):]
            and r["c_field"][len(prefix):] not in skip and r["type"] in _PY_TYPES]


def _name(row: Dict[str, Any], prefix: str) -> str:
    return row["c_field"][len(prefix):]


def scalar_fields(model: str, skip: Iterable[str] = (), prefix: str = "") -> list:
    """``dataclasses.make_dataclass`` fields for the scalar rows: the C field's
    name (after ``prefix``), its Python type, the table's default."""
    return [(_name(r, prefix), _PY_TYPES[r["type"]], dataclasses.field(default=_default(r)))
            for r in scalar_rows(model, skip, prefix)]


def scalar_defaults(model: str, skip: Iterable[str] = (), prefix: str = "") -> Dict[str, Any]:
    """The scalar rows' defaults by field name (after ``prefix``): a nested
    struct's defaults, e.g. the energy model's "danger_weights."."""
    return {_name(r, prefix): _default(r) for r in scalar_rows(model, skip, prefix)}


def c_ordered_fields(ctype: str, model: str, hand: Dict[str, tuple]) -> list:
    """``make_dataclass`` fields in the order of the C descriptor ``ctype``'s
    fields: a field named in ``hand`` (the C field's name -> a hand-written
    ``(name, type, dataclasses.field)``, e.g. "has_fixed_centre" -> centre)
    takes its place, a scalar row of ``model``'s table comes from the table,
    and any other C field (pointers' counts, fields a hand field covers) is
    left out.  Keeps a class's positional order when its scalar fields move
    to the table."""
    scalars = {f[0]: f for f in scalar_fields(model, hand)}
    out = []
    for name, _ in ffi.typeof(ctype).fields:
        if name in hand:
            out.append(hand[name])
        elif name in scalars:
            out.append(scalars.pop(name))
    if scalars:
        raise RuntimeError(f"{model} table rows that are not {ctype} fields: {sorted(scalars)}")
    return out


def parameter_doc(model: str, skip: Iterable[str] = (), prefix: str = "") -> str:
    """One line per scalar parameter: name, unit, doc, valid range, paper."""
    return "\n".join("    " + _line(r) for r in scalar_rows(model, skip, prefix))


def copy_scalars_to_c(obj: Any, desc, model: str, skip: Iterable[str] = (), prefix: str = "") -> None:
    """Copies ``obj``'s scalar parameters into the C descriptor ``desc`` (with
    ``prefix``, ``desc`` is that nested struct: ``p.weights`` for
    "weights."); a value of the wrong kind is a TypeError naming the
    parameter (the library checks the ranges)."""
    for r in scalar_rows(model, skip, prefix):
        name = _name(r, prefix)
        v = getattr(obj, name)
        try:
            setattr(desc, name, int(bool(v)) if r["type"] == "bool" else _PY_TYPES[r["type"]](v))
        except (TypeError, ValueError, OverflowError):
            raise TypeError(f"{type(obj).__name__}.{name} must be a {r['type']} in {r['range']}, got {v!r}") from None
