"""Spaces built as quotients of spheres by free simplicial group actions: lens spaces, RP^n."""

from __future__ import annotations

from math import gcd

import numpy as np

from dhlb._coerce import check_int
from dhlb.errors import InvalidParameterError
from dhlb.examples._util import kuhn_paths, shuffle_paths
from dhlb.topology.complex import SimplicialComplex

__all__ = ["lens_space", "projective_space"]

# Fundamental-domain sizes of the two circles in the lens-space construction: with k = l = 3
# every vertex v of the cover and every deck transformation g != 1 have edge distance
# d(v, g v) >= 3, so the quotient is a simplicial complex (checked in tests/test_examples.py).
_LENS_K, _LENS_L = 3, 3


def _lens_cover(p: int, q: int, k: int = _LENS_K, l: int = _LENS_L, all_cells: bool = False):
    """Top simplices of the Z/p-invariant S^3 (or its quotient) in the lens-space construction.

    Returns ``(cover_rows, quotient_rows)``: ``(m, 4)`` arrays of cover vertex ids and of quotient
    vertex ids of the same tetrahedra. With ``all_cells=False`` only one tetrahedron per orbit.
    Cover vertex ids: ``(x_i, y_j) -> i * b + j``, ``(c_A, y_j) -> a * b + j``,
    ``(x_i, c_B) -> a * b + b + i`` with ``a = p k``, ``b = p l``.
    """
    a, b = p * k, p * l
    n_i = a if all_cells else k
    i = np.arange(n_i, dtype=np.int64)[:, None]
    j = np.arange(b, dtype=np.int64)[None, :]
    i, j = np.broadcast_to(i, (n_i, b)).ravel(), np.broadcast_to(j, (n_i, b)).ravel()
    blocks = []
    # (1) edge (x_i < x_{i+1}) x triangle (c_B < y_j < y_{j+1});  (2) triangle (c_A < x_i < x_{i+1}) x edge
    # Factor coordinates: x-index (-1 = centre c_A), y-index (-1 = centre c_B).
    for sig, tau in (((i, (i + 1) % a), (-np.ones_like(j), j, (j + 1) % b)),
                     ((-np.ones_like(i), i, (i + 1) % a), (j, (j + 1) % b))):
        I, J = shuffle_paths(len(sig) - 1, len(tau) - 1)
        xs = np.stack(sig, axis=1)[:, I]  # (cells, paths, 4)
        ys = np.stack(tau, axis=1)[:, J]
        blocks.append((xs.reshape(-1, 4), ys.reshape(-1, 4)))
    xs = np.concatenate([blk[0] for blk in blocks])
    ys = np.concatenate([blk[1] for blk in blocks])
    cover = np.where(xs < 0, a * b + ys, np.where(ys < 0, a * b + b + xs, xs * b + ys))
    s = np.floor_divide(xs, k)  # the deck transformation g^{-s} moves x_i into 0 <= i < k
    j0 = np.mod(ys - s * q * l, b)
    quot = np.where(xs < 0, k * b + np.mod(ys, l), np.where(ys < 0, k * b + l + np.mod(xs, k), np.mod(xs, k) * b + j0))
    return cover, quot


def lens_space(p: int, q: int = 1) -> SimplicialComplex:
    """A triangulation of the lens space ``L(p, q) = S^3 / (Z/p)``.

    ``Z/p`` acts on ``S^3 ⊂ C^2`` by ``(z_1, z_2) -> (ζ z_1, ζ^q z_2)``, ``ζ = exp(2πi / p)``
    (the convention of Hatcher's *Algebraic Topology*, §2.2). ``L(1, q) = S^3``,
    ``L(2, 1) = RP^3``; the homology is ``Z, Z/p, 0, Z``.

    Triangulation: ``S^3 = ∂(D_A × D_B)`` with ``D_A`` the cone from a centre ``c_A`` over a
    ``3p``-gon ``x_0 .. x_{3p-1}`` and ``D_B`` the cone from ``c_B`` over a ``3p``-gon
    ``y_0 .. y_{3p-1}``, i.e. ``(C_A × D_B) ∪ (D_A × C_B)``, each product cell triangulated by the
    shuffle (staircase) triangulation for the local vertex orders ``c < x_i < x_{i+1}`` and
    ``c < y_j < y_{j+1}`` (indices cyclic). The generator acts by ``x_i -> x_{i+3}``,
    ``y_j -> y_{j+3q}``, freely, simplicially, and moving every vertex at least 3 edges away, so
    the orbit space is a simplicial complex (the join construction ``C_A * C_B`` would not be:
    the quotient of a join has ``p`` edges between the same two vertices).

    Parameters
    ----------
    p : int, >= 1
    q : int, coprime to ``p`` (taken modulo ``p``)

    Returns
    -------
    SimplicialComplex
        ``9p + 6`` vertices and ``54p`` tetrahedra. Vertex numbering (orbit representatives):
        ``i * 3p + j`` for the orbit of ``(x_i, y_j)`` with ``0 <= i < 3``, ``0 <= j < 3p``;
        ``9p + j`` (``0 <= j < 3``) for the orbit of ``(c_A, y_j)``; ``9p + 3 + i``
        (``0 <= i < 3``) for the orbit of ``(x_i, c_B)``.

    Raises
    ------
    InvalidParameterError
        ``p < 1`` or ``gcd(p, q) != 1``.

    Examples
    --------
    >>> from dhlb.examples import lens_space
    >>> L = lens_space(3, 1)
    >>> L.counts, L.euler_characteristic
    ((33, 195, 324, 162), 0)
    """
    p = check_int(p, "p", 1)
    q = check_int(q, "q")
    if gcd(p, q) != 1:
        raise InvalidParameterError(
            f"L(p, q) needs gcd(p, q) = 1, got p = {p}, q = {q} (gcd {gcd(p, q)}); the Z/p action would not be free"
        )
    _, quot = _lens_cover(p, q % p)
    return SimplicialComplex(quot)


