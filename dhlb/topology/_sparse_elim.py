"""Sparse unit-pivot elimination of integer chain complexes (internal).

A pivot ``(a, b)`` with ``∂_k[a, b] = u = ±1`` splits off the contractible summand
``b -> ∂b``: in the new bases (``a' = ∂b`` replaces ``a`` in ``C_{k-1}``, ``c' = c - λ_c b`` with
``λ_c = u ∂_k[a, c]`` replaces ``c`` in ``C_k``) the complex is the direct sum of ``{b -> a'}`` and a
reduced complex with

* ``∂'_k``: the Schur complement ``∂_k - ∂_k[:, b] u ∂_k[a, :]`` without row ``a`` and column ``b``,
* ``∂'_{k-1}``: ``∂_{k-1}`` without column ``a``,
* ``∂'_{k+1}``: ``∂_{k+1}`` without row ``b``.

The reduced complex has the same homology.  ``ι`` (reduced chains -> chains) and ``π`` (chains ->
reduced chains) are chain maps with ``π ι = id``; ``ι`` is a back-substitution over the stored
pivot rows, and ``π^T`` (reduced cochains -> cochains) one over the stored pivot columns.  So
cycles lift with ``ι``, cocycles with ``π^T``, and Kronecker pairings are preserved:
``⟨π^T φ, ι z⟩ = ⟨φ, z⟩``.  Pivots are chosen Markowitz-style (shortest line first, then the
unit entry whose other line is shortest) to limit fill; entries are exact Python ints.
"""

from __future__ import annotations

import heapq

import numpy as np
import scipy.sparse as sp

from dhlb.errors import InvalidMatrixError, ShapeError
from dhlb.topology._intmatrix import to_int_array
from dhlb.topology._normal_forms import dense_kernel_basis, dense_solve_integer
from dhlb.topology.graph import graph_kernel, incidence, incidence_forest

_I64 = np.iinfo(np.int64)


def _to_dicts(A, p: int | None = None) -> tuple[dict, dict]:
    """Row and column dicts ``{i: {j: v}}`` of a sparse integer matrix (exact Python ints; modulo ``p`` if given)."""
    A = sp.csr_matrix(A)
    if A.dtype.kind == "f":
        if not np.all(np.isfinite(A.data)) or np.any(A.data != np.round(A.data)):
            raise InvalidMatrixError("matrix has non-integer entries; pass an integer matrix.")
    elif A.dtype.kind not in "iub":
        raise InvalidMatrixError(f"matrix has dtype {A.dtype}, expected integers.")
    A = A.astype(np.int64)
    A.sum_duplicates()
    if p is not None:
        A.data %= p
    A.eliminate_zeros()
    R, C = {}, {}
    ip, ind, dat = A.indptr, A.indices.tolist(), A.data.tolist()
    for i in range(A.shape[0]):
        s, e = ip[i], ip[i + 1]
        if s < e:
            R[i] = dict(zip(ind[s:e], dat[s:e]))
    At = A.tocsc()
    ip, ind, dat = At.indptr, At.indices.tolist(), At.data.tolist()
    for j in range(A.shape[1]):
        s, e = ip[j], ip[j + 1]
        if s < e:
            C[j] = dict(zip(ind[s:e], dat[s:e]))
    return R, C


def substitute(terms, u_inv: int, p: int | None = None) -> dict:
    """One back-substitution step on sparse chains: ``−u⁻¹ Σ v z`` over ``terms`` = pairs ``(v, z)``.

    ``z`` are sparse vectors ``{generator: value}`` (the chains of several generators at once);
    exact Python integers, or residues modulo ``p``.  Returns the (possibly empty) result dict.
    """
    acc: dict = {}
    for v, z in terms:
        for g, w in z.items():
            nv = acc.get(g, 0) + v * w
            if p is not None:
                nv %= p
            if nv:
                acc[g] = nv
            else:
                del acc[g]
    if p is not None:
        return {g: (-u_inv * w) % p for g, w in acc.items()}
    return {g: -w for g, w in acc.items()} if u_inv == 1 else acc


