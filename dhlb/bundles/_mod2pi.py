"""Solve ``d₁ω ≡ Ω (mod 2π)`` for a real 1-cochain ω (the constructive half of Theorem 8).

Method (sparse, exact up to rounding, no big linear algebra):

1. *Tet collapses* (only if X has 3-simplices).  For closed Ω the four face equations of a
   tetrahedron are dependent (``Σ ±(dω − Ω) = −dΩ = 0``).  Repeatedly pair a tetrahedron with a
   free face (a triangle in no other remaining tetrahedron) and drop that face's equation; if
   stuck, discard a tetrahedron.  By reverse induction the dropped equations follow from the
   kept ones.
2. *Edge collapses.*  On the kept triangles, repeatedly pair a free edge (in exactly one
   remaining triangle) with its triangle; that triangle's equation will *define* ω on the edge.
   If stuck, defer a triangle (its equation is solved at the end).  Rounds are batched (one free
   edge per triangle per round), so the loop runs over rounds, not simplices.
3. *Core.*  The edges never collapsed form a graph; ω = 0 on a spanning forest of it and a free
   variable ``y_j`` on each of its ``q`` other edges.  Back-substituting the collapse pairs in
   reverse order gives ``ω = a + B y`` with ``B`` integer, and every non-deferred equation holds.
4. *Deferred equations* ``A y ≡ b (mod 2π)`` (A integer, small) are solved with the Smith form
   ``U A V = D``: ``y = V y'`` with ``y'_i = (U b)_i / d_i``; rows beyond the rank need
   ``(U b)_i ∈ 2πZ`` — this is where non-integral Ω would fail.

For a closed surface one triangle per component is deferred and the rest is a tree–cotree
sweep; the cost is ``O(n)`` plus ``O(rounds)`` vectorized steps.
"""

from __future__ import annotations

import numpy as np

from dhlb.forms.groups import wrap_angle
from dhlb.topology.graph import spanning_forest

__all__ = ["solve_mod_2pi"]

_SIGNS = np.array([1, -1, 1], dtype=np.int64)
_BLOCK = 32  # core variables propagated per pass


def _peel(faces: np.ndarray, alive: np.ndarray, n_low: int):
    """Batched collapses of (low face, high simplex) pairs among the ``alive`` high simplices.

    Returns ``(rounds, stuck, low_alive)``: the ``(low, high)`` index arrays of each round, the
    high simplices removed without a partner (in removal order), and a mask of the low faces
    that were never collapsed.
    """
    alive = alive.copy()
    ids = np.nonzero(alive)[0]
    flat = faces[ids].ravel()
    cnt = np.bincount(flat, minlength=n_low).astype(np.int64)
    acc = np.bincount(flat, weights=np.repeat(ids, faces.shape[1]).astype(np.float64), minlength=n_low).astype(np.int64)
    low_alive = np.ones(n_low, bool)
    stamp = np.zeros(n_low, np.int64)
    owner = np.zeros(faces.shape[0], np.int64)
    cand = np.nonzero(cnt == 1)[0]
    rounds, stuck = [], []
    n_alive = ids.size
    scan = 0
    while n_alive:
        cand = cand[(cnt[cand] == 1) & low_alive[cand]]
        if cand.size:  # drop repeated candidates, then keep one free face per high simplex (O(k), no sort)
            pos = np.arange(cand.size)
            stamp[cand] = pos
            cand = cand[stamp[cand] == pos]
            high = acc[cand]
            owner[high] = cand
            keep = owner[high] == cand
            low, high = cand[keep], high[keep]
            low_alive[low] = False
            rounds.append((low, high))
        else:
            while not alive[scan]:
                scan += 1
            high = np.array([scan], np.int64)
            stuck.append(scan)
        alive[high] = False
        n_alive -= high.size
        fl = faces[high].ravel()
        np.subtract.at(cnt, fl, 1)
        np.subtract.at(acc, fl, np.repeat(high, faces.shape[1]))
        cand = fl
    return rounds, np.array(stuck, np.int64), low_alive


