"""How the scripts under scripts/ write paths into results and docs: never a
machine's absolute path (tests/python/test_machine_paths.py fails on one in
any tracked file).  A path inside the repository is written relative to it
(``models/policy_roaming.safetensors``), one beside it relative to it too
(``../shared/papers``), one in the temporary folder as ``$TMPDIR/...`` (it is
gone after the run; the name says what it was)."""

from __future__ import annotations

import json
import os
import shlex
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def shown_path(path) -> str:
    """`path` as a result records it (see the module's docstring)."""
    p = Path(os.path.abspath(path))
    tmp = Path(os.path.abspath(tempfile.gettempdir()))
    for base in (ROOT, ROOT.resolve()):
        if p == base or base in p.parents:
            return p.relative_to(base).as_posix() or "."
    if p == tmp or tmp in p.parents:
        return "$TMPDIR/" + p.relative_to(tmp).as_posix()
    return os.path.relpath(p, ROOT)


def shown_value(value):
    """A result's value with every path in it shown by shown_path: Path
    objects, and strings that are absolute paths; lists, tuples and dicts
    element by element."""
    if isinstance(value, Path):
        return shown_path(value)
    if isinstance(value, str):
        return shown_path(value) if os.path.isabs(value) else value
    if isinstance(value, dict):
        return {k: shown_value(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [shown_value(v) for v in value]
    return value


def shown_command(argv) -> str:
    """A command line as a result records it: the program by its name,
    absolute paths among the arguments by shown_path."""
    argv = [str(a) for a in argv]
    if not argv:
        return ""
    return shlex.join([Path(argv[0]).name, *(shown_value(a) for a in argv[1:])])


def write_result(out: dict, path) -> None:
    """A benchmark's results as JSON at `path` (its folder made), every path
    in them shown by shown_value, and a line saying where."""
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with open(path, "w", encoding="utf-8") as f:
        json.dump(shown_value(out), f, indent=1)
    print(f"written to {shown_path(path)}")