class ChainReduction:
    """Unit-pivot reduction of a chain complex ``C_n -> ... -> C_0``.

    Parameters
    ----------
    mats : list
        ``mats[k]`` is ``∂_k`` (sparse, shape ``(sizes[k-1], sizes[k])``) for ``k = 1..n``;
        ``mats[0]`` is ignored.
    sizes : sequence of int
        ``(n_0, ..., n_n)``.
    p : int, optional
        A prime: eliminate over ``Z/p`` (every nonzero entry is a pivot; the entries of ``mats``
        are read modulo ``p``).  Default: over ``Z`` with ±1 pivots.

    Notes
    -----
    ``mats[k]`` may also be a pair ``(rows, cols)`` of dicts ``{i: {j: v}}`` (as from
    :meth:`dhlb.topology._morse.MorseMatching.residual`); then it is used as it is.
    """

    def __init__(self, mats, sizes, p: int | None = None):
        self.sizes = [int(s) for s in sizes]
        self.n = len(self.sizes) - 1
        self.p = p
        self.R = [None] * (self.n + 1)
        self.C = [None] * (self.n + 1)
        for k in range(2, self.n + 1):
            self.R[k], self.C[k] = mats[k] if isinstance(mats[k], tuple) else _to_dicts(mats[k], p)
        self.alive = [np.ones(s, dtype=bool) for s in self.sizes]
        self.row_steps = [[] for _ in self.sizes]  # row_steps[j]: pivots in ∂_j (b ∈ C_j): (b, u⁻¹, row_a, a)
        self.col_steps = [[] for _ in self.sizes]  # col_steps[j]: pivots in ∂_{j+1} (a ∈ C_j): (a, u⁻¹, col_b, b)
        self.graph_done = (self.n >= 1 and p is None and not isinstance(mats[1], tuple)
                           and self._eliminate_graph(mats[1]))
        if self.n >= 1 and not self.graph_done:
            self.R[1], self.C[1] = mats[1] if isinstance(mats[1], tuple) else _to_dicts(mats[1], p)

    def _eliminate_graph(self, A) -> bool:
        """Fast path for an incidence matrix ``∂_1``.

        Pivots ``(v, tree edge to the parent)`` of a breadth-first forest, parents first.  Then
        every pivot column is ``{v: u, root: -u}``
        (column sums stay zero, the fill goes to the root row), the stored rows are the original
        rows, and the residual is zero.  Returns False if ``A`` is not an incidence matrix.
        """
        A = sp.csc_matrix(A)
        if A.dtype.kind not in "iu":
            return False
        A = A.astype(np.int64)
        A.eliminate_zeros()
        A.sort_indices()
        inc = incidence(A)
        if inc is None:
            return False
        head, tail = inc
        m = A.shape[0]
        order, _pred, tree_col, _sign, root = incidence_forest(head, tail, m)
        Ar = A.tocsr()
        ip, ind, dat = Ar.indptr, Ar.indices.tolist(), Ar.data.tolist()
        for v in order.tolist():
            b = int(tree_col[v])
            if b < 0:
                continue
            row = dict(zip(ind[ip[v]:ip[v + 1]], dat[ip[v]:ip[v + 1]]))
            u = row.pop(b)
            self.row_steps[1].append((b, u, row, v))
            self.col_steps[0].append((v, u, {int(root[v]): -u}, b))
        tree = tree_col[tree_col >= 0]
        self.alive[1][tree] = False
        self.alive[0][tree_col >= 0] = False
        self.R[1], self.C[1] = {}, {}
        if self.n >= 2:
            R2, C2 = self.R[2], self.C[2]
            for b in tree.tolist():
                row = R2.pop(b, None)
                if row:
                    for c in row:
                        del C2[c][b]
        return True

    # ------------------------------------------------------------------ elimination
    def eliminate(self, k: int) -> int:
        """Eliminate unit pivots of ``∂_k`` until none is left; return the number of pivots."""
        R, C = self.R[k], self.C[k]
        p = self.p
        # heap of columns keyed by (length << 32 | column); rows are reached through their columns
        heap = [(len(v) << 32) | j for j, v in C.items()]
        heapq.heapify(heap)
        push, pop = heapq.heappush, heapq.heappop
        count = 0
        while heap:
            item = pop(heap)
            L, key = item >> 32, item & 0xFFFFFFFF
            line = C.get(key)
            if line is None or len(line) != L:
                continue
            best, bl = None, None
            for k2, v in line.items():
                if p is not None or v == 1 or v == -1:
                    l2 = len(R[k2])
                    if bl is None or l2 < bl:
                        best, bl = k2, l2
                        if l2 <= 1:
                            break
            if best is None:
                continue
            a, b = best, key
            row_a = R.pop(a)
            u = row_a.pop(b)
            if p is not None:
                u = pow(u, -1, p)  # u⁻¹; over Z, u⁻¹ = u
            col_b = C.pop(b)
            del col_b[a]
            for c in row_a:
                del C[c][a]
            for x in col_b:
                del R[x][b]
            for x, vx in col_b.items():
                f = vx * u
                rx = R[x]
                for c, vc in row_a.items():
                    nv = rx.get(c, 0) - f * vc
                    if p is not None:
                        nv %= p
                    if nv:
                        rx[c] = nv
                        C[c][x] = nv
                    else:
                        del rx[c]
                        del C[c][x]
            for c in row_a:
                push(heap, (len(C[c]) << 32) | c)
            if k > 1:  # column a of ∂_{k-1} and row b of ∂_{k+1} disappear
                col = self.C[k - 1].pop(a, None)
                if col:
                    Rl = self.R[k - 1]
                    for y in col:
                        del Rl[y][a]
            if k < self.n:
                row = self.R[k + 1].pop(b, None)
                if row:
                    Cu = self.C[k + 1]
                    for c in row:
                        del Cu[c][b]
            self.alive[k][b] = False
            self.alive[k - 1][a] = False
            self.row_steps[k].append((b, u, row_a, a))
            self.col_steps[k - 1].append((a, u, col_b, b))
            count += 1
        return count

    def reduce_all(self) -> None:
        """Eliminate in ``∂_1`` (spanning forest), then ``∂_n, ∂_{n-1}, ..., ∂_2``."""
        if self.n >= 1 and not self.graph_done:
            self.eliminate(1)
        for k in range(self.n, 1, -1):
            self.eliminate(k)

    # ------------------------------------------------------------------ residual and lifting
    def alive_index(self, j: int) -> np.ndarray:
        """Original indices of the cells of ``C_j`` that survive (the reduced basis)."""
        return np.flatnonzero(self.alive[j])

    def residual(self, k: int) -> np.ndarray:
        """Dense object matrix of ``∂'_k`` on the surviving cells."""
        rows, cols = self.alive_index(k - 1), self.alive_index(k)
        M = np.zeros((len(rows), len(cols)), dtype=object)
        if len(rows) and len(cols):
            rpos = {int(r): i for i, r in enumerate(rows)}
            cpos = {int(c): j for j, c in enumerate(cols)}
            for r, line in self.R[k].items():
                i = rpos[r]
                for c, v in line.items():
                    M[i, cpos[c]] = v
        return M

    def residual_core(self, k: int):
        """``(rows, cols, M)``: the nonzero rows/columns of ``∂'_k`` and the dense matrix on them.

        Rows and columns are original indices, ``M`` is an object matrix; every other surviving row
        and column of ``∂'_k`` is zero.
        """
        rows = sorted(r for r, line in self.R[k].items() if line)
        cols = sorted({c for r in rows for c in self.R[k][r]})
        cpos = {c: j for j, c in enumerate(cols)}
        M = np.zeros((len(rows), len(cols)), dtype=object)
        for i, r in enumerate(rows):
            for c, v in self.R[k][r].items():
                M[i, cpos[c]] = v
        return np.asarray(rows, dtype=np.int64), np.asarray(cols, dtype=np.int64), M

    def _backsolve(self, steps, start: dict) -> dict:
        """``vals[t] = -u⁻¹ Σ_c line[c] vals[c]`` over ``steps`` in reverse; vals are sparse dicts."""
        vals = dict(start)
        for t, u, line, _ in reversed(steps):
            z = substitute(((v, zc) for c, v in line.items() if (zc := vals.get(c))), u, self.p)
            if z:
                vals[t] = z
        return vals

    def _lift(self, steps, j: int, Z) -> np.ndarray:
        Z = np.asarray(Z, dtype=object)
        idx = self.alive_index(j)
        r = Z.shape[1]
        start = {}
        for t, i in enumerate(idx):
            d = {g: int(w) for g, w in enumerate(Z[t]) if w != 0}
            if d:
                start[int(i)] = d
        vals = self._backsolve(steps, start)
        out = np.zeros((self.sizes[j], r), dtype=object)
        for p, d in vals.items():
            for g, w in d.items():
                out[p, g] = w
        return out

    def lift_chains(self, j: int, Z) -> np.ndarray:
        """``ι``: reduced j-chains (rows = surviving cells) -> chains on all of ``C_j``."""
        return self._lift(self.row_steps[j], j, Z)

    def lift_cochains(self, j: int, Phi) -> np.ndarray:
        """``π^T``: reduced j-cochains -> cochains on all of ``C_j``."""
        return self._lift(self.col_steps[j], j, Phi)


