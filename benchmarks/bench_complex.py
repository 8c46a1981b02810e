"""Benchmark: construction of a 1M-tet complex with all faces and boundary matrices.

Target (issue 2): < 10 s.  Run:  OPENBLAS_NUM_THREADS=1 python benchmarks/bench_complex.py
"""
from __future__ import annotations

import time

import numpy as np

from dhlb import SimplicialComplex
from dhlb.examples import cube_nd


def main(m: int = 55) -> None:
    _, T = _tets(m)
    t0 = time.perf_counter()
    X = SimplicialComplex(T)
    t1 = time.perf_counter()
    boundaries = [X.boundary(k) for k in range(X.dim + 1)]
    t2 = time.perf_counter()
    assert all(abs(boundaries[k - 1] @ boundaries[k]).sum() == 0 for k in range(2, X.dim + 1))
    print(f"complex: {T.shape[0]:,} tets, counts {X.counts}")
    print(f"  construction (all faces, sorted, indexed): {t1 - t0:6.2f} s")
    print(f"  all boundary matrices:                     {t2 - t1:6.2f} s")
    print(f"  total:                                     {t2 - t0:6.2f} s   (target < 10 s)")
    # 4x smaller for a linearity ratio
    _, T4 = _tets(round(m / 4 ** (1 / 3)))
    s0 = time.perf_counter()
    Y = SimplicialComplex(T4)
    [Y.boundary(k) for k in range(Y.dim + 1)]
    s1 = time.perf_counter()
    print(f"  time ratio for {T.shape[0] / T4.shape[0]:.2f}x the size: {(t2 - t0) / (s1 - s0):.2f}")


def _tets(m):
    X = cube_nd(3, m)
    return X, np.asarray(X.vertex_labels[X.simplices(3)])


if __name__ == "__main__":
    main()
