"""The computational core of :mod:`dhlb.topology.homology`: reduced complex and Smith bases.

Steps 1–2 of the method described in :mod:`dhlb.topology.homology`: :func:`check_boundaries`
validates the boundary matrices; :class:`HomologyBases` reduces the chain complex by sparse ±1
elimination (:mod:`dhlb.topology._sparse_elim`) and, for each degree ``k``, computes from two
Smith forms on the small residual the homology basis ``G`` (free generators, torsion generators
with their orders) and the dual integer cochains ``ε`` with ``ε_i(G_j) = δ_ij``, lifted back to
the original complex on demand. The universal-coefficient step 3 stays in
:func:`dhlb.topology.homology.cohomology_from_boundaries`.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from dhlb.errors import InvalidMatrixError, ShapeError
from dhlb.topology._intmatrix import as_object_matrix, to_int_array
from dhlb.topology._normal_forms import _snf
from dhlb.topology._sparse_elim import ChainReduction

__all__ = ["check_boundaries", "HomologyBases"]


def check_boundaries(boundaries) -> list:
    """Validate ``[∂_0, ..., ∂_n]`` (shapes, integer entries, ``∂_{k-1} ∂_k = 0``) and return them as int64 CSR."""
    mats = []
    for k, B in enumerate(boundaries):
        if not sp.issparse(B):
            M = to_int_array(as_object_matrix(B, f"∂_{k}"))
            if M.dtype != np.int64:
                raise InvalidMatrixError(f"∂_{k} has entries beyond int64; boundary matrices are small integers.")
            B = M
        mats.append(sp.csr_matrix(B))
    if not mats:
        raise ShapeError("boundaries is empty; pass [∂_0, ∂_1, ..., ∂_n] with ∂_0 of shape (0, n_0).")
    if mats[0].shape[0] != 0:
        raise ShapeError(f"boundaries[0] must be ∂_0 of shape (0, n_0) (as X.boundary(0)), got shape "
                         f"{mats[0].shape}; prepend scipy.sparse.csr_matrix((0, n_0)).")
    for k in range(1, len(mats)):
        if mats[k].shape[0] != mats[k - 1].shape[1]:
            raise ShapeError(f"∂_{k} has {mats[k].shape[0]} rows but ∂_{k - 1} has {mats[k - 1].shape[1]} "
                             f"columns; ∂_k must have shape (n_{{k-1}}, n_k).")
        if mats[k].dtype.kind not in "iub":
            A = mats[k]
            if A.dtype.kind != "f" or np.any(A.data != np.round(A.data)) or not np.all(np.isfinite(A.data)):
                raise InvalidMatrixError(f"∂_{k} has non-integer entries; boundary matrices are integer.")
        mats[k] = mats[k].astype(np.int64)
        if k >= 2:
            P = (mats[k - 1] @ mats[k]).tocoo()
            P.eliminate_zeros()
            if P.nnz:
                raise InvalidMatrixError(f"∂_{k - 1} ∂_{k} ≠ 0 (entry ({P.row[0]}, {P.col[0]}) is {P.data[0]}); "
                                         "the matrices do not form a chain complex.")
    return mats


class HomologyBases:
    """The reduced chain complex and, per degree, the Smith bases of its homology (module docstring)."""

    def __init__(self, boundaries):
        self.mats = check_boundaries(boundaries)
        self.n = len(self.mats) - 1
        self.sizes = [self.mats[0].shape[1]] + [M.shape[1] for M in self.mats[1:]]
        self.red = ChainReduction(self.mats, self.sizes)
        self.red.reduce_all()
        na = [len(self.red.alive_index(k)) for k in range(self.n + 1)]
        self.D = [np.zeros((0, na[0]), dtype=object)] + [self.red.residual(k) for k in range(1, self.n + 1)]
        self.deg = []
        for k in range(self.n + 1):
            Dk = self.D[k]
            Dk1 = self.D[k + 1] if k < self.n else np.zeros((na[k], 0), dtype=object)
            _, S, Q, _, Qi = _snf(Dk)
            r = sum(1 for i in range(min(S.shape)) if S[i, i] != 0)
            Z, Zdual = Q[:, r:], Qi[r:, :]
            C = Zdual.dot(Dk1)
            P, S2, _, Pi, _ = _snf(C)
            s = [S2[i, i] for i in range(min(S2.shape)) if S2[i, i] != 0]
            G = Z.dot(Pi)
            eps = P.dot(Zdual)
            free = list(range(len(s), Z.shape[1]))
            tors = [i for i, d in enumerate(s) if d > 1]
            self.deg.append(dict(G=G, eps=eps, free=free, tors=tors, orders=tuple(int(s[i]) for i in tors)))
        self._cochains = {}

    def homology_generators(self, k: int) -> tuple:
        """``(rank, torsion, generators)`` of ``H_k``: generator cycles lifted to ``X.simplices(k)``."""
        d = self.deg[k]
        cols = d["free"] + d["tors"]
        gens = self.red.lift_chains(k, d["G"][:, cols])
        gens = to_int_array(gens)
        if gens.dtype == np.int64 and gens.size:  # cheap exact check: the lifted chains are cycles
            if k >= 1 and abs(self.mats[k] @ gens).max() != 0:
                raise RuntimeError("internal error: a lifted homology generator is not a cycle")
        return len(d["free"]), d["orders"], gens

    def dual_cochains(self, k: int) -> np.ndarray:
        """Lifted ε rows for the free then torsion generators of H_k, as columns (object)."""
        if k not in self._cochains:
            d = self.deg[k]
            rows = d["free"] + d["tors"]
            self._cochains[k] = self.red.lift_cochains(k, d["eps"][rows].T)
        return self._cochains[k]

    def ext_cocycles(self, k: int):
        """Integer cocycles ``τ = δ ε_t / d`` in degree k for the torsion of H_{k-1}, and their orders."""
        if k == 0:
            return np.zeros((self.sizes[0], 0), dtype=object), ()
        d = self.deg[k - 1]
        eps_t = d["eps"][d["tors"]]  # (t, n'_{k-1})
        tau = eps_t.dot(self.D[k])  # rows: δε_t on the reduced complex
        for i, o in enumerate(d["orders"]):
            tau[i] = tau[i] // o
        return self.red.lift_cochains(k, tau.T), d["orders"]
