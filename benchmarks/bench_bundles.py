"""Benchmark of the line-bundle layer on large periodic torus grids.

For a torus with ~1M triangles (an n×n periodic grid, two triangles per square) it times:
building a bundle with prescribed curvature (Weil construction), the curvature check of
:class:`HermitianLineBundle`, the integrality check, the degree and the index form of a
random section; then repeats at 4× the size and prints the time ratios (≈ 4 for linear
scaling).  Run:  ``python benchmarks/bench_bundles.py [n]``  (default n = 707).
"""

from __future__ import annotations

import sys
import time

import numpy as np

from dhlb import SimplicialComplex
from dhlb.bundles import HermitianLineBundle, check_integrality, line_bundle_with_curvature


def torus_grid(n: int) -> SimplicialComplex:
    """n×n periodic grid, 2 triangles per square: 2n² triangles."""
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    i, j = i.ravel(), j.ravel()

    def v(a, b):
        return (a % n) * n + (b % n)

    t1 = np.stack([v(i, j), v(i + 1, j), v(i + 1, j + 1)], axis=1)
    t2 = np.stack([v(i, j), v(i, j + 1), v(i + 1, j + 1)], axis=1)
    X = SimplicialComplex(np.concatenate([t1, t2]))
    X.faces(2)  # the face tables are part of building the complex (cached)
    return X


def timed(label, fn, out):
    t = time.perf_counter()
    res = fn()
    dt = time.perf_counter() - t
    out[label] = dt
    print(f"  {label:<28s} {dt:8.3f} s")
    return res


def run(n: int, degree: int = 7) -> dict:
    times: dict = {}
    print(f"torus grid {n}x{n}: {2 * n * n:,} triangles")
    X = timed("build complex", lambda: torus_grid(n), times)
    o = timed("orientation", X.orientation, times)
    Om = o * (2 * np.pi * degree / X.n_simplices(2))
    L = timed("line_bundle_with_curvature", lambda: line_bundle_with_curvature(X, Om), times)
    timed("curvature (bundle check)", lambda: HermitianLineBundle(X, L.connection, Om), times)
    timed("integrality check", lambda: check_integrality(X, Om), times)
    deg = timed("degree", L.degree, times)
    rng = np.random.default_rng(0)
    z = rng.standard_normal(X.n_vertices) + 1j * rng.standard_normal(X.n_vertices)
    ind = timed("index form", lambda: L.index_form(z), times)
    assert deg == degree and int(o @ ind) == degree, "Poincaré–Hopf failed"
    return times


def main(argv) -> None:
    n = int(argv[1]) if len(argv) > 1 else 707
    small = run(n)
    large = run(2 * n)
    print("time ratio for 4x the size (linear scaling: about 4):")
    for k in small:
        print(f"  {k:<28s} {large[k] / max(small[k], 1e-9):6.2f}")
    for k in ("curvature (bundle check)", "integrality check", "degree", "index form"):
        status = "ok" if small[k] < 10 else "SLOW"
        print(f"  1M-triangle {k}: {small[k]:.2f} s  [{status}: target < 10 s]")


if __name__ == "__main__":
    main(sys.argv)
