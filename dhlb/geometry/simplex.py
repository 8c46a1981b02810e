"""Metric quantities of Euclidean simplices, vectorized over stacks of simplices.

A stack of ``m`` n-simplices is given either by vertex positions ``P`` of shape
``(m, n+1, d)`` (any ambient dimension ``d >= n``) or by squared edge lengths ``L2`` of shape
``(m, n+1, n+1)``.  Everything is expressed in the edge basis ``e_a = p_a - p_0``
(``a = 1..n``) of the simplex: the **metric** (Gram matrix of edge vectors) is

    g_ab = <e_a, e_b> = (L2[0, a] + L2[0, b] - L2[a, b]) / 2,

the polarization identity ``<x, y> = (|x|^2 + |y|^2 - |x - y|^2)/2`` applied to
``x = e_a``, ``y = e_b``, ``x - y = p_a - p_b`` (this is the seed's Eq. 11.1 with ``f = l^2``;
on the diagonal it reads ``g_aa = L2[0, a]``).

The barycentric coordinates ``λ_1..λ_n`` are dual to the edge basis (``dλ_a(e_b) = δ_ab``) and
``λ_0 = 1 - Σ λ_a``, hence ``<∇λ_a, ∇λ_b> = (g⁻¹)_ab`` and the full ``(n+1) x (n+1)`` Gram matrix
of barycentric gradients is ``G = Dᵀ g⁻¹ D`` with ``D = [-1 | I_n]``; its rows sum to zero.
It is computed as ``G = YᵀY`` with ``Y = R⁻ᵀ D`` for a triangular factor ``g = RᵀR`` (QR of the
edge matrix in the point route, Cholesky in the length route) -- never an explicit inverse.
``Y``'s columns are the gradients ``∇λ_i`` in an orthonormal frame of the simplex.

The P1 stiffness (the seed's Theorem 16, "cotangent formula") is ``c_ij = ∫_σ <dλ_i, dλ_j> =
vol(σ) G_ij``: for ``i ≠ j`` it equals ``-cot(α_ij) vol(σ∖{i,j}) / (n(n-1))`` with ``α_ij`` the
dihedral angle between the facets opposite ``i`` and ``j``; ``c_ii = vol(σ∖{i}) / (n h_i)``.
"""

from __future__ import annotations

from functools import cached_property
from itertools import combinations
from math import factorial
from typing import TYPE_CHECKING

import numpy as np

from dhlb.errors import DegenerateSimplexError, InvalidMetricError, NonFiniteError, ShapeError
from dhlb.geometry._small import (
    cholesky_3,
    eigvalsh_small,
    factor_from_edges,
    gradient_gram_2,
    gradients_from_factor,
    gram_of_columns,
    soa_empty,
    surely_definite_3,
)

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["SimplexStack", "metric_from_squared_lengths", "squared_lengths_from_points", "default_rtol"]

OK, DEGENERATE, INDEFINITE = 0, 1, 2


def default_rtol(n: int) -> float:
    """Default relative threshold ``100 n eps`` below which ``λ_min(g)/λ_max(g)`` counts as zero."""
    return 100.0 * max(n, 1) * np.finfo(float).eps


def squared_lengths_from_points(points: ArrayLike) -> np.ndarray:
    """Squared edge lengths ``(m, n+1, n+1)`` of simplices given by points ``(m, n+1, d)``.

    Parameters
    ----------
    points : (m, n+1, d) float array
        The vertex positions of ``m`` n-simplices in ``R^d``.

    Returns
    -------
    L2 : (m, n+1, n+1) float array
        ``L2[s, a, b] = |p_a - p_b|²`` for the vertices ``p_a, p_b`` of simplex ``s`` (symmetric, zero diagonal).

    Examples
    --------
    >>> squared_lengths_from_points([[[0, 0], [3, 0], [0, 4]]])[0]
    array([[ 0.,  9., 16.],
           [ 9.,  0., 25.],
           [16., 25.,  0.]])
    """
    P = np.asarray(points, dtype=float)
    diff = P[:, :, None, :] - P[:, None, :, :]
    return np.einsum("mabk,mabk->mab", diff, diff)


