"""MPI checks of dhlb.linalg.distributed; run ``mpirun -n P python tests/mpi/linalg_checks.py OUT.npz [--nan]``.

Each rank builds only its own rows of a complex Hermitian pencil on a 3-D grid (a magnetic
Laplacian ``A`` with a weak potential, a non-diagonal mass ``M``), row by row from the grid
coordinates; no rank ever forms the global matrix.  Rank 0 writes the eigenvalues, the gathered
eigenvectors and the shift to ``OUT.npz`` (the pytest compares the runs for P = 1, 2, 3) and prints
one line per check.  ``--nan``: the last rank puts a NaN into one of its rows; every rank must
raise the same error, and the run must end with one error line, not hang.
"""

import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from mpi4py import MPI  # noqa: E402

from dhlb.linalg.backends_petsc import row_ranges  # noqa: E402
from dhlb.linalg.distributed import (  # noqa: E402
    RowBlock,
    default_shift_distributed,
    gather_to_root,
    petsc_matrix,
    row_layout,
    scatter_values,
    start_vector,
)
from dhlb.linalg.distributed_eigen import distributed_eigenpairs  # noqa: E402

COMM = MPI.COMM_WORLD
RANK, SIZE = COMM.rank, COMM.size
SHAPE = (13, 11, 9)            # grid points per axis: n = 1287, generic (simple spectrum)
FLUX = 0.37                    # magnetic flux per xy-plaquette


def grid_rows(start, stop):
    """The rows ``[start, stop)`` of ``A`` and ``M``: built from the grid coordinates of those rows only."""
    nx, ny, nz = SHAPE
    g = np.arange(start, stop)
    i, j, k = g // (ny * nz), (g // nz) % ny, g % nz
    rows_a, rows_m = [], []
    for gi, ii, jj, kk in zip(g, i, j, k):
        cols, vals, mvals = [], [], []
        w = 1.0 + 0.3 * np.cos(0.7 * gi)                        # mass weight of this point
        for d, (di, dj, dk) in enumerate([(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]):
            a, b, c = ii + di, jj + dj, kk + dk
            if not (0 <= a < nx and 0 <= b < ny and 0 <= c < nz):
                continue
            h = (a * ny + b) * nz + c
            theta = FLUX * ii * dj + 0.11 * kk * di             # antisymmetric: ii (kk) is fixed along y (x)
            cols.append(h)
            vals.append(-np.exp(1j * theta))
            wh = 1.0 + 0.3 * np.cos(0.7 * h)
            mvals.append(0.05 * np.sqrt(w * wh) if d < 2 else 0.0)
        deg = len(cols)
        cols.append(gi)
        vals.append(deg + 0.02 * ii + 0.013 * jj * jj)          # a weak potential: no degeneracies
        mvals.append(w)
        order = np.argsort(cols)
        cols = np.asarray(cols)[order]
        rows_a.append((cols, np.asarray(vals)[order]))
        rows_m.append((cols, np.asarray(mvals)[order]))
    return rows_a, rows_m


def block(rows, start, stop, n):
    indptr = np.r_[0, np.cumsum([len(c) for c, _ in rows])].astype(np.int64)
    indices = np.concatenate([c for c, _ in rows]).astype(np.int64)
    data = np.concatenate([v for _, v in rows]).astype(np.complex128)
    return RowBlock(indptr=indptr, indices=indices, data=data, start=start, stop=stop, n=n)


def main():
    out = sys.argv[1]
    n = int(np.prod(SHAPE))
    start, stop, n_sum = row_layout(np.diff(row_ranges(n, SIZE)[RANK])[0])
    assert n_sum == n and (start, stop) == row_ranges(n, SIZE)[RANK]
    rows_a, rows_m = grid_rows(start, stop)
    A, M = block(rows_a, start, stop, n), block(rows_m, start, stop, n)
    if "--nan" in sys.argv and RANK == SIZE - 1:
        A.data[3] = np.nan
    lines = []
    # what is handed to PETSc: only the owned rows
    Ap = petsc_matrix(A)
    assert len(A.indptr) - 1 == stop - start and A.indices.size <= 7 * (stop - start)
    assert Ap.getLocalSize() == (stop - start, stop - start) and Ap.getOwnershipRange() == (start, stop)
    lines.append(f"local rows {stop - start} of {n} (PETSc local size {Ap.getLocalSize()}): ok")
    # halo scatter: the values at the column ids of the owned rows, 1 and 2 columns, real and complex
    x = np.column_stack([np.arange(start, stop) + 0.5j * np.arange(start, stop) ** 2, -np.arange(start, stop)])
    halo = np.unique(A.indices)[::-1]
    got = scatter_values(x, start, stop, n, np.r_[halo, halo[:3]])
    want = np.column_stack([np.r_[halo, halo[:3]] + 0.5j * np.r_[halo, halo[:3]] ** 2, -np.r_[halo, halo[:3]]])
    assert np.array_equal(got, want), "halo scatter (2 columns) wrong"
    assert np.array_equal(scatter_values(start_vector(start, stop), start, stop, n, halo), start_vector(0, n)[halo])
    lines.append(f"halo scatter of {halo.size} ids (of which {np.sum((halo < start) | (halo >= stop))} "
                 "off-rank): ok")
    eps = default_shift_distributed(A, M)
    res = distributed_eigenpairs(A, M, 3, tol=1e-12, method="krylovschur")
    assert res.converged and res.vectors.shape == (stop - start, 3), res.note
    gam = distributed_eigenpairs(A, M, 1, tol=1e-10, method="lobpcg-gamg")
    assert gam.converged and abs(gam.eigenvalues[0] / res.eigenvalues[0] - 1) < 1e-8, (gam, res.eigenvalues)
    lines.append(f"eigenvalues {res.eigenvalues.tolist()} (η ≤ {res.residuals.max():.1e}, "
                 f"{res.stats.get('factor_entries', 0):.3g} factor entries), lobpcg-gamg {gam.iterations} its: ok")
    U = gather_to_root(res.vectors)
    if RANK == 0:
        np.savez(out, eigenvalues=res.eigenvalues, vectors=U, shift=eps, lobpcg=gam.eigenvalues)
        for ln in lines:
            print(f"[{SIZE} ranks] {ln}")


if __name__ == "__main__":
    main()
