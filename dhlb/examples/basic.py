"""Simplices, spheres, and the cone / suspension / join constructions."""

from __future__ import annotations

from itertools import combinations
from typing import TYPE_CHECKING

import numpy as np

from dhlb._coerce import check_int
from dhlb.examples._util import as_complex, from_blocks
from dhlb.topology.complex import SimplicialComplex

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["simplex", "ball", "sphere", "join", "cone", "suspension"]


def simplex(n: int, return_points: bool = False) -> SimplicialComplex | tuple[SimplicialComplex, np.ndarray]:
    """The full n-simplex ``(0, 1, ..., n)`` with all its faces: a triangulated n-ball.

    Parameters
    ----------
    n : int, >= 0
    return_points : bool
        Also return coordinates: vertex 0 at the origin, vertex ``i`` at ``e_i`` in ``R^n``.

    Returns
    -------
    X : SimplicialComplex
        ``binom(n + 1, k + 1)`` k-simplices; vertices ``0 .. n``.
    points : (n + 1, n) float64, only if ``return_points``

    Examples
    --------
    >>> from dhlb.examples import simplex
    >>> simplex(3).counts
    (4, 6, 4, 1)
    >>> simplex(2, return_points=True)[1].tolist()
    [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]
    """
    n = check_int(n, "n", 0)
    X = SimplicialComplex(np.arange(n + 1, dtype=np.int64)[None, :])
    if return_points:
        return X, np.vstack([np.zeros((1, n)), np.eye(n)])
    return X


def ball(n: int, return_points: bool = False) -> SimplicialComplex | tuple[SimplicialComplex, np.ndarray]:
    """The n-ball as a single n-simplex; the same as :func:`simplex`.

    Parameters
    ----------
    n : int, >= 0
    return_points : bool
        Also return coordinates: vertex 0 at the origin, vertex ``i`` at ``e_i`` in ``R^n``.

    Returns
    -------
    X : SimplicialComplex
        The full n-simplex ``(0, 1, ..., n)`` with all its faces.
    points : (n + 1, n) float64, only if ``return_points``

    Raises
    ------
    InvalidParameterError
        ``n`` is not an integer >= 0.

    Examples
    --------
    >>> from dhlb.examples import ball
    >>> B = ball(2)
    >>> B.counts, B.euler_characteristic
    ((3, 3, 1), 1)
    """
    return simplex(n, return_points=return_points)


def _regular_simplex_on_sphere(n_vertices: int) -> np.ndarray:
    """Vertices of a regular simplex inscribed in the unit sphere of ``R^{n_vertices - 1}``.

    The columns of the Helmert matrix span the hyperplane ``Σ x_i = 0``; row ``i`` of the result
    is the orthogonal projection of ``e_i`` onto it, written in that basis and normalised.
    """
    N = n_vertices
    H = np.zeros((N, N - 1))
    for j in range(1, N):  # column j-1: (1, ..., 1, -j, 0, ..., 0) / sqrt(j (j + 1))
        H[:j, j - 1] = 1.0
        H[j, j - 1] = -float(j)
        H[:, j - 1] /= np.sqrt(j * (j + 1.0))
    return H / np.linalg.norm(H, axis=1, keepdims=True)


def sphere(n: int, return_points: bool = False) -> SimplicialComplex | tuple[SimplicialComplex, np.ndarray]:
    """The n-sphere as the boundary of the (n+1)-simplex ``(0, ..., n+1)``.

    The minimal triangulation of ``S^n``: vertices ``0 .. n+1``, every set of ``n + 1`` of them is a
    top simplex. ``sphere(0)`` is two points, ``sphere(1)`` a triangle's boundary.

    Parameters
    ----------
    n : int, >= 0
    return_points : bool
        Also return coordinates: the vertices of a regular (n+1)-simplex inscribed in the unit
        sphere of ``R^{n+1}``.

    Returns
    -------
    X : SimplicialComplex
        ``binom(n + 2, k + 1)`` k-simplices for ``k <= n``; ``χ = 1 + (-1)^n``.
    points : (n + 2, n + 1) float64, only if ``return_points``

    Examples
    --------
    >>> from dhlb.examples import sphere
    >>> S = sphere(2)
    >>> S.counts, S.euler_characteristic
    ((4, 6, 4), 2)
    >>> import numpy as np
    >>> X, P = sphere(3, return_points=True)
    >>> bool(np.allclose(np.linalg.norm(P, axis=1), 1.0)), P.shape
    (True, (5, 4))
    """
    n = check_int(n, "n", 0)
    rows = np.array(list(combinations(range(n + 2), n + 1)), dtype=np.int64)
    X = SimplicialComplex(rows)
    if return_points:
        return X, _regular_simplex_on_sphere(n + 2)
    return X