# ---------------------------------------------------------------------------- single matrices
def _int_sparse(entries, shape) -> sp.csc_matrix:
    rows, cols, vals = entries
    vals = list(vals)
    if vals and any(not (_I64.min <= v <= _I64.max) for v in vals):
        raise InvalidMatrixError("an entry of the result does not fit in int64; use the dense functions.")
    return sp.csc_matrix((np.asarray(vals, dtype=np.int64), (np.asarray(rows, dtype=np.int64),
                                                               np.asarray(cols, dtype=np.int64))), shape=shape)


def sparse_kernel_basis(A) -> sp.csc_matrix:
    """Z-basis of ``ker A`` for a sparse integer matrix (see :func:`integer_kernel_basis`)."""
    A = sp.csc_matrix(A)
    m, n = A.shape
    if A.dtype.kind in "iu":
        G = A.astype(np.int64)
        G.eliminate_zeros()
        G.sort_indices()
        K = graph_kernel(G)
        if K is not None:
            return K
    red = ChainReduction([None, A], [m, n])
    red.eliminate(1)
    _, core_cols, M = red.residual_core(1)
    start = {}  # reduced kernel: unit vectors of the zero columns, then the kernel of the core
    g, core = 0, set(core_cols.tolist())
    for c in red.alive_index(1).tolist():
        if c not in core:
            start[c] = {g: 1}
            g += 1
    if M.size:
        Kd = dense_kernel_basis(M)
        for t, c in enumerate(core_cols.tolist()):
            d = {g + j: int(w) for j, w in enumerate(Kd[t]) if w != 0}
            if d:
                start[c] = d
        g += Kd.shape[1]
    vals = red._backsolve(red.row_steps[1], start)
    rows, cols, data = [], [], []
    for p, d in vals.items():
        for j, w in d.items():
            rows.append(p)
            cols.append(j)
            data.append(w)
    return _int_sparse((rows, cols, data), (n, g))


