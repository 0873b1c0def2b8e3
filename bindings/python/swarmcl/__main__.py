"""python -m swarmcl fit|sweep ...: the package's commands (what `swarmcl fit`
and `swarmcl sweep` run)."""
import sys


def _main(argv) -> int:
    if argv and argv[0] == "fit":
        from .fitting import main as fit_main
        return fit_main(argv[1:])
    if argv and argv[0] == "sweep":
        from .sweep import main as sweep_main
        return sweep_main(argv[1:])
    print("usage: python -m swarmcl fit SCENARIO.json --tracks FILE.csv --ranges RANGES.json [...]  (--help)\n"
          "       python -m swarmcl sweep SCENARIO.json --grid GRID.json [--tracks FILE.csv] [...]  (--help)",
          file=sys.stderr)
    return 2


if __name__ == "__main__":
    raise SystemExit(_main(sys.argv[1:]))
