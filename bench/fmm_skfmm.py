#!/usr/bin/env python3
"""scikit-fmm's distance on the grid fmm_bench uses (called by fmm_bench with
/usr/bin/python3, where Debian's python3-scikit-fmm lives): a sphere of
radius R around C in a cube of N cells of edge H, cell centres; prints one
JSON line with the median seconds and the max error against the exact
distance, for first and second order."""
import json
import sys
import time

import numpy as np
import skfmm


def main():
    n, h, r = int(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3])
    c = [float(v) for v in sys.argv[4:7]]
    repeats = int(sys.argv[7]) if len(sys.argv) > 7 else 3
    x = (np.arange(n) + 0.5) * h
    X, Y, Z = np.meshgrid(x, x, x, indexing="ij")
    exact = np.sqrt((X - c[0]) ** 2 + (Y - c[1]) ** 2 + (Z - c[2]) ** 2) - r
    out = {}
    for order in (1, 2):
        times = []
        for _ in range(repeats):
            t0 = time.perf_counter()
            d = skfmm.distance(exact.copy(), dx=h, order=order)
            times.append(time.perf_counter() - t0)
        outside = exact > 0
        out[f"order{order}"] = {"seconds": float(np.median(times)),
                                "max_error": float(np.max(np.abs(d[outside] - exact[outside])))}
    print(json.dumps(out))


if __name__ == "__main__":
    main()