def sparse_solve_integer(A, B: np.ndarray):
    """Integer solution of ``A X = B`` (object array B, shape (m, p)) or None."""
    m, n = A.shape
    if B.shape[0] != m:
        raise ShapeError(f"b has {B.shape[0]} rows but A has {m}; they must match.")
    red = ChainReduction([None, A], [m, n])
    red.eliminate(1)
    core_rows, core_cols, M = red.residual_core(1)
    zero_rows = np.setdiff1d(red.alive_index(0), core_rows).tolist()
    core_rows = core_rows.tolist()
    X = np.zeros((n, B.shape[1]), dtype=object)
    for q in range(B.shape[1]):
        b = [int(v) for v in B[:, q]]
        for a, u, col, _ in red.col_steps[0]:  # forward elimination on the right-hand side
            f = u * b[a]
            if f:
                for x, vx in col.items():
                    b[x] -= vx * f
        if any(b[i] for i in zero_rows):
            return None
        y = np.zeros((0, 1), dtype=object)
        if M.size:
            y = dense_solve_integer(M, np.array([b[i] for i in core_rows], dtype=object).reshape(-1, 1))
            if y is None:
                return None
        cols = core_cols
        x = {int(c): int(v) for c, v in zip(cols, y[:, 0]) if v}
        for bb, u, row, a in reversed(red.row_steps[1]):
            s = b[a] - sum(v * x[c] for c, v in row.items() if c in x)
            if s:
                x[bb] = u * s
        for c, v in x.items():
            X[c, q] = v
    return to_int_array(X)