def _cross_polytope_flags(n: int):
    """Sign vectors and face vectors of the barycentric flags of ``∂β_{n+1}`` with first sign ``+``.

    Returns ``faces`` of shape ``(2^n (n+1)!, n+1, n+1)``: ``faces[t, r]`` is the ``r``-th face
    (a ``{-1, 0, 1}`` vector with ``r + 1`` non-zeros) of flag ``t``.
    """
    d = n + 1
    signs = np.array(np.meshgrid(*([[1, -1]] * d), indexing="ij"), dtype=np.int64).reshape(d, -1).T
    signs = signs[signs[:, 0] == 1]  # one flag per antipodal pair: the action is sign -> -sign
    masks = kuhn_paths(d)[:, 1:, :]  # (d!, d, d): r-th mask has the first r+1 permuted axes
    return (signs[:, None, None, :] * masks[None]).reshape(-1, d, d)


def projective_space(n: int, return_points: bool = False) -> SimplicialComplex | tuple[SimplicialComplex, np.ndarray]:
    """Real projective space ``RP^n`` as the antipodal quotient of the subdivided cross-polytope.

    The barycentric subdivision of the boundary of the ``(n+1)``-dimensional cross-polytope
    ``β = conv(±e_0, ..., ±e_n)`` has one vertex per non-empty face ``F`` of ``∂β`` — written as a
    vector ``f ∈ {-1, 0, 1}^{n+1}`` (``f_a = ±1`` iff ``±e_a ∈ F``) — and one simplex per flag
    ``F_0 ⊂ F_1 ⊂ ...``. The antipodal map ``f -> -f`` is free and moves every vertex at least 3
    edges away (``F ∩ -F = ∅`` and ``F ∪ -F`` is no face), so the quotient is a simplicial
    complex: the standard triangulation of ``RP^n`` with ``(3^{n+1} - 1) / 2`` vertices and
    ``2^n (n+1)!`` top simplices. ``RP^1`` is the 4-gon; ``RP^3 = L(2, 1)``. For the small
    6-vertex ``RP^2`` see :func:`dhlb.examples.projective_plane`.

    Parameters
    ----------
    n : int, >= 0
    return_points : bool
        Also return, per vertex, the unit vector ``f / |f|`` of its canonical representative
        (the line ``±f`` is the point of ``RP^n``).

    Returns
    -------
    X : SimplicialComplex
        Vertex numbering: the canonical representative of ``±f`` has first non-zero entry ``+1``;
        vertices are numbered in increasing order of ``Σ_a (f_a + 1) 3^{n-a}``.
    points : (N, n+1) float64, only if ``return_points``

    Examples
    --------
    >>> from dhlb.examples import projective_space
    >>> projective_space(2).counts
    (13, 36, 24)
    >>> projective_space(3).euler_characteristic
    0
    """
    n = check_int(n, "n", 0)
    faces = _cross_polytope_flags(n)  # (m, d, d)
    first = np.argmax(faces != 0, axis=2)
    lead = np.take_along_axis(faces, first[:, :, None], axis=2)
    canon = faces * lead  # first non-zero entry +1
    codes = (canon + 1) @ (3 ** np.arange(n, -1, -1, dtype=np.int64))
    X = SimplicialComplex(codes)
    if not return_points:
        return X
    labels = X.vertex_labels
    digits = (labels[:, None] // (3 ** np.arange(n, -1, -1, dtype=np.int64))[None, :]) % 3 - 1
    return X, digits / np.linalg.norm(digits, axis=1, keepdims=True)
