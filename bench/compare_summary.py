"""The figures of a bench/compare_builds.sh run, old against new, as a
Markdown table (docs/benchmarks.md) and JSON:
    python3 bench/compare_summary.py OUT_DIR [--json FILE]
Every round found in OUT_DIR counts; benchmarks that were not run are left
out."""
import json
import sys
from pathlib import Path


def figures(d: Path, label: str, rnd: int) -> dict:
    def load(name):
        f = d / f"{label}-{name}_bench-r{rnd}.json"
        return json.loads(f.read_text()) if f.is_file() else None
    out = {}
    if (nb := load("noise")) is not None:
        fm = nb["field_model"]["median_ms"]
        out["field 1M full step, procedural (ms)"] = fm["procedural/full step (advance + grid rebuild + MDE)"]
        out["field 1M advance kernel, procedural (ms)"] = fm["procedural/advance kernel (noise + goal + Euler)"]
        out["field 1M full step, baked (ms)"] = fm["baked/full step (advance + grid rebuild + MDE)"]
        out["field 1M advance kernel, baked (ms)"] = fm["baked/advance kernel (noise + goal + Euler)"]
    if (fb := load("force")) is not None:
        for r in fb["rows"]:
            out[f"force {r['scenario']} {r['agents'] // 1000}k (steps/s)"] = r["steps_per_s"]
    if (p := load("path")) is not None:
        out["path 1M locusts (ms/step)"] = p["locusts_ms_per_step"]
        out["path 1M advance only (ms/step)"] = p["locusts_advance_only_ms_per_step"]
    if (eb := load("energy")) is not None:
        for r in eb["rows"]:
            out[f"energy {r['agents'] // 1000}k (ms/step)"] = r["energy_ms_per_step"]
    if (pb := load("policy")) is not None:
        for r in pb["rows"]:
            out[f"policy {r['agents'] // 1000}k observe (ms)"] = r["observe_ms"]
            out[f"policy {r['agents'] // 1000}k MLP (ms)"] = r["mlp_ms"]
    return out


def main() -> None:
    d = Path(sys.argv[1])
    rounds = sorted({int(f.stem.rsplit("-r", 1)[1]) for f in d.glob("old-*-r*.json")})
    runs = {(lab, r): figures(d, lab, r) for lab in ("old", "new") for r in rounds}
    head = " / ".join(str(r) for r in rounds)
    print(f"| figure | old (round {head}) | new (round {head}) | new / old (means) |")
    print("|---|---|---|---|")
    rows = []
    for k in runs[("old", rounds[0])]:
        o = [runs[("old", r)][k] for r in rounds]
        n = [runs[("new", r)][k] for r in rounds]
        ratio = (sum(n) / len(n)) / (sum(o) / len(o))
        rows.append({"figure": k, "old": o, "new": n, "new_over_old": ratio})
        print(f"| {k} | {' / '.join(f'{x:.4g}' for x in o)} | {' / '.join(f'{x:.4g}' for x in n)} | {ratio:.3f} |")
    if "--json" in sys.argv:
        machine = (d / "machine.txt").read_text().splitlines()
        Path(sys.argv[sys.argv.index("--json") + 1]).write_text(
            json.dumps({"cpu": machine[0], "log": machine[1:], "rows": rows}, indent=1) + "\n")


if __name__ == "__main__":
    main()