def join(X: SimplicialComplex | ArrayLike, Y: SimplicialComplex | ArrayLike) -> SimplicialComplex:
    """The simplicial join ``X * Y``: simplices ``σ ∪ τ`` for ``σ ∈ X``, ``τ ∈ Y`` (either may be empty).

    Parameters
    ----------
    X, Y : SimplicialComplex, or anything :class:`SimplicialComplex` accepts

    Returns
    -------
    SimplicialComplex
        Vertex ``v`` of ``X`` (compact index) is vertex ``v``; vertex ``w`` of ``Y`` is vertex
        ``X.n_vertices + w``. Its dimension is ``X.dim + Y.dim + 1``.

    Examples
    --------
    >>> from dhlb.examples import join, sphere
    >>> J = join(sphere(1), sphere(1))   # S^1 * S^1 = S^3
    >>> J.counts, J.euler_characteristic
    ((6, 15, 18, 9), 0)
    """
    X, Y = as_complex(X, "X"), as_complex(Y, "Y")
    shift = X.n_vertices
    blocks = []
    for A in X.maximal_simplices():
        for B in Y.maximal_simplices():
            if A.shape[0] == 0 or B.shape[0] == 0:
                continue
            a = np.repeat(A, B.shape[0], axis=0)
            b = np.tile(B, (A.shape[0], 1)) + shift
            blocks.append(np.hstack([a, b]))
    return from_blocks(blocks)


def cone(X: SimplicialComplex | ArrayLike) -> SimplicialComplex:
    """The cone over ``X``: every simplex ``σ`` of ``X`` also spans ``σ ∪ {apex}``.

    Parameters
    ----------
    X : SimplicialComplex, or anything :class:`SimplicialComplex` accepts

    Returns
    -------
    SimplicialComplex
        Vertex ``v < N = X.n_vertices`` is vertex ``v`` of ``X`` (compact index); the apex is ``N``.
        Contractible; ``X`` is its subcomplex on the vertices ``0 .. N-1``.

    Examples
    --------
    >>> from dhlb.examples import cone, sphere
    >>> C = cone(sphere(1))      # a disk: triangle fan around vertex 3
    >>> C.simplices(2).tolist()
    [[0, 1, 3], [0, 2, 3], [1, 2, 3]]
    """
    return join(X, [(0,)])


def suspension(X: SimplicialComplex | ArrayLike) -> SimplicialComplex:
    """The (unreduced) suspension of ``X``: two cones over ``X`` glued along ``X``.

    Parameters
    ----------
    X : SimplicialComplex, or anything :class:`SimplicialComplex` accepts

    Returns
    -------
    SimplicialComplex
        Vertex ``v < N = X.n_vertices`` is vertex ``v`` of ``X``; the two apexes are ``N`` and
        ``N + 1``. ``H̃_{k+1}(ΣX) = H̃_k(X)``; the suspension of ``S^n`` is ``S^{n+1}``.

    Examples
    --------
    >>> from dhlb.examples import suspension, sphere
    >>> S = suspension(sphere(1))   # the octahedron-like bipyramid, S^2
    >>> S.counts, S.euler_characteristic
    ((5, 9, 6), 2)
    """
    return join(X, [(0,), (1,)])
