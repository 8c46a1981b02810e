"""An acyclic matching of a chain complex by collapses and coreductions, and its Morse complex (internal).

The reduction that runs before any elimination (:mod:`dhlb.topology._sparse_elim`) or Smith form.
A *pair* ``(a, b)``, ``a ∈ C_{k-1}``, ``b ∈ C_k``, with ``∂_k[a, b]`` a unit, is matched when, among
the cells still unmatched,

* **collapse** (an elementary collapse): ``b`` is the only coface of ``a``;
* **coreduction** (Mrozek–Batko): ``a`` is the only face of ``b`` that is not critical.

When neither exists, the lowest-degree cell whose faces are all matched or critical is made
*critical* (one vertex per component first: the coreductions from it are a breadth-first spanning
forest, which is computed vectorized when ``∂_1`` is an incidence matrix).  The decisions read only
counts of the original matrices, so matching costs ``O(nnz)``.  Cells left unmatched (critical,
or stuck where no pair is a unit) span the *Morse complex*, whose differential is the Schur
complement ``∂'_k = D − C A⁻¹ B`` of the matched block ``A = ∂_k[rows matched up, columns matched
down]``.  The rules make ``A`` triangular (a coreduction column has no later matched row; a collapse
row no later matched column), so:

* ``ι`` (Morse chains -> chains, lifting cycles): ``x_b = −u Σ_{c ≠ b} ∂[a, c] x_c`` over the
  coreduction pairs of ``∂_k`` in reverse order (a collapse contributes 0);
* ``π^T`` (Morse cochains -> cochains, lifting cocycles): ``φ_a = −u Σ_{x ≠ a} ∂[x, b] φ_x`` over
  the coreductions of ``∂_{k+1}`` in order, then its collapses in reverse order;
* ``∂'_k = (∂_k ι)`` restricted to the critical rows, or ``(π^T)ᵀ ∂_k`` restricted to the
  critical columns, whichever side has fewer cells.

``⟨π^T φ, ι z⟩ = ⟨φ, z⟩``: homology, torsion, generators and cocycles all pass through.  Over
``Z/p`` every nonzero entry is a unit and arithmetic is modulo ``p``.
"""

from __future__ import annotations

from array import array
from collections import deque

import numpy as np
import scipy.sparse as sp

from dhlb.topology._sparse_elim import substitute
from dhlb.topology.graph import incidence, incidence_forest

__all__ = ["MorseMatching"]

COLLAPSE, COREDUCTION = 0, 1


