"""python -m swarmcl fit ...: the package's commands (what `swarmcl fit` runs)."""
import sys

from .fitting import main as fit_main


def _main(argv) -> int:
    if not argv or argv[0] != "fit":
        print("usage: python -m swarmcl fit SCENARIO.json --tracks FILE.csv --ranges RANGES.json [...]  (--help)",
              file=sys.stderr)
        return 2
    return fit_main(argv[1:])


if __name__ == "__main__":
    raise SystemExit(_main(sys.argv[1:]))
