#!/usr/bin/env python3
"""Fails when a tracked text file names a folder of one machine: an absolute
path into the root's work, root, home or tmp folders in docs, scripts,
sources or results.  Paths in the repository are written relative to it, the shared
folder beside it as ../shared, a temporary file as $TMPDIR/... (scripts write
results through scripts/result_paths.py).  ctest runs it
(repo.no_machine_paths), and once with --self-test, which plants such paths
in a scratch repository and checks that they are found.

    python3 scripts/check_machine_paths.py [REPO]      # exit 1 and the lines found
"""

from __future__ import annotations

import re
import subprocess
import sys
import tempfile
from pathlib import Path

# An absolute path: the folder at the start of a word (not "../root/", not
# "build/tmp/", not "$TMPDIR/").
MACHINE_PATH = re.compile(r"(?<![\w.$~/-])/(?:work|root|home|tmp)/")


def tracked_files(repo: Path) -> list[str]:
    out = subprocess.run(["git", "-C", str(repo), "ls-files", "-z"], check=True, capture_output=True).stdout
    return [name for name in out.decode("utf-8", "surrogateescape").split("\0") if name]


def is_text(data: bytes) -> bool:
    """Git's rule: no NUL byte in the first 8000 bytes."""
    return b"\0" not in data[:8000]


def findings(repo: Path) -> list[str]:
    found = []
    for name in tracked_files(repo):
        path = repo / name
        if not path.is_file() or path.is_symlink():
            continue
        data = path.read_bytes()
        if not is_text(data):
            continue
        for number, line in enumerate(data.decode("utf-8", "replace").splitlines(), 1):
            for m in MACHINE_PATH.finditer(line):
                found.append(f"{name}:{number}: {line[max(0, m.start() - 30):m.end() + 40].strip()}")
    return found


def self_test() -> int:
    """The check finds planted paths and leaves relative ones alone."""
    with tempfile.TemporaryDirectory() as tmp:
        repo = Path(tmp)
        subprocess.run(["git", "init", "-q", str(repo)], check=True)
        r = "/"  # the planted paths are put together here, so this file holds none
        planted = {
            "docs/a.md": f"papers in {r}work/shared/papers\n",
            "scripts/b.py": f'PY = "{r}home/alice/venv/bin/python"\n',
            "results/c.json": f'{{"model": "{r}tmp/run/x.safetensors"}}\n',
            "d.txt": f"cd {r}root/swarmcl && make\n",
        }
        clean = {
            "e.md": "../shared/papers, build/tmp/x, $TMPDIR/rlrun2, ~/tmp/y, examples/root/z, a/home/b\n",
            "f.bin": f"\0{r}tmp/binary files are not text\n",
        }
        for name, text in {**planted, **clean}.items():
            (repo / name).parent.mkdir(parents=True, exist_ok=True)
            (repo / name).write_text(text)
        subprocess.run(["git", "-C", str(repo), "add", "-A"], check=True)
        got = {line.split(":", 1)[0] for line in findings(repo)}
        if got != set(planted):
            print(f"self-test failed: found {sorted(got)}, planted {sorted(planted)}", file=sys.stderr)
            return 1
    print("self-test: the planted paths are found, the relative ones are not")
    return 0


def main(argv: list[str]) -> int:
    if argv and argv[0] == "--self-test":
        return self_test()
    repo = Path(argv[0]) if argv else Path(__file__).resolve().parents[1]
    found = findings(repo)
    for line in found:
        print(line)
    if found:
        print(f"\n{len(found)} absolute path(s) of one machine in tracked files: write them relative to the "
              "repository (or ../shared; $TMPDIR/... for a temporary file; scripts/result_paths.py)", file=sys.stderr)
        return 1
    print(f"no machine path in {len(tracked_files(repo))} tracked files")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
