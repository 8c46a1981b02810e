"""The dual graph of the top simplices, shared by the manifold checks and the orientation code.

:func:`interior_pairs` (re-exported by :mod:`dhlb.topology.manifold`, where it is documented)
and the strongly connected components of the dual graph (the messages of both modules name
simplices with :mod:`dhlb.topology._names`). Neither :mod:`dhlb.topology.manifold` nor
:mod:`dhlb.topology.orientation` is imported here, so both can import this module.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components as _cc

if TYPE_CHECKING:
    from dhlb.topology._protocol import ComplexLike

__all__ = ["interior_pairs", "strong_components"]


def interior_pairs(X: ComplexLike):
    """The dual graph: pairs of top simplices sharing an (n−1)-face that has exactly two cofaces.

    Returns
    -------
    pairs : (E, 2) rows of the two n-simplices
    positions : (E, 2) position (in each) of the vertex not on the shared face
    faces : (E,) row of the shared (n−1)-face
    counts : (n_{n-1},) number of cofaces of every (n−1)-simplex

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1, 2), (1, 2, 3)])
    >>> pairs, pos, faces, counts = interior_pairs(X)
    >>> pairs.tolist(), pos.tolist(), X.simplices(1)[faces].tolist()
    ([[0, 1]], [[0, 2]], [[1, 2]])
    """
    n = X.dim
    f = np.asarray(X.faces(n)).ravel()  # flat position = top * (n+1) + local position
    counts = np.bincount(f, minlength=X.n_simplices(n - 1))
    flat = np.arange(f.size, dtype=np.int64)
    lo = np.full(counts.size, f.size, np.int64)
    hi = np.full(counts.size, -1, np.int64)
    np.minimum.at(lo, f, flat)  # O(n) first/last occurrence per face, no sort
    np.maximum.at(hi, f, flat)
    faces = np.nonzero(counts == 2)[0]
    (ta, pa), (tb, pb) = np.divmod(lo[faces], n + 1), np.divmod(hi[faces], n + 1)
    return np.stack([ta, tb], axis=1), np.stack([pa, pb], axis=1), faces, counts


def strong_components(X: ComplexLike, pairs: np.ndarray) -> tuple[int, np.ndarray]:
    """Number and labels (per top simplex) of the connected components of the dual graph ``pairs``."""
    m = X.n_simplices(X.dim)
    g = sp.csr_matrix((np.ones(len(pairs), np.int8), (pairs[:, 0], pairs[:, 1])), shape=(m, m))
    return _cc(g, directed=False)
