"""The computational core of :mod:`dhlb.topology.homology`: the reduced complex, its groups, and Smith bases.

Steps 1–2 of the method described in :mod:`dhlb.topology.homology`: :func:`check_boundaries`
validates the boundary matrices; :class:`HomologyBases` reduces the chain complex, first by an
acyclic matching (:mod:`dhlb.topology._morse`), then by sparse unit-pivot elimination of the Morse
complex (:mod:`dhlb.topology._sparse_elim`), and reads the groups off the small residual ("core"):
``b_k = n'_k − rank ∂''_k − rank ∂''_{k+1}``, the torsion from the invariant factors of
``∂''_{k+1}``.  No basis is built for that.  Bases are built per degree when asked: the cells of
the residual that meet neither core are free generators on their own (unit vectors), and two
Smith forms on the cells that do give the rest — the homology basis ``G`` (free generators,
torsion generators with their orders) and the dual integer cochains ``ε`` with
``ε_i(G_j) = δ_ij`` — lifted back to the original complex as sparse chains.  Over ``Z/p`` the
elimination leaves no core and the residual cells are the basis.  The universal-coefficient
step 3 stays in :func:`dhlb.topology.homology.cohomology_from_boundaries`.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from dhlb.errors import InvalidMatrixError, ShapeError
from dhlb.topology._intmatrix import as_object_matrix, to_int_array
from dhlb.topology._morse import MorseMatching
from dhlb.topology._normal_forms import _snf
from dhlb.topology._sparse_elim import ChainReduction

__all__ = ["check_boundaries", "HomologyBases"]


def check_boundaries(boundaries, trusted: bool = False) -> list:
    """Validate ``[∂_0, ..., ∂_n]`` (shapes, integer entries, ``∂_{k-1} ∂_k = 0`` unless ``trusted``) as int64 CSR."""
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
        if k >= 2 and not trusted:
            P = (mats[k - 1] @ mats[k]).tocoo()
            P.eliminate_zeros()
            if P.nnz:
                raise InvalidMatrixError(f"∂_{k - 1} ∂_{k} ≠ 0 (entry ({P.row[0]}, {P.col[0]}) is {P.data[0]}); "
                                         "the matrices do not form a chain complex.")
    return mats


class HomologyBases:
    """The reduced chain complex, its groups, and (per degree, on demand) Smith bases (module docstring).

    Parameters
    ----------
    boundaries : list
        ``[∂_0, ..., ∂_n]`` as for :func:`check_boundaries`.
    p : int, optional
        A prime: work over ``Z/p`` (then ``rank(k)`` is the dimension of ``H_k(Z/p)`` and there
        is no torsion).  Default: over ``Z``.
    trusted : bool, default False
        The matrices are a :class:`~dhlb.topology.complex.SimplicialComplex`'s own: ``∂∂ = 0`` is
        not checked again.
    """

    def __init__(self, boundaries, p: int | None = None, trusted: bool = False):
        self.mats = check_boundaries(boundaries, trusted)
        self.p = p
        self.n = len(self.mats) - 1
        self.sizes = [self.mats[0].shape[1]] + [M.shape[1] for M in self.mats[1:]]
        self.morse = MorseMatching(self.mats, p)
        crit = [len(c) for c in self.morse.critical]
        self.red = ChainReduction([None] + [self.morse.residual(k) for k in range(1, self.n + 1)], crit, p)
        self.morse.release()
        self.red.reduce_all()
        self.alive = [self.red.alive_index(k) for k in range(self.n + 1)]
        self.cores = [None] + [self.red.residual_core(k) for k in range(1, self.n + 1)]
        self.invariants = [()] + [self._invariants(self.cores[k][2]) for k in range(1, self.n + 1)]
        self._deg: dict = {}
        self._cochains: dict = {}

    def _invariants(self, M) -> tuple:
        """The nonzero Smith invariants of a core matrix (over ``Z/p`` a core is always empty)."""
        if not M.size:
            return ()
        if self.p is not None:
            raise RuntimeError("internal error: the elimination over Z/p left a residual")
        _, S, _, _, _ = _snf(M)
        return tuple(int(S[i, i]) for i in range(min(S.shape)) if S[i, i] != 0)

    # ------------------------------------------------------------------ groups
    def rank(self, k: int) -> int:
        """``b_k`` (over ``Z/p``: the dimension of ``H_k(Z/p)``)."""
        r_k = len(self.invariants[k]) if k >= 1 else 0
        r_k1 = len(self.invariants[k + 1]) if k < self.n else 0
        return len(self.alive[k]) - r_k - r_k1

    def torsion(self, k: int) -> tuple:
        """The torsion coefficients of ``H_k`` (invariant factors > 1 of ``∂''_{k+1}``)."""
        return tuple(d for d in self.invariants[k + 1] if d > 1) if k < self.n else ()

    # ------------------------------------------------------------------ bases
    def degree(self, k: int) -> dict:
        """The Smith bases of degree ``k`` on the residual (computed once, on first use).

        ``free0``: residual positions that are free generators on their own; ``W``: the positions
        of the two cores; ``G`` / ``eps`` (over ``W``): basis and dual cochains of the rest;
        ``free`` / ``tors`` index their columns; ``orders`` the torsion orders.
        """
        if k in self._deg:
            return self._deg[k]
        na = len(self.alive[k])
        rk, ck, Mk = self.cores[k] if k >= 1 else (np.zeros(0, np.int64), np.zeros(0, np.int64),
                                                     np.zeros((0, 0), dtype=object))
        if k < self.n:
            rk1, ck1, Mk1 = self.cores[k + 1]
        else:
            rk1, ck1, Mk1 = np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros((0, 0), dtype=object)
        pos = {int(c): i for i, c in enumerate(self.alive[k].tolist())}
        W = sorted({pos[int(c)] for c in ck} | {pos[int(r)] for r in rk1})
        wpos = {w: i for i, w in enumerate(W)}
        Dk = np.zeros((len(rk), len(W)), dtype=object)
        for j, c in enumerate(ck.tolist()):
            Dk[:, wpos[pos[c]]] = Mk[:, j]
        Dk1 = np.zeros((len(W), len(ck1)), dtype=object)
        for i, r in enumerate(rk1.tolist()):
            Dk1[wpos[pos[r]], :] = Mk1[i, :]
        _, S, Q, _, Qi = _snf(Dk)
        r = sum(1 for i in range(min(S.shape)) if S[i, i] != 0)
        Z, Zdual = Q[:, r:], Qi[r:, :]
        P, S2, _, Pi, _ = _snf(Zdual.dot(Dk1))
        s = [S2[i, i] for i in range(min(S2.shape)) if S2[i, i] != 0]
        tors = [i for i, d in enumerate(s) if d > 1]
        inW = set(W)
        d = dict(free0=[i for i in range(na) if i not in inW], W=W, G=Z.dot(Pi), eps=P.dot(Zdual),
                 free=list(range(len(s), Z.shape[1])), tors=tors, orders=tuple(int(s[i]) for i in tors))
        self._deg[k] = d
        return d

    def _to_cells(self, k: int, vals: dict, lift) -> dict:
        """Residual positions -> reduced (Morse) cells -> all cells, as ``{cell: {g: v}}``."""
        crit = self.morse.critical[k]
        return lift(k, {int(crit[i]): z for i, z in vals.items()})

    def _dense(self, k: int, vals: dict, g: int) -> np.ndarray:
        from dhlb._memory_errors import check_memory

        check_memory(f"the basis of degree {k} ({g:,} chains over {self.sizes[k]:,} cells)", g, 16 * self.sizes[k] * g,
                     advice="the groups themselves (rank, torsion) need no basis; ask for the basis of a "
                            "smaller complex or a lower degree")
        out = np.zeros((self.sizes[k], g), dtype=object)
        for cell, z in vals.items():
            for j, w in z.items():
                out[cell, j] = w
        return to_int_array(out) if self.p is None else out.astype(np.int64)

    def _start(self, k: int, d: dict, vectors) -> tuple[dict, int]:
        """The basis of degree ``k`` on the residual as ``({cell: {g: v}}, count)``.

        The unit vectors of ``free0`` first, then ``vectors`` (over ``W``), numbered in that order;
        ``d`` is :meth:`degree` ``(k)``.
        """
        cells = self.alive[k]
        start: dict = {int(cells[i]): {g: 1} for g, i in enumerate(d["free0"])}
        g = len(d["free0"])
        for vec in vectors:
            for i, w in enumerate(vec):
                if w:
                    start.setdefault(int(cells[d["W"][i]]), {})[g] = int(w)
            g += 1
        return start, g

    def homology_generators(self, k: int) -> tuple:
        """``(rank, torsion, generators)`` of ``H_k``: generator cycles lifted to ``X.simplices(k)``."""
        d = self.degree(k)
        start, g = self._start(k, d, [d["G"][:, col] for col in d["free"] + d["tors"]])
        vals = self.red._backsolve(self.red.row_steps[k], start)
        gens = self._dense(k, self._to_cells(k, vals, self.morse.lift_chains), g)
        if gens.dtype == np.int64 and gens.size and k >= 1:  # cheap exact check: the lifted chains are cycles
            B = self.mats[k] @ gens
            if (B % self.p if self.p is not None else B).any():
                raise RuntimeError("internal error: a lifted homology generator is not a cycle")
        return self.rank(k), self.torsion(k), gens

    def _lift_cochains(self, k: int, start: dict, g: int) -> np.ndarray:
        vals = self.red._backsolve(self.red.col_steps[k], start)
        return self._dense(k, self._to_cells(k, vals, self.morse.lift_cochains), g)

    def dual_cochains(self, k: int) -> np.ndarray:
        """Lifted ε rows for the free then torsion generators of H_k, as columns."""
        if k not in self._cochains:
            d = self.degree(k)
            start, g = self._start(k, d, [d["eps"][row] for row in d["free"] + d["tors"]])
            self._cochains[k] = self._lift_cochains(k, start, g)
        return self._cochains[k]

    def ext_cocycles(self, k: int):
        """Integer cocycles ``τ = δ ε_t / d`` in degree k for the torsion of H_{k-1}, and their orders."""
        if k == 0:
            return np.zeros((self.sizes[0], 0), dtype=np.int64), ()
        d = self.degree(k - 1)
        if not d["tors"]:
            return np.zeros((self.sizes[k], 0), dtype=np.int64), ()
        # δ ε_t on the residual: ε_t lives on W of degree k-1; ∂''_k maps residual k-cells there
        R = self.red.R[k]
        start: dict = {}
        for g, (row, o) in enumerate(zip(d["tors"], d["orders"])):
            eps = {int(self.alive[k - 1][d["W"][i]]): int(w) for i, w in enumerate(d["eps"][row]) if w}
            acc: dict = {}
            for a, w in eps.items():
                for c, v in R.get(a, {}).items():
                    acc[c] = acc.get(c, 0) + w * v
            for c, v in acc.items():
                if v:
                    if v % o:
                        raise RuntimeError("internal error: δε_t is not divisible by the torsion order")
                    start.setdefault(c, {})[g] = v // o
        return self._lift_cochains(k, start, len(d["tors"])), d["orders"]