class Mod2PiSolution:
    """All ``ω`` with ``d₁ω ≡ Ω (mod 2π)`` up to the free and torsion parameters.

    Attributes
    ----------
    consistent : bool
        False if the deferred system has no solution (Ω not integral).
    defect : float
        Largest violation (mod 2π, in (−π, π]) of a rank-deficient row.
    """

    def __init__(self, X, Omega: np.ndarray):
        self.X = X
        n1, n2 = X.n_simplices(1), X.n_simplices(2)
        f = X.faces(2) if n2 else np.zeros((0, 3), np.int64)
        keep = np.ones(n2, bool)
        if X.dim >= 3 and X.n_simplices(3):
            rounds3, _, _ = _peel(X.faces(3), np.ones(X.n_simplices(3), bool), n2)
            for low, _high in rounds3:
                keep[low] = False
        rounds, deferred, edge_alive = _peel(f, keep, n1) if n2 else ([], np.zeros(0, np.int64), np.ones(n1, bool))
        core = np.nonzero(edge_alive)[0]
        gens = spanning_forest(X, edges=core).nontree
        q = gens.size
        self._f, self._rounds, self._gens, self._Omega = f, rounds, gens, Omega
        fd = f[deferred]
        # ω = a + B y is affine in the core variables y; B is propagated in column blocks so
        # that memory stays O(n_1 · _BLOCK) whatever the genus.
        A = np.zeros((deferred.size, q), np.int64)
        b = np.zeros(deferred.size)
        for j0 in range(0, max(q, 1), _BLOCK):
            cols = np.arange(j0, min(q, j0 + _BLOCK))
            W = np.zeros((n1, 1 + cols.size))
            W[gens[cols], 1 + np.arange(cols.size)] = 1.0
            self._back_substitute(W, with_omega=j0 == 0)
            if j0 == 0:
                b = Omega[deferred] - (W[fd, 0] * _SIGNS).sum(axis=1) if deferred.size else b
            A[:, cols] = np.rint(np.einsum("j,djq->dq", _SIGNS, W[fd, 1:])).astype(np.int64)
        self._solve_deferred(A, b)

    def _back_substitute(self, W: np.ndarray, with_omega: bool) -> None:
        """Undo the collapses in reverse order: each pair's triangle equation defines its edge.

        Column 0 carries the constant part (with Ω, wrapped to (−π, π]); the other columns the
        integer coefficients of the core variables (right-hand side 0).
        """
        f, Om = self._f, self._Omega
        for e, t in reversed(self._rounds):
            ft = f[t]
            k = t.size
            hit = ft == e[:, None]
            s_e = _SIGNS[np.argmax(hit, axis=1)].astype(np.float64)
            oe = ft[~hit].reshape(k, 2)
            os = np.broadcast_to(_SIGNS, (k, 3))[~hit].reshape(k, 2).astype(np.float64)
            vals = -s_e[:, None] * np.einsum("kj,kjc->kc", os, W[oe])
            if with_omega:
                vals[:, 0] = wrap_angle(vals[:, 0] + s_e * Om[t])
            W[e] = vals

    def _solve_deferred(self, A: np.ndarray, b: np.ndarray) -> None:
        m, q = A.shape
        if m == 0 or q == 0 or not np.any(A):
            self._V = np.eye(q, dtype=np.int64)
            self._d = np.zeros(0, np.int64)
            self._c = np.zeros(0)
            resid = wrap_angle(b)
        else:
            from dhlb.topology.intlinalg import smith_normal_form

            U, D, V = smith_normal_form(A)
            U = np.asarray(U, dtype=np.float64)
            diag = np.array([int(D[i, i]) for i in range(min(m, q))], np.int64)
            r = int(np.count_nonzero(diag))
            c = U @ b
            self._V = np.asarray(V, dtype=np.int64)
            self._d = diag[:r]
            self._c = c[:r]
            resid = wrap_angle(c[r:])
        self.defect = float(np.max(np.abs(resid))) if resid.size else 0.0
        self.consistent = self.defect <= 1e-7 * max(1.0, float(np.max(np.abs(b))) if b.size else 1.0)

    @property
    def torsion_orders(self) -> tuple:
        return tuple(int(d) for d in self._d if d > 1)

    def omega(self, free=None, torsion=None) -> np.ndarray:
        """A solution ω (angles in (−π, π]).

        ``free`` sets the ``q − r`` free coordinates, ``torsion`` the branch ``k`` (mod d) of each
        torsion row.
        """
        q = self._V.shape[0]
        r = self._d.size
        y1 = np.zeros(q)
        k = np.zeros(r)
        tors = np.nonzero(self._d > 1)[0]
        if torsion is not None:
            k[tors] = np.asarray(torsion, dtype=np.float64)
        if r:
            y1[:r] = (self._c + 2 * np.pi * k) / self._d
        if free is not None:
            y1[r:] = free
        W = np.zeros((self.X.n_simplices(1), 1))
        W[self._gens, 0] = wrap_angle(self._V @ y1) if q else 0.0
        self._back_substitute(W, with_omega=True)
        return wrap_angle(W[:, 0])


def solve_mod_2pi(X, Omega) -> Mod2PiSolution:
    """Solve ``d₁ω ≡ Ω (mod 2π)``; see the module docstring.  ``Omega`` must be closed.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)])   # a 2-sphere
    >>> Om = np.array([1.0, 2.0, 0.5, -0.5 - 2 * np.pi])    # ∫ over [1, -1, 1, -1] is 2π
    >>> sol = solve_mod_2pi(X, Om)
    >>> sol.consistent, bool(np.allclose(np.exp(1j * (X.coboundary(1) @ sol.omega())), np.exp(1j * Om)))
    (True, True)
    """
    return Mod2PiSolution(X, np.asarray(Omega, dtype=np.float64))