def metric_from_squared_lengths(sq_lengths: ArrayLike) -> np.ndarray:
    """Metric ``g`` ``(m, n, n)`` in the edge basis from squared lengths ``(m, n+1, n+1)``.

    ``g_ab = (L2[0,a] + L2[0,b] - L2[a,b]) / 2`` (polarization identity; see module docstring).

    Parameters
    ----------
    sq_lengths : (m, n+1, n+1) float array
        Squared edge lengths of ``m`` n-simplices, ``sq_lengths[s, a, b] = |p_a - p_b|²``. Not checked
        (use :meth:`SimplexStack.from_squared_lengths` for checked input).

    Returns
    -------
    g : (m, n, n) float array
        The symmetric metric in the edge basis ``e_a = p_a - p_0`` (``a = 1..n``) of each simplex.

    Examples
    --------
    >>> metric_from_squared_lengths([[[0, 1, 1], [1, 0, 2], [1, 2, 0]]])[0]
    array([[1., 0.],
           [0., 1.]])
    """
    L2 = np.asarray(sq_lengths, dtype=float)
    m, n = L2.shape[0], L2.shape[1] - 1
    g = soa_empty(m, n, n)
    for a in range(n):
        for b in range(a, n):
            g[:, a, b] = g[:, b, a] = 0.5 * (L2[:, 0, a + 1] + L2[:, 0, b + 1] - L2[:, a + 1, b + 1])
    return g


def _check_finite(arr: np.ndarray, what: str) -> None:
    bad = ~np.isfinite(arr)
    if np.any(bad):
        idx = tuple(int(i) for i in np.argwhere(bad)[0])
        raise NonFiniteError(f"{what} contains a non-finite value (NaN or inf) at index {idx}; "
                             "replace it by a finite number")


