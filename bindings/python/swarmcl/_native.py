"""Loading libswarmcl through cffi in ABI mode.

The declarations come from the installed C header, ``swarmcl/swarmcl.h``: it is
read at import time, run through a tiny preprocessor (conditionals, object-like
macros, comments) and handed to ``FFI.cdef``.  The header stays the one source
of truth; nothing is copied by hand.

Where things are found (first hit wins):

library
  1. ``$SWARMCL_LIBRARY`` (a path to ``libswarmcl.so.0.2`` / ``.dylib`` / ``.dll``)
  2. inside the package: ``swarmcl/lib/`` (where the wheel installs it)
  3. development fallback, only when the package is imported from a source
     checkout (``bindings/python/swarmcl``): ``$SWARMCL_BUILD_DIR`` or
     ``<checkout>/build`` (what ``scripts/build.sh`` produces)

header
  1. ``$SWARMCL_HEADER`` (a path to ``swarmcl.h``)
  2. inside the package: ``swarmcl/include/swarmcl/swarmcl.h``
  3. source checkout: ``<checkout>/capi/include/swarmcl/swarmcl.h``
"""

from __future__ import annotations

import os
import re
import sys
from importlib import resources
from pathlib import Path

from cffi import FFI

__all__ = ["ffi", "lib", "constants", "header_path", "library_path", "enum_members"]

_PKG = __name__.rpartition(".")[0] or "swarmcl"


def _package_dir() -> Path | None:
    """The package's folder on disk (importlib.resources; None in a zip)."""
    try:
        return Path(os.fspath(resources.files(_PKG)))
    except (ModuleNotFoundError, TypeError):  # pragma: no cover - namespace or zip import
        here = Path(__file__).parent
        return here if here.is_dir() else None


def _checkout_root() -> Path | None:
    """The repository root when imported from bindings/python/swarmcl."""
    pkg = _package_dir()
    if pkg is None:
        return None
    root = pkg.parent.parent.parent
    if (root / "capi" / "include" / "swarmcl" / "swarmcl.h").is_file() and pkg.parent.name == "python":
        return root
    return None


def _find_header() -> Path:
    tried = []
    env = os.environ.get("SWARMCL_HEADER")
    if env:
        p = Path(env)
        if p.is_file():
            return p
        tried.append(f"$SWARMCL_HEADER={env}")
    pkg = _package_dir()
    if pkg is not None:
        p = pkg / "include" / "swarmcl" / "swarmcl.h"
        if p.is_file():
            return p
        tried.append(str(p))
    root = _checkout_root()
    if root is not None:
        p = root / "capi" / "include" / "swarmcl" / "swarmcl.h"
        if p.is_file():
            return p
    raise ImportError("swarmcl: cannot find the C header swarmcl/swarmcl.h (tried "
                      + ", ".join(tried) + "); set SWARMCL_HEADER or reinstall the package")


def _library_names() -> list[str]:
    if sys.platform == "win32":
        return ["swarmcl.dll", "libswarmcl.dll"]
    if sys.platform == "darwin":
        return ["libswarmcl.0.2.dylib", "libswarmcl.dylib"]
    return ["libswarmcl.so.0.2", "libswarmcl.so"]


def _find_library() -> Path:
    tried = []
    env = os.environ.get("SWARMCL_LIBRARY")
    if env:
        p = Path(env)
        if p.is_file():
            return p.resolve()
        raise ImportError(f"swarmcl: SWARMCL_LIBRARY={env} is not a file")
    folders = []
    pkg = _package_dir()
    if pkg is not None:
        folders.append(pkg / "lib")
    root = _checkout_root()
    if root is not None:
        build = os.environ.get("SWARMCL_BUILD_DIR")
        folders.append(Path(build) if build else root / "build")
    for folder in folders:
        for name in _library_names():
            p = folder / name
            if p.is_file():
                return p.resolve()
            tried.append(str(p))
    raise ImportError("swarmcl: cannot find the shared library (tried " + ", ".join(tried)
                      + "); set SWARMCL_LIBRARY to the path of libswarmcl")


# ---- a tiny C preprocessor, enough for a plain C99 header ----------------------

_COMMENT = re.compile(r"/\*.*?\*/|//[^\n]*", re.S)
_DIRECTIVE = re.compile(r"^\s*#\s*(\w+)\s*(.*?)\s*$")
_DEFINE = re.compile(r"^([A-Za-z_]\w*)(\(.*?\))?\s*(.*)$")
_INT = re.compile(r"^\(?\s*([-+]?(?:0[xX][0-9a-fA-F]+|\d+))[uUlL]*\s*\)?$")


