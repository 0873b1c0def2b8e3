"""The figures of a bench/compare_builds.sh run, old against new, as a
Markdown table (docs/benchmarks.md) and JSON:
    python3 bench/compare_summary.py OUT_DIR [--json FILE]"""
import json
import sys
from pathlib import Path


def figures(d: Path, label: str, rnd: int) -> dict:
    def load(name):
        return json.loads((d / f"{label}-{name}_bench-r{rnd}.json").read_text())
    out = {}
    fm = load("noise")["field_model"]["median_ms"]
    out["field 1M full step, procedural (ms)"] = fm["procedural/full step (advance + grid rebuild + MDE)"]
    out["field 1M advance kernel, procedural (ms)"] = fm["procedural/advance kernel (noise + goal + Euler)"]
    out["field 1M full step, baked (ms)"] = fm["baked/full step (advance + grid rebuild + MDE)"]
    for r in load("force")["rows"]:
        out[f"force {r['scenario']} {r['agents'] // 1000}k (steps/s)"] = r["steps_per_s"]
    p = load("path")
    out["path 1M locusts (ms/step)"] = p["locusts_ms_per_step"]
    out["path 1M advance only (ms/step)"] = p["locusts_advance_only_ms_per_step"]
    for r in load("energy")["rows"]:
        out[f"energy {r['agents'] // 1000}k (ms/step)"] = r["energy_ms_per_step"]
    for r in load("policy")["rows"]:
        out[f"policy {r['agents'] // 1000}k observe (ms)"] = r["observe_ms"]
        out[f"policy {r['agents'] // 1000}k MLP (ms)"] = r["mlp_ms"]
    return out


def main() -> None:
    d = Path(sys.argv[1])
    runs = {(lab, r): figures(d, lab, r) for lab in ("old", "new") for r in (1, 2)}
    print("| figure | old (round 1 / 2) | new (round 1 / 2) | new / old (means) |")
    print("|---|---|---|---|")
    rows = []
    for k in runs[("old", 1)]:
        o = [runs[("old", r)][k] for r in (1, 2)]
        n = [runs[("new", r)][k] for r in (1, 2)]
        ratio = (sum(n) / 2) / (sum(o) / 2)
        rows.append({"figure": k, "old": o, "new": n, "new_over_old": ratio})
        print(f"| {k} | {o[0]:.4g} / {o[1]:.4g} | {n[0]:.4g} / {n[1]:.4g} | {ratio:.3f} |")
    if "--json" in sys.argv:
        machine = (d / "machine.txt").read_text().splitlines()
        Path(sys.argv[sys.argv.index("--json") + 1]).write_text(
            json.dumps({"cpu": machine[0], "log": machine[1:], "rows": rows}, indent=1) + "\n")


if __name__ == "__main__":
    main()
