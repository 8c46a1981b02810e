"""Timings of integral (co)homology on large complexes.

Run: ``OPENBLAS_NUM_THREADS=1 python benchmarks/bench_homology.py``.  Builds

* a closed surface with >= 100k triangles (Freudenthal triangulation of a flat 2-torus grid,
  and the same grid with a cross-cap glued in: a non-orientable surface with Z/2 torsion),
* a closed 3-manifold with >= 50k tetrahedra (Freudenthal triangulation of the 3-torus),

and prints the time for ``homology`` (ranks, torsion and generator cycles) and ``cohomology``.
"""

from __future__ import annotations

import itertools
import time

import numpy as np


def freudenthal_torus(N: int, d: int) -> np.ndarray:
    """Top simplices of the Freudenthal triangulation of the d-torus on an N^d grid (N >= 3)."""
    grid = np.stack(np.meshgrid(*[np.arange(N)] * d, indexing="ij"), -1).reshape(-1, d)
    weights = N ** np.arange(d)[::-1]
    out = []
    for perm in itertools.permutations(range(d)):
        pts = [grid]
        cur = grid.copy()
        for axis in perm:
            cur = cur.copy()
            cur[:, axis] += 1
            pts.append(cur)
        out.append(np.stack([(p % N) @ weights for p in pts], axis=1))
    return np.concatenate(out)


def torus_with_crosscap(N: int) -> np.ndarray:
    """The non-orientable surface T² # RP², with H_1 = Z² ⊕ Z/2.

    The N×N grid torus with one square replaced by an annulus glued to a 6-vertex RP² minus a
    triangle.
    """
    T = freudenthal_torus(N, 2)
    a, b, c, d = 0, 1, N + 1, N  # the square of grid cell (0, 0)
    quad = {tuple(sorted(t)) for t in ([a, b, c], [a, c, d], [a, b, d])}
    T = T[np.array([tuple(sorted(t)) not in quad for t in T.tolist()])]
    M = N * N
    rp2 = np.array([(0, 1, 2), (0, 2, 3), (0, 3, 4), (0, 4, 5), (0, 1, 5),
                    (1, 2, 4), (2, 3, 5), (1, 3, 4), (1, 3, 5), (2, 4, 5)])[1:] + M  # hole M, M+1, M+2
    x, y, z = M, M + 1, M + 2
    annulus = np.array([(a, b, x), (b, x, y), (b, c, y), (c, y, z), (c, d, z), (d, z, x), (d, a, x)])
    return np.concatenate([T, rp2, annulus])


def run():
    import dhlb
    from dhlb.topology.homology import cohomology, homology
    from dhlb.topology.intlinalg import integer_kernel_basis, solve_integer

    cases = [
        ("2-torus, Freudenthal 224x224", freudenthal_torus(224, 2)),
        ("T^2 # RP^2 (torus grid 224x224 + cross-cap)", torus_with_crosscap(224)),
        ("3-torus, Freudenthal 21^3", freudenthal_torus(21, 3)),
    ]
    for name, F in cases:
        t0 = time.perf_counter()
        X = dhlb.SimplicialComplex(F)
        t1, c1 = time.perf_counter(), time.process_time()
        H = homology(X)
        t2, c2 = time.perf_counter(), time.process_time()
        C = cohomology(X, "Z")
        t3, c3 = time.perf_counter(), time.process_time()
        print(f"{name}: counts {X.counts}")
        print(f"    build complex {t1 - t0:6.2f} s | homology {t2 - t1:6.2f} s wall ({c2 - c1:5.2f} s cpu): "
              f"{[str(h) for h in H]} | cohomology(Z) {t3 - t2:6.2f} s wall ({c3 - c2:5.2f} s cpu): "
              f"{[str(h) for h in C]}")
        if X.dim == 2:
            for k in (1, 2):
                t0 = time.perf_counter()
                K = integer_kernel_basis(X.boundary(k))
                print(f"    Z-basis of ker ∂_{k}: {K.shape[1]} cycles, {K.nnz} nonzeros, "
                      f"{time.perf_counter() - t0:6.2f} s")
            rng = np.random.default_rng(0)
            for k in (0, 1):
                d = X.coboundary(k)
                beta = d @ rng.integers(-3, 4, X.n_simplices(k))
                t0 = time.perf_counter()
                alpha = solve_integer(d, beta)
                assert alpha is not None and np.array_equal(d @ alpha, beta)
                print(f"    solve_integer(d_{k}, β) over Z: {time.perf_counter() - t0:6.2f} s")


if __name__ == "__main__":
    run()