def _eval_condition(expr: str, macros: dict) -> bool:
    expr = re.sub(r"defined\s*\(\s*(\w+)\s*\)|defined\s+(\w+)",
                  lambda m: " 1 " if (m.group(1) or m.group(2)) in macros else " 0 ", expr)
    expr = expr.replace("&&", " and ").replace("||", " or ")
    expr = re.sub(r"!(?!=)", " not ", expr)

    def ident(m):
        name = m.group(0)
        if name in ("and", "or", "not"):
            return name
        v = macros.get(name)
        return str(v) if isinstance(v, int) else "0"

    expr = re.sub(r"[A-Za-z_]\w*", ident, expr)
    expr = re.sub(r"(0[xX][0-9a-fA-F]+|\d+)[uUlL]+", r"\1", expr)
    return bool(eval(expr, {"__builtins__": {}}, {}))  # noqa: S307 - digits and operators only


def preprocess(text: str) -> tuple[str, dict[str, int]]:
    """Returns (declarations for cffi, integer object-like macros).

    Nothing is predefined, so ``__cplusplus``, ``_WIN32`` and ``__GNUC__`` blocks
    fall through to their plain-C branches.  Object-like macros are expanded
    in the declarations (an empty one such as ``SWCL_API`` disappears)."""
    text = text.replace("\\\n", " ")
    text = _COMMENT.sub(lambda m: " " if m.group(0).startswith("/*") else "", text)
    macros: dict[str, object] = {}
    stack: list[list[bool]] = []  # [active now, some branch taken, parent active]
    out: list[str] = []
    for line in text.splitlines():
        m = _DIRECTIVE.match(line)
        active = all(frame[0] for frame in stack)
        if m:
            kind, rest = m.group(1), m.group(2)
            if kind in ("if", "ifdef", "ifndef"):
                if kind == "ifdef":
                    cond = rest in macros
                elif kind == "ifndef":
                    cond = rest not in macros
                else:
                    cond = active and _eval_condition(rest, macros)
                stack.append([cond, cond])
            elif kind == "elif":
                frame = stack[-1]
                cond = not frame[1] and _eval_condition(rest, macros)
                frame[0] = cond
                frame[1] = frame[1] or cond
            elif kind == "else":
                frame = stack[-1]
                frame[0] = not frame[1]
                frame[1] = True
            elif kind == "endif":
                stack.pop()
            elif kind == "define" and active:
                d = _DEFINE.match(rest)
                if d and not d.group(2):
                    value = d.group(3).strip()
                    im = _INT.match(value)
                    macros[d.group(1)] = int(im.group(1), 0) if im else value
            elif kind == "undef" and active:
                macros.pop(rest, None)
            continue  # include, pragma, error: nothing for cffi
        if active:
            out.append(line)
    body = "\n".join(out)
    simple = {k: v for k, v in macros.items() if isinstance(v, int) or re.fullmatch(r"\w*", str(v))}
    if simple:
        pattern = re.compile(r"\b(" + "|".join(map(re.escape, simple)) + r")\b")
        body = pattern.sub(lambda m: str(simple[m.group(1)]), body)
    constants = {k: v for k, v in macros.items() if isinstance(v, int)}
    return body, constants


header_path = _find_header()
library_path = _find_library()

ffi = FFI()
_cdef, constants = preprocess(header_path.read_text(encoding="utf-8"))
ffi.cdef(_cdef)
try:
    lib = ffi.dlopen(str(library_path))
except OSError as exc:  # pragma: no cover - depends on the machine
    raise ImportError(f"swarmcl: cannot load {library_path}: {exc} "
                      "(the OpenCL ICD loader is needed: apt-get install ocl-icd-libopencl1)") from exc

_loaded_major = int(lib.swcl_version()) // 10000
if _loaded_major != constants.get("SWCL_VERSION_MAJOR", _loaded_major):
    raise ImportError(f"swarmcl: {library_path} is version {ffi.string(lib.swcl_version_string()).decode()}, "
                      f"the header {header_path} is {constants['SWCL_VERSION_MAJOR']}.x")


def enum_members(ctype: str) -> dict:
    """The enumerators of a C enum of the header, name -> value, without the
    ``*_MAX_ENUM`` entry every enum ends with (it only widens the enum's range
    to int32, docs/c-api.md; it is never a valid value)."""
    return {k: v for k, v in ffi.typeof(ctype).relements.items() if not k.endswith("_MAX_ENUM")}
