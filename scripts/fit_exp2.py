#!/usr/bin/env python3
"""The coefficients of kernels/lib/exp2.cl: 2^f = 1 + f P(f) on [-1/2, 1/2],
P of degree 4, fitted to the least largest relative error by Lawson's
iteratively reweighted least squares (plain Python, no packages).

    python3 scripts/fit_exp2.py [--degree 4]
prints the coefficients c1.. (of f, f^2, ...) and the largest relative error.
"""
import argparse


def solve(a, b):
    """Gauss-Jordan with partial pivoting: a x = b."""
    n = len(b)
    m = [row[:] + [v] for row, v in zip(a, b)]
    for i in range(n):
        p = max(range(i, n), key=lambda r: abs(m[r][i]))
        m[i], m[p] = m[p], m[i]
        for r in range(n):
            if r != i:
                f = m[r][i] / m[i][i]
                for c in range(i, n + 1):
                    m[r][c] -= f * m[i][c]
    return [m[i][n] / m[i][i] for i in range(n)]


def fit(terms, points=4001, iterations=60):
    xs = [-0.5 + i / (points - 1) for i in range(points)]
    w = [1.0] * points
    worst = 0.0
    for _ in range(iterations):
        a = [[0.0] * terms for _ in range(terms)]
        b = [0.0] * terms
        for x, wx in zip(xs, w):
            t = 2.0 ** x
            basis = [x ** (k + 1) / t for k in range(terms)]
            y = 1.0 - 1.0 / t  # (1 + sum c_k x^k) / 2^x - 1 = 0
            for i in range(terms):
                b[i] += wx * basis[i] * y
                for j in range(terms):
                    a[i][j] += wx * basis[i] * basis[j]
        c = solve(a, b)
        errs = [abs((1.0 + sum(c[k] * x ** (k + 1) for k in range(terms))) / 2.0 ** x - 1.0) for x in xs]
        worst = max(errs)
        w = [wx * (e / worst + 1e-3) for wx, e in zip(w, errs)]
        s = sum(w)
        w = [wx / s * points for wx in w]
    return c, worst


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--degree", type=int, default=4, help="degree of P (2^f = 1 + f P(f))")
    args = ap.parse_args()
    c, worst = fit(args.degree + 1)
    for k, v in enumerate(c, 1):
        print(f"c{k} = {v!r}")
    print(f"largest relative error on [-1/2, 1/2]: {worst:.3g}")


if __name__ == "__main__":
    main()