class SimplexStack:
    """Metric quantities of a stack of ``m`` Euclidean n-simplices (all cached, all vectorized).

    Build it with :meth:`from_points` or :meth:`from_squared_lengths`.  Quantities that need a
    positive-definite metric are ``nan`` on simplices that are not (see :attr:`status`, or call
    :meth:`check`, which raises).

    Parameters
    ----------
    metric : (m, n, n) float array
        The symmetric metric ``g`` of each simplex in its edge basis ``e_a = p_a - p_0``.
    factor : (m, n, n) float array, optional
        An upper-triangular ``R`` with ``g = RᵀR`` (e.g. from a QR of the edge vectors); computed when needed
        if not given.
    sq_lengths : (m, n+1, n+1) float array, optional
        The squared edge lengths, if known (else computed from ``points``).
    points : (m, n+1, d) float array, optional
        The vertex positions, if known.
    rtol : float, optional
        Relative threshold below which ``λ_min(g)/λ_max(g)`` counts as zero (degenerate); default
        ``100 n eps``.

    Examples
    --------
    >>> S = SimplexStack.from_points([[[0, 0], [1, 0], [0, 1]]])
    >>> S.n, S.volumes.tolist()
    (2, [0.5])
    >>> S.cotan_weights[0]
    array([[ 1. , -0.5, -0.5],
           [-0.5,  0.5,  0. ],
           [-0.5,  0. ,  0.5]])
    >>> np.degrees(S.dihedral_angles[0, 1, 2]).round(6)   # angle at vertex 0
    np.float64(90.0)
    """

    def __init__(self, metric: np.ndarray, factor: np.ndarray | None = None, sq_lengths: np.ndarray | None = None,
                 points: np.ndarray | None = None, rtol: float | None = None):
        self._g = metric
        self._factor_given = factor
        self._L2_given = sq_lengths
        self._points = points
        self.n = metric.shape[1]
        self.m = metric.shape[0]
        self.rtol = default_rtol(self.n) if rtol is None else float(rtol)
        self._cross = self._det = None

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_points(cls, points: ArrayLike, *, rtol: float | None = None) -> SimplexStack:
        """Stack from vertex positions ``(m, n+1, d)``, ``d >= n``; uses a QR factor of the edges."""
        P = np.asarray(points, dtype=float)
        if P.ndim != 3 or P.shape[1] < 1:
            raise ShapeError(f"points of a simplex stack must have shape (m, n+1, d), got {P.shape}")
        _check_finite(P, "the simplex points")
        m, n1, d = P.shape
        n = n1 - 1
        if d < n:
            raise ShapeError(f"{n}-simplices need an ambient dimension d >= {n}, got d = {d}")
        E = np.swapaxes(P[:, 1:, :] - P[:, :1, :], 1, 2)  # (m, d, n): columns are edge vectors
        if 1 <= n <= 2:  # closed forms (dhlb.geometry._small)
            R, g = factor_from_edges(E)
            return cls(g, factor=R, points=P, rtol=rtol)
        if n == 3:  # closed-form Cholesky factor of g, lazily (dhlb.geometry._small)
            cols = [np.ascontiguousarray(E[:, :, a]) for a in range(3)]
            g = soa_empty(m, 3, 3)
            for a, b in ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)):
                g[:, a, b] = g[:, b, a] = np.einsum("md,md->m", cols[a], cols[b])
            S = cls(g, points=P, rtol=rtol)
            if d == 3:  # in R³: ∇λ_a = (e_b × e_c) / det E (cyclic), accurate to eps·cond(E), not cond²
                S._cross = [np.cross(cols[(a + 1) % 3], cols[(a + 2) % 3]) for a in range(3)]
                S._det = np.einsum("md,md->m", cols[0], S._cross[0])
            return S
        R = np.linalg.qr(E, mode="r") if n > 0 else np.zeros((m, 0, 0))
        R = R[:, :n, :n]
        g = np.swapaxes(E, 1, 2) @ E
        g = 0.5 * (g + np.swapaxes(g, 1, 2))
        return cls(g, factor=R, points=P, rtol=rtol)

    @classmethod
    def from_squared_lengths(cls, sq_lengths: ArrayLike, *, rtol: float | None = None) -> SimplexStack:
        """Stack from squared edge lengths ``(m, n+1, n+1)`` (symmetric, zero diagonal, > 0 off it)."""
        L2 = np.asarray(sq_lengths, dtype=float)
        if L2.ndim != 3 or L2.shape[1] != L2.shape[2] or L2.shape[1] < 1:
            raise ShapeError(f"squared lengths must have shape (m, n+1, n+1), got {L2.shape}")
        _check_finite(L2, "the squared edge lengths")
        if not np.array_equal(L2, np.swapaxes(L2, 1, 2)):
            raise InvalidMetricError("the squared-length matrices must be symmetric")
        if np.any(np.diagonal(L2, axis1=1, axis2=2) != 0):
            raise InvalidMetricError("the squared-length matrices must have a zero diagonal")
        off = ~np.eye(L2.shape[1], dtype=bool)
        if np.any(L2[:, off] <= 0):
            s, a, b = (int(v) for v in np.argwhere((L2 <= 0) & off)[0])
            raise InvalidMetricError(f"simplex {s}: the edge ({a}, {b}) has non-positive length; "
                                     "edge lengths must be > 0")
        return cls._from_checked_lengths(L2, rtol)

    @classmethod
    def _from_checked_lengths(cls, L2: np.ndarray, rtol: float | None) -> SimplexStack:
        """:meth:`from_squared_lengths` for data validated by the caller (``EuclideanComplex``)."""
        return cls(metric_from_squared_lengths(L2), sq_lengths=L2, rtol=rtol)

    # ------------------------------------------------------------------ definiteness
    @cached_property
    def squared_lengths(self) -> np.ndarray:
        """Squared edge lengths ``(m, n+1, n+1)``."""
        return self._L2_given if self._L2_given is not None else squared_lengths_from_points(self._points)

    @cached_property
    def metric(self) -> np.ndarray:
        """Metric ``g`` in the edge basis ``p_a - p_0``, shape ``(m, n, n)``."""
        return self._g

    @cached_property
    def metric_eigenvalues(self) -> np.ndarray:
        """Eigenvalues of ``g`` ascending, shape ``(m, n)`` (absolute accuracy ``~ eps λ_max``)."""
        if self.n == 0:
            return np.zeros((self.m, 0))
        if self.n <= 2:
            if self._factor_given is not None:  # √det = Π diag R: no squaring (edges of 1e±150 stay finite)
                return eigvalsh_small(self._g, sqrt_det=np.prod(np.diagonal(self._factor_given, axis1=1, axis2=2),
                                                                axis=1))
            return eigvalsh_small(self._g)
        return np.linalg.eigvalsh(self._g)

    @cached_property
    def _cholesky_3(self) -> np.ndarray:
        """Closed-form Cholesky factor of every metric (n = 3), ``nan`` where a pivot fails."""
        return cholesky_3(self._g)

    def _classify(self, ev: np.ndarray) -> np.ndarray:
        scale = np.maximum(np.abs(ev).max(axis=1), np.finfo(float).tiny)
        lo = ev[:, 0] / scale
        return np.where(lo > self.rtol, OK, np.where(lo >= -self.rtol, DEGENERATE, INDEFINITE)).astype(np.int64)

    @cached_property
    def status(self) -> np.ndarray:
        """Per simplex: 0 positive definite, 1 degenerate (zero volume), 2 indefinite (not realizable)."""
        if self.n == 0:
            return np.zeros(self.m, np.int64)
        if self.n == 3 and "metric_eigenvalues" not in self.__dict__:
            # certified simplices need no eigenvalues; the others get the exact test
            doubt = np.nonzero(~surely_definite_3(self._g, self._cholesky_3, self.rtol))[0]
            out = np.zeros(self.m, np.int64)
            if doubt.size:
                out[doubt] = self._classify(np.linalg.eigvalsh(self._g[doubt]))
            return out
        return self._classify(self.metric_eigenvalues)

    @cached_property
    def positive_definite(self) -> np.ndarray:
        """Boolean mask of simplices whose metric is positive definite (beyond ``rtol``)."""
        return self.status == OK

    @cached_property
    def condition_numbers(self) -> np.ndarray:
        """``λ_max(g) / λ_min(g)`` per simplex (``inf`` if not positive definite)."""
        ev = self.metric_eigenvalues
        if self.n == 0:
            return np.ones(self.m)
        out = np.full(self.m, np.inf)
        ok = self.positive_definite
        out[ok] = ev[ok, -1] / ev[ok, 0]
        return out

    def triangle_violations(self) -> list[tuple[int, tuple[int, int, int]]]:
        """``(simplex, (a, b, c))`` for local 2-faces whose side lengths violate the triangle inequality.

        ``c`` is the vertex opposite the edge that is longer than the sum of the other two.
        """
        out = []
        L = np.sqrt(np.maximum(self.squared_lengths, 0))
        for a, b, c in combinations(range(self.n + 1), 3):
            for (x, y), z in (((a, b), c), ((a, c), b), ((b, c), a)):
                slack = L[:, x, z] + L[:, y, z] - L[:, x, y]
                tol = self.rtol * (L[:, x, z] + L[:, y, z])
                for s in np.nonzero(slack < -tol)[0]:
                    out.append((int(s), (x, y, z)))
        return sorted(out)

    def check(self, labels: ArrayLike | None = None, what: str = "simplex") -> None:
        """Raise if some metric is not positive definite, listing the offenders and why.

        Parameters
        ----------
        labels : (m, n+1) array, optional
            Vertex labels to print for each simplex (default: local vertex numbers).
        what : str
            Noun used in the message.

        Raises
        ------
        InvalidMetricError
            Some metric is indefinite (the lengths violate a triangle inequality or, in higher
            dimension, are not realizable by a Euclidean simplex).
        DegenerateSimplexError
            Otherwise, if some simplex has (numerically) zero volume.
        """
        st = self.status
        if np.all(st == OK):
            return
        lab = np.broadcast_to(np.arange(self.n + 1), (self.m, self.n + 1)) if labels is None else np.asarray(labels)

        def name(s):
            return f"{what} {tuple(int(v) for v in lab[s])}"

        bad_idx = np.nonzero(st == INDEFINITE)[0]
        if bad_idx.size:
            viol = {}
            for s, (x, y, z) in self.triangle_violations():
                viol.setdefault(s, (x, y, z))
            lines = []
            for s in bad_idx[:10]:
                if s in viol:
                    x, y, z = viol[s]
                    L = np.sqrt(self.squared_lengths[s])
                    lines.append(f"{name(s)}: triangle inequality fails on the face "
                                 f"{tuple(int(lab[s][v]) for v in sorted((x, y, z)))}: "
                                 f"|{int(lab[s][x])}{int(lab[s][y])}| = {L[x, y]:.6g} > "
                                 f"{L[x, z]:.6g} + {L[y, z]:.6g}")
                else:
                    lines.append(f"{name(s)}: the edge lengths are not realizable by a Euclidean "
                                 f"simplex (metric form indefinite, smallest eigenvalue "
                                 f"{self.metric_eigenvalues[s, 0]:.3g})")
            more = f" (and {bad_idx.size - 10} more)" if bad_idx.size > 10 else ""
            raise InvalidMetricError(f"{bad_idx.size} {what}(s) have no positive-definite metric{more}:\n  "
                                     + "\n  ".join(lines) + "\nfix the edge lengths of these simplices")
        deg = np.nonzero(st == DEGENERATE)[0]
        lines = [f"{name(s)}: zero volume (λ_min/λ_max of its metric = "
                 f"{self.metric_eigenvalues[s, 0] / self.metric_eigenvalues[s, -1]:.3g} <= rtol = {self.rtol:.3g})"
                 for s in deg[:10]]
        more = f" (and {deg.size - 10} more)" if deg.size > 10 else ""
        raise DegenerateSimplexError(f"{deg.size} degenerate {what}(s){more}:\n  " + "\n  ".join(lines)
                                     + "\nremove or repair these simplices (collinear/coplanar vertices)")

    # ------------------------------------------------------------------ derived quantities
    @cached_property
    def factor(self) -> np.ndarray:
        """Upper-triangular ``R`` with ``g = RᵀR`` (``nan`` where ``g`` is not positive definite)."""
        n = self.n
        if self._factor_given is not None:
            ok = self.positive_definite
            if ok.all():   # nothing to blank out: the given factor, read-only (no copy)
                R = self._factor_given.view()
                R.setflags(write=False)
                return R
            R = self._factor_given.copy()
            R[~ok] = np.nan
            return R
        if n == 3:
            R = self._cholesky_3.copy()
            R[~self.positive_definite] = np.nan
            return R
        R = np.full((self.m, n, n), np.nan)
        ok = self.positive_definite
        if np.any(ok) and n > 0:
            R[ok] = np.swapaxes(np.linalg.cholesky(self._g[ok]), 1, 2)
        elif n == 0:
            R = np.zeros((self.m, 0, 0))
        return R

    @cached_property
    def volumes(self) -> np.ndarray:
        """n-volume ``sqrt(det g) / n!`` per simplex (0 if degenerate, ``nan`` if indefinite)."""
        if self.n == 0:
            return np.ones(self.m)
        if self.n == 3:
            if self._det is not None:
                vol = np.abs(self._det) / 6.0
            else:
                R = self.factor
                vol = np.abs(R[:, 0, 0] * R[:, 1, 1] * R[:, 2, 2]) / 6.0
            vol[self.status == DEGENERATE] = 0.0
            return vol
        vol = np.abs(np.prod(np.diagonal(self.factor, axis1=1, axis2=2), axis=1)) / factorial(self.n)
        vol[self.status == DEGENERATE] = 0.0
        return vol

    @cached_property
    def barycentric_gradients(self) -> np.ndarray:
        """``Y`` ``(m, n, n+1)``: column ``i`` is ``∇λ_i`` in an orthonormal frame (``Y = R⁻ᵀ[-1 | I]``)."""
        m, n = self.m, self.n
        if n == 0:
            return np.zeros((m, 0, 1))
        ok = self.positive_definite
        if self._cross is not None:
            Y = soa_empty(m, 3, 4)
            with np.errstate(invalid="ignore", divide="ignore"):
                inv = np.where(ok, 1.0 / self._det, np.nan)
            for k in range(3):
                for a in range(3):
                    Y[:, k, a + 1] = self._cross[a][:, k] * inv
                Y[:, k, 0] = -(Y[:, k, 1] + Y[:, k, 2] + Y[:, k, 3])
            return Y
        if n <= 3:
            if ok.all():
                return gradients_from_factor(self.factor)
            Y = np.full((m, n, n + 1), np.nan)
            Y[ok] = gradients_from_factor(self.factor[ok])
            return Y
        Z = np.full((m, n, n), np.nan)
        if np.any(ok):
            Rt = np.swapaxes(self.factor[ok], 1, 2)
            Z[ok] = np.linalg.solve(Rt, np.broadcast_to(np.eye(n), Rt.shape))
        return np.concatenate([-Z.sum(axis=2, keepdims=True), Z], axis=2)

    @cached_property
    def barycentric_gradient_gram(self) -> np.ndarray:
        """``G_ij = <∇λ_i, ∇λ_j>`` ``(m, n+1, n+1)``, symmetric positive semidefinite, rows sum to 0."""
        if self.n == 2 and "barycentric_gradients" not in self.__dict__ and self.positive_definite.all():
            return gradient_gram_2(self.factor)  # the same numbers, without the stack Y
        Y = self.barycentric_gradients
        if 1 <= self.n <= 3:  # symmetric by construction
            return gram_of_columns(Y)
        G = np.swapaxes(Y, 1, 2) @ Y
        return 0.5 * (G + np.swapaxes(G, 1, 2))

    @cached_property
    def cotan_weights(self) -> np.ndarray:
        """``c_ij = ∫_σ <dλ_i, dλ_j> = vol · G_ij`` ``(m, n+1, n+1)``: the local P1 stiffness (Theorem 16)."""
        return self.volumes[:, None, None] * self.barycentric_gradient_gram

    @cached_property
    def heights(self) -> np.ndarray:
        """``h_i`` ``(m, n+1)``: distance from vertex ``i`` to the opposite facet (``1/|∇λ_i|``)."""
        return 1.0 / np.linalg.norm(self.barycentric_gradients, axis=1)

    @cached_property
    def dihedral_angles(self) -> np.ndarray:
        """``α_ij`` ``(m, n+1, n+1)``: interior angle between the facets opposite ``i`` and ``j`` (0 on the diagonal).

        ``α_ij = π - ∠(∇λ_i, ∇λ_j)``, the angle between vectors computed stably as
        ``2 atan2(|u - v|, |u + v|)`` for the unit vectors ``u, v``.  For ``n = 2`` it is the
        angle at the third vertex, for ``n = 1`` it is 0.
        """
        Y = self.barycentric_gradients
        U = Y / np.linalg.norm(Y, axis=1, keepdims=True)
        diff = np.linalg.norm(U[:, :, :, None] - U[:, :, None, :], axis=1)
        summ = np.linalg.norm(U[:, :, :, None] + U[:, :, None, :], axis=1)
        alpha = np.pi - 2.0 * np.arctan2(diff, summ)
        idx = np.arange(self.n + 1)
        alpha[:, idx, idx] = 0.0
        return alpha
