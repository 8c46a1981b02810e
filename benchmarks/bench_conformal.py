"""Benchmark of dhlb.conformal.conformal_deformation on tetrahedralised balls (end to end).

Prints, per size: tets, vertices, the time of each phase, the total, and the total divided by the
time of one factorization (+ one solve) of the real cotangent Laplacian ``L + εM`` of the same mesh
(:func:`dhlb.fem.solve`), and the peak resident memory.  Targets (issue 20): 200k tets < 20 s,
1M tets < 120 s, < 8 GB.

    OPENBLAS_NUM_THREADS=1 python benchmarks/bench_conformal.py            # ~200k tets
    OPENBLAS_NUM_THREADS=1 python benchmarks/bench_conformal.py 200k 1M
"""

from __future__ import annotations

import resource
import sys
import time

import numpy as np

from dhlb.conformal import conformal_deformation, point_charge_factor
from dhlb.fem import solve
from dhlb.geometry import EuclideanComplex
from dhlb.mesh import ball_tet_mesh

SIZES = {"5k": 6, "40k": 12, "200k": 20, "1M": 34}   # ball_tet_mesh(n): 6 n³ + 36 n² ceil(n/2) tets


def factor_time(mesh) -> float:
    geo = EuclideanComplex(mesh.complex, points=mesh.points)
    L, M = geo.stiffness_matrix(), geo.mass_matrix(lumped=True)
    eps = 1e-8 * float(abs(L).sum(axis=1).max() / M.diagonal().min())
    t = time.perf_counter()
    solve(L, M, -eps, np.ones(L.shape[0]), positive_definite=True)
    return time.perf_counter() - t


def main(names):
    u = point_charge_factor([[0.0, 0.0, 1.6, 0.8], [1.5, 0.0, 0.0, -0.5]])
    for name in names:
        n = SIZES[name]
        t = time.perf_counter()
        mesh = ball_tet_mesh(n)
        t_mesh = time.perf_counter() - t
        res = conformal_deformation(mesh, None, u)
        tf = factor_time(mesh)
        tt = res.timings
        rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024**2
        print(f"{name:>5}: {mesh.tets.shape[0]} tets, {mesh.points.shape[0]} vertices; generate {t_mesh:.2f} s; "
              + ", ".join(f"{k} {v:.2f} s" for k, v in tt.items())
              + f"; one factorization of L: {tf:.2f} s; total / factorization = {tt['total'] / tf:.1f}; "
              f"λ₁ = {res.eigenvalue:.4g}, backend {res.statistics['solver']['backend']}, peak RSS {rss:.2f} GB",
              flush=True)


if __name__ == "__main__":
    main(sys.argv[1:] or ["200k"])
