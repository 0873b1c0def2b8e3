#!/usr/bin/env python3
"""The data's own floor: a recording's first half (by time) scored against its
second half, as a model's simulation would be (issue 26, items 3-4;
docs/evaluation.md, "Physical scale and robust standardisation").

Prints and writes (--json) per metric: E_phi with the paper's z-score (mean,
sigma) and with the robust one (median, 1.4826 MAD), the Wasserstein-1
distance in the metric's unit, and each half's sigma, median and MAD; and the
score E both ways.  Every figure comes from the data.

    python3 scripts/data_floor.py ../shared/data/anopheles-coluzzii-swarm.csv \\
        --columns id,datetime,x_cm,y_cm,z_cm --unit-scale 0.01 --json bench/results/eval/data_floor.json
"""
import argparse
import json
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "bindings", "python"))
import swarmcl  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("tracks")
    ap.add_argument("--columns", default="id,time,x,y,z", help="ID,T,X,Y,Z (default id,time,x,y,z)")
    ap.add_argument("--unit-scale", type=float, default=1.0, help="the tracks' length unit in metres")
    ap.add_argument("--json", help="write the figures here")
    a = ap.parse_args()
    names = a.columns.split(",")
    if len(names) != 5:
        ap.error("--columns: expected five names: id,time,x,y,z")
    cols = dict(zip(("id", "time", "x", "y", "z"), names))
    kw = dict(columns=cols, unit_scale=a.unit_scale)
    with swarmcl.Metrics.from_csv(a.tracks, window=(0.0, 0.5), **kw) as first, \
            swarmcl.Metrics.from_csv(a.tracks, window=(0.5, 1.0), **kw) as second:
        plain = swarmcl.distances(first, second)
        robust = swarmcl.distances(first, second, robust=True)
        w1 = swarmcl.wasserstein(first, second)
        out = {"tracks": os.path.basename(a.tracks), "score": swarmcl.score(plain),
               "score_robust": swarmcl.score(robust), "metrics": {}}
        print(f"{'metric':22s} {'E_phi':>7s} {'robust':>7s} {'W1':>10s} {'unit':8s} "
              f"{'sigma 1st/2nd':>19s} {'median 1st/2nd':>19s} {'MAD 1st/2nd':>19s}")
        for k, name in enumerate(swarmcl.METRICS):
            f, s = first.info(k), second.info(k)
            out["metrics"][name] = {"distance": float(plain[k]), "distance_robust": float(robust[k]),
                                    "wasserstein": w1[name], "unit": swarmcl.METRIC_UNITS[k],
                                    "first": f, "second": s}
            w = "-" if w1[name] is None else f"{w1[name]:.4g}"
            print(f"{name:22s} {plain[k]:7.3f} {robust[k]:7.3f} {w:>10s} {swarmcl.METRIC_UNITS[k]:8s} "
                  f"{f['sigma']:9.4g}/{s['sigma']:<9.4g} {f['median']:9.4g}/{s['median']:<9.4g} "
                  f"{f['mad']:9.4g}/{s['mad']:<9.4g}")
    print(f"halves against each other: E = {out['score']:.3f} (mean, sigma), {out['score_robust']:.3f} (median, MAD)")
    if a.json:
        os.makedirs(os.path.dirname(os.path.abspath(a.json)), exist_ok=True)
        with open(a.json, "w", encoding="utf-8") as fh:
            json.dump(out, fh, indent=1)
            fh.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