class MorseMatching:
    """The matching of ``C_n -> ... -> C_0`` and the maps to and from its Morse complex.

    Parameters
    ----------
    mats : list of sparse int64 matrices
        ``[∂_0, ..., ∂_n]`` (validated, ``∂_0`` of shape ``(0, n_0)``).
    p : int or None
        ``None`` for integer coefficients (units ±1), else a prime: arithmetic modulo ``p``.
    """

    def __init__(self, mats, p: int | None = None):
        self.p = p
        self.n = n = len(mats) - 1
        self.sizes = [mats[0].shape[1]] + [M.shape[1] for M in mats[1:]]
        self._d1 = mats[1] if n >= 1 else None
        self.csc = [None] + [sp.csc_matrix(mats[k]) for k in range(1, n + 1)]
        self.csr = [None] + [sp.csr_matrix(mats[k]) for k in range(1, n + 1)]
        for k in range(1, n + 1):
            for M in (self.csc[k], self.csr[k]):
                M.sort_indices()
                if p is not None:
                    M.data %= p
                M.eliminate_zeros()
        self._lists = {}
        self.alive = [np.ones(s, dtype=bool) for s in self.sizes]
        # steps[k]: pairs of ∂_k in matching order: (a, b, u, kind)
        self.steps = [[] for _ in self.sizes]
        self._match()
        self.critical = [np.flatnonzero(al) for al in self.alive]

    # ------------------------------------------------------------------ helpers
    def _lines(self, kind: str, k: int):
        """``(indptr, indices, data)`` of ``∂_k`` by rows (``"r"``) or columns (``"c"``) as int64 arrays.

        ``array.array``: Python-speed indexing at 8 bytes an entry; cached until :meth:`release`.
        """
        key = (kind, k)
        if key not in self._lists:
            M = self.csr[k] if kind == "r" else self.csc[k]
            self._lists[key] = tuple(array("q", np.asarray(x, dtype=np.int64).tobytes())
                                     for x in (M.indptr, M.indices, M.data))
        return self._lists[key]

    def _rows(self, k):
        return self._lines("r", k)

    def _cols(self, k):
        return self._lines("c", k)

    def release(self) -> None:
        """Drop the cached lines (the lifts build them again when a basis is asked for)."""
        self._lists.clear()

    def _unit(self, v) -> bool:
        return v % self.p != 0 if self.p is not None else v in (1, -1)

    def _inverse(self, u: int) -> int:
        return u if self.p is None else pow(u, -1, self.p)

    # ------------------------------------------------------------------ the matching
    def _graph_start(self, alive, crit, cnt) -> bool:
        """Coreductions from one root per component through ``∂_1``, vectorized (a BFS forest)."""
        A = sp.csc_matrix(self._d1).astype(np.int64)
        A.sort_indices()
        inc = incidence(A)
        if inc is None:
            return False
        head, tail = inc
        m = A.shape[0]
        order, _pred, tree_col, _sign, root = incidence_forest(head, tail, m)
        tc = tree_col[order]
        verts, edges = order[tc >= 0], tc[tc >= 0]
        vals = np.where(head[edges] == verts, 1, -1)  # ∂[v, e] = +1 at the head
        if self.p is not None:
            vals %= self.p
        self.steps[1] = list(zip(verts.tolist(), edges.tolist(), vals.tolist(), [COREDUCTION] * len(verts)))
        roots = np.unique(root) if m else np.zeros(0, dtype=np.int64)
        a0, c0, a1 = (np.frombuffer(x, dtype=np.uint8) for x in (alive[0], crit[0], alive[1]))
        a0[:] = 0
        a0[roots] = 1
        c0[roots] = 1
        a1[edges] = 0
        cnt[1] = [0] * self.sizes[1]
        if self.n >= 2:
            dead = np.zeros(self.sizes[1], dtype=np.int64)
            dead[edges] = 1
            cnt[2] = (np.asarray(cnt[2], dtype=np.int64) - (abs(self.csc[2]) > 0).T.astype(np.int64) @ dead).tolist()
        return True

    def _match(self) -> None:
        n, sizes = self.n, self.sizes
        alive = [bytearray(b"\x01") * s for s in sizes]
        crit = [bytearray(s) for s in sizes]
        cnt = [None] + [np.diff(self.csc[k].indptr).tolist() for k in range(1, n + 1)]
        rcnt = [None] + [np.diff(self.csr[k].indptr).tolist() for k in range(1, n + 1)]
        graph = n >= 1 and self._graph_start(alive, crit, cnt)
        zeros = [[] if graph else list(range(sizes[0]))[::-1]]  # cells that may become critical
        Q = deque()  # coreduction candidates (k, column b)
        L = []  # collapse candidates (k, row a)
        for k in range(1, n + 1):
            al = np.frombuffer(alive[k], dtype=np.uint8).astype(bool)
            cn = np.asarray(cnt[k])
            zeros.append(np.flatnonzero(al & (cn == 0)).tolist()[::-1])
            Q.extend((k, b) for b in np.flatnonzero(al & (cn == 1)).tolist())
            below = np.frombuffer(alive[k - 1], dtype=np.uint8).astype(bool)
            L.extend((k, a) for a in np.flatnonzero(below & (np.asarray(rcnt[k]) == 1)).tolist())
        rows = [None] + [self._rows(k) for k in range(1, n + 1)]
        cols = [None] + [self._cols(k) for k in range(1, n + 1)]
        unit = self._unit
        steps = self.steps

        def kill(j, c):
            if j >= 1:
                al, rc = alive[j - 1], rcnt[j]
                cp, ci, _ = cols[j]
                for t in range(cp[c], cp[c + 1]):
                    x = ci[t]
                    if al[x]:
                        rc[x] -= 1
                        if rc[x] == 1:
                            L.append((j, x))
            if j < n:
                al, cn = alive[j + 1], cnt[j + 1]
                rp, ri, _ = rows[j + 1]
                for t in range(rp[c], rp[c + 1]):
                    e = ri[t]
                    if al[e]:
                        cn[e] -= 1
                        Q.append((j + 1, e))

        while True:
            while L or Q:
                if L:
                    k, a = L.pop()
                    if not alive[k - 1][a] or crit[k - 1][a] or rcnt[k][a] != 1:
                        continue
                    al, cr = alive[k], crit[k]
                    rp, ri, rv = rows[k]
                    for t in range(rp[a], rp[a + 1]):
                        b = ri[t]
                        if al[b]:
                            break
                    u = rv[t]
                    if cr[b] or not unit(u):
                        continue
                    kind = COLLAPSE
                else:
                    k, b = Q.popleft()
                    if not alive[k][b] or crit[k][b]:
                        continue
                    c = cnt[k][b]
                    if c != 1:
                        if c == 0:
                            zeros[k].append(b)
                        continue
                    alr, crr = alive[k - 1], crit[k - 1]
                    cp, ci, cv = cols[k]
                    for t in range(cp[b], cp[b + 1]):
                        a = ci[t]
                        if alr[a] and not crr[a]:
                            break
                    u = cv[t]
                    if not unit(u):
                        continue
                    kind = COREDUCTION
                alive[k - 1][a] = 0
                alive[k][b] = 0
                steps[k].append((a, b, u, kind))
                kill(k - 1, a)
                kill(k, b)
            found = None
            for k in range(n + 1):
                z = zeros[k]
                while z:
                    c = z.pop()
                    if alive[k][c] and not crit[k][c] and (k == 0 or cnt[k][c] == 0):
                        found = k
                        break
                if found is not None:
                    break
            if found is None:
                break
            k = found
            crit[k][c] = 1
            if k < n:
                al, cn = alive[k + 1], cnt[k + 1]
                rp, ri, _ = rows[k + 1]
                for t in range(rp[c], rp[c + 1]):
                    e = ri[t]
                    if al[e]:
                        cn[e] -= 1
                        Q.append((k + 1, e))
        self.alive = [np.frombuffer(bytes(al), dtype=np.uint8).astype(bool) for al in alive]

    # ------------------------------------------------------------------ lifting
    def _solve(self, lines, order, vals: dict) -> dict:
        """``vals[target] = −u⁻¹ Σ_{c ≠ target} line[c] vals[c]`` over ``order`` (sparse dicts of generators)."""
        ptr, ind, dat = lines
        for target, other, u in order:
            z = substitute(((dat[t], zc) for t in range(ptr[other], ptr[other + 1])
                            if ind[t] != target and (zc := vals.get(ind[t]))), self._inverse(u), self.p)
            if z:
                vals[target] = z
        return vals

    def lift_chains(self, k: int, start: dict) -> dict:
        """``ι``: a Morse k-chain ``{critical cell: {g: value}}`` -> the k-chain on all of ``C_k`` (same form)."""
        if k == 0 or not self.steps[k]:
            return dict(start)
        order = [(b, a, u) for a, b, u, kind in reversed(self.steps[k]) if kind == COREDUCTION]
        return self._solve(self._rows(k), order, dict(start))

    def lift_cochains(self, k: int, start: dict) -> dict:
        """``π^T``: a Morse k-cochain ``{critical cell: {g: value}}`` -> the cochain on all of ``C_k``."""
        if k == self.n or not self.steps[k + 1]:
            return dict(start)
        st = self.steps[k + 1]
        order = [(a, b, u) for a, b, u, kind in st if kind == COREDUCTION]
        order += [(a, b, u) for a, b, u, kind in reversed(st) if kind == COLLAPSE]
        return self._solve(self._cols(k + 1), order, dict(start))

    def residual(self, k: int) -> tuple[dict, dict]:
        """``∂'_k`` on the critical cells as row and column dicts ``{i: {j: v}}`` (positions in ``critical``)."""
        rows_c, cols_c = self.critical[k - 1], self.critical[k]
        R: dict = {}
        C: dict = {}
        if not len(rows_c) or not len(cols_c):
            return R, C
        rpos = {int(r): i for i, r in enumerate(rows_c)}
        cpos = {int(c): j for j, c in enumerate(cols_c)}
        p = self.p
        if len(cols_c) <= len(rows_c):  # lift the critical columns, apply ∂_k, keep the critical rows
            chains = self.lift_chains(k, {int(c): {j: 1} for j, c in enumerate(cols_c.tolist())})
            rp, ri, rv = self._rows(k)
            for r, i in rpos.items():
                acc: dict = {}
                for t in range(rp[r], rp[r + 1]):
                    z = chains.get(ri[t])
                    if z:
                        v = rv[t]
                        for j, w in z.items():
                            acc[j] = acc.get(j, 0) + v * w
                line = {j: (w % p if p is not None else w) for j, w in acc.items()}
                line = {j: w for j, w in line.items() if w}
                if line:
                    R[i] = line
        else:  # lift the critical rows as cochains, apply δ, keep the critical columns
            cochains = self.lift_cochains(k - 1, {int(r): {i: 1} for i, r in enumerate(rows_c.tolist())})
            cp, ci, cv = self._cols(k)
            for c, j in cpos.items():
                for t in range(cp[c], cp[c + 1]):
                    z = cochains.get(ci[t])
                    if z:
                        v = cv[t]
                        for i, w in z.items():
                            row = R.setdefault(i, {})
                            row[j] = row.get(j, 0) + v * w
            for i in list(R):
                line = {j: (w % p if p is not None else w) for j, w in R[i].items()}
                line = {j: w for j, w in line.items() if w}
                if line:
                    R[i] = line
                else:
                    del R[i]
        for i, line in R.items():
            for j, v in line.items():
                C.setdefault(j, {})[i] = v
        return R, C
