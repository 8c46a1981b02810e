"""The product of two simplicial complexes, triangulated by the shuffle (staircase) construction."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from dhlb.examples._util import as_complex, from_blocks, shuffle_paths

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from dhlb.topology.complex import SimplicialComplex

__all__ = ["product"]


def product(
    X: SimplicialComplex | ArrayLike, Y: SimplicialComplex | ArrayLike, return_pairs: bool = False
) -> SimplicialComplex | tuple[SimplicialComplex, np.ndarray]:
    """The product ``X × Y`` with the shuffle (staircase) triangulation of each cell ``σ × τ``.

    The vertices of ``X`` and of ``Y`` are ordered by their compact indices. For a p-simplex
    ``σ = (x_0 < ... < x_p)`` and a q-simplex ``τ = (y_0 < ... < y_q)`` the prism ``σ × τ`` is
    cut into ``binom(p + q, p)`` simplices of dimension ``p + q``, one per monotone lattice path
    ``(0, 0) = (i_0, j_0), (i_1, j_1), ..., (p, q)`` (each step raises one coordinate by one):
    the simplex with vertices ``(x_{i_r}, y_{j_r})`` (the classical triangulation of a product of
    ordered simplicial complexes; its simplices are the shuffles of Eilenberg–Zilber 1953). Equivalently
    the simplices are the chains of the product order in which both projections are simplices. The
    triangulations of neighbouring prisms agree on common faces, so this is a simplicial complex
    homeomorphic to ``|X| × |Y|``.

    Parameters
    ----------
    X, Y : SimplicialComplex, or anything :class:`SimplicialComplex` accepts
    return_pairs : bool
        Also return the ``(N, 2)`` array of ``(x, y)`` (compact indices) per product vertex.

    Returns
    -------
    P : SimplicialComplex
        Vertex ``x * Y.n_vertices + y`` is the pair ``(x, y)`` of compact indices; the compact
        order of ``P`` is the lexicographic order of pairs, which restricts to the product order
        on every simplex, so products nest: ``product(product(X, Y), Z) == product(X, product(Y, Z))``.
        ``dim P = X.dim + Y.dim``; ``χ(P) = χ(X) χ(Y)``.
    pairs : (N, 2) int64, only if ``return_pairs``

    Examples
    --------
    >>> from dhlb.examples import product, simplex, sphere
    >>> square = product(simplex(1), simplex(1))
    >>> square.simplices(2).tolist()           # the diagonal runs from (0, 0) to (1, 1)
    [[0, 1, 3], [0, 2, 3]]
    >>> T = product(sphere(1), sphere(1))       # the 9-vertex torus
    >>> T.counts, T.euler_characteristic
    ((9, 27, 18), 0)
    """
    X, Y = as_complex(X, "X"), as_complex(Y, "Y")
    n_y = Y.n_vertices
    blocks = []
    for S in X.maximal_simplices():
        if S.shape[0] == 0:
            continue
        for T in Y.maximal_simplices():
            if T.shape[0] == 0:
                continue
            I, J = shuffle_paths(S.shape[1] - 1, T.shape[1] - 1)  # (paths, p + q + 1)
            xs = S[:, I]  # (m_S, paths, L)
            ys = T[:, J]  # (m_T, paths, L)
            rows = xs[:, None, :, :] * n_y + ys[None, :, :, :]
            blocks.append(rows.reshape(-1, I.shape[1]))
    P = from_blocks(blocks)
    if return_pairs:
        v = np.arange(P.n_vertices, dtype=np.int64)
        return P, np.stack([v // n_y, v % n_y], axis=1)
    return P
