"""Orientations of pure complexes: consistent orientation, orientability, fundamental cycle.

An orientation of a pure n-dimensional complex is a sign ±1 per top simplex, relative to its
canonical (sorted) orientation, such that every (n−1)-face with two cofaces receives opposite
induced orientations (see ``docs/conventions.md`` for the induced orientation ``(−1)^i`` of the
face omitting vertex i). :func:`is_consistently_oriented` checks the orientation given by the
vertex order of user rows (e.g. a face array) instead. The manifold checks are in
:mod:`dhlb.topology.manifold`, which re-exports these functions.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from dhlb.errors import InvalidSimplexError, NonManifoldError, NonOrientableError
from dhlb.topology._dual_graph import interior_pairs
from dhlb.topology._dual_graph import propagate_signs as _propagate_signs
from dhlb.topology._names import kind_name as _name
from dhlb.topology._names import raise_at as _raise
from dhlb.topology._names import simplex_labels
from dhlb.topology.structure import maximal_mask

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from dhlb.topology._protocol import ComplexLike

__all__ = ["orientation", "is_orientable", "fundamental_cycle", "is_consistently_oriented"]


def _require_orientable_shape(X: ComplexLike):
    n = X.dim
    for j in range(n):
        mask = maximal_mask(X, j)
        if np.any(mask):
            s = simplex_labels(X, j, int(np.argmax(mask)))
            _raise(NonManifoldError(f"an orientation needs a pure complex, but the {_name(j)} {s} (input labels) "
                                    f"is a face of no {_name(n)}; remove it"), s, j)
    pairs, pos, faces, counts = interior_pairs(X)
    if np.any(counts > 2):
        r = int(np.argmax(counts > 2))
        s = simplex_labels(X, n - 1, r)
        _raise(NonManifoldError(f"the {_name(n - 1)} {s} (input labels) is a face of {counts[r]} {_name(n)}s; "
                                f"an orientation needs at most 2"), s, n - 1)
    return pairs, pos, faces


def orientation(X: ComplexLike) -> np.ndarray:
    """A consistent orientation: ±1 per top simplex relative to its canonical (sorted) orientation.

    Every (n−1)-face with two cofaces receives opposite induced orientations. The first top
    simplex of each strongly connected component (dual-graph component; for a manifold these
    are the connected components) gets +1. Signs are propagated over a BFS tree of the dual
    graph by pointer jumping (vectorized, O(m log depth)), then every dual edge is checked.

    Raises
    ------
    NonManifoldError
        X is not pure or an (n−1)-face has three or more cofaces (attribute ``simplex``).
    NonOrientableError
        No consistent orientation exists; the message (and the attribute ``simplex``, in input
        labels) names a face where the signs clash.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1, 2), (0, 2, 3), (0, 3, 1), (1, 2, 3)])   # tetrahedron boundary
    >>> orientation(X).tolist()
    [1, -1, 1, -1]
    >>> (X.boundary(2) @ orientation(X)).tolist()
    [0, 0, 0, 0, 0, 0]
    """
    n, m = X.dim, X.n_simplices(X.dim)
    if n == 0:
        return np.ones(m, np.int64)
    pairs, pos, faces = _require_orientable_shape(X)
    flip = (pos[:, 0] + pos[:, 1] + 1) % 2  # o_b = o_a * (-1)^flip cancels the shared face
    o, _, clash = _propagate_signs(m, pairs, flip)
    clash = np.nonzero(clash)[0]
    if clash.size:
        f = int(faces[clash].min())
        err = NonOrientableError(
            f"the complex is not orientable: no choice of orientations makes the two {_name(n)}s at the "
            f"{_name(n - 1)} {simplex_labels(X, n - 1, f)} (input labels) induce opposite orientations "
            f"(it lies on an orientation-reversing loop, as in a Möbius band)")
        _raise(err, simplex_labels(X, n - 1, f), n - 1)
    return o


def is_orientable(X: ComplexLike) -> bool:
    """True iff X is pure, no (n−1)-face has three or more cofaces, and an orientation exists.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> is_orientable(SimplicialComplex([(i, (i + 1) % 5, (i + 2) % 5) for i in range(5)]))  # Möbius
    False
    """
    try:
        orientation(X)
    except (NonManifoldError, NonOrientableError):
        return False
    return True


def fundamental_cycle(X: ComplexLike) -> np.ndarray:
    """The n-chain Σ o_σ σ of :func:`orientation` (int64, length n_n).

    On a closed oriented pseudomanifold it is a cycle; with boundary its boundary is the
    fundamental cycle of the boundary (interior faces cancel).

    Parameters
    ----------
    X : SimplicialComplex
        A pure complex of dimension n whose (n−1)-faces have one or two cofaces, orientable.

    Returns
    -------
    (n_n,) int64 array
        The coefficient ``o_σ = ±1`` of every n-simplex (row of ``X.simplices(X.dim)``).

    Raises
    ------
    NonManifoldError
        ``X`` is not pure or an (n−1)-face has three or more cofaces (attribute ``simplex``).
    NonOrientableError
        ``X`` is not orientable; the message (and the attribute ``simplex``, in input labels)
        names a face where the signs clash.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1), (1, 2), (0, 2)])
    >>> c = fundamental_cycle(X)
    >>> c.tolist(), (X.boundary(1) @ c).tolist()
    ([1, -1, 1], [0, 0, 0])
    """
    return orientation(X)


def is_consistently_oriented(X: ComplexLike, F: ArrayLike) -> tuple[bool, tuple | None]:
    """Whether the top simplices given in the user's vertex order are consistently oriented.

    Parameters
    ----------
    X : SimplicialComplex of dimension n
    F : int array (m, n+1) of top simplices of X in input labels; the row order of the
        vertices is the orientation meant (e.g. the face array of a mesh).

    Returns
    -------
    ok : bool
    face : tuple of input labels or None
        The first (n−1)-face (sorted labels) shared by two rows of F that induce the same
        orientation on it, e.g. an edge of a surface mesh traversed twice the same way.

    Raises
    ------
    InvalidSimplexError
        A simplex occurs twice in F.
    NonManifoldError
        An (n−1)-face is shared by three or more rows of F.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1, 2), (0, 2, 3)])
    >>> is_consistently_oriented(X, [(0, 1, 2), (0, 2, 3)])
    (True, None)
    >>> is_consistently_oriented(X, [(0, 1, 2), (0, 3, 2)])
    (False, (0, 2))
    """
    n = X.dim
    F = np.asarray(F)
    idx = X.index(n, F)
    sign = X.orientation_of(F)
    uniq, _first, cnt = np.unique(idx, return_index=True, return_counts=True)
    if np.any(cnt > 1):
        r = int(uniq[cnt > 1][0])
        i, j = np.nonzero(idx == r)[0][:2]
        s = simplex_labels(X, n, r)
        _raise(InvalidSimplexError(f"rows {i} and {j} of F are the same {_name(n)} {s}; remove one"), s, n)
    if n == 0:
        return True, None
    fc = np.asarray(X.faces(n))[idx]  # (m, n+1)
    induced = sign[:, None] * (1 - 2 * (np.arange(n + 1) % 2))[None, :]
    nf = X.n_simplices(n - 1)
    used = np.bincount(fc.ravel(), minlength=nf)
    if np.any(used > 2):
        r = int(np.argmax(used > 2))
        s = simplex_labels(X, n - 1, r)
        _raise(NonManifoldError(f"the {_name(n - 1)} {s} (input labels) is shared by {used[r]} rows of F; "
                                f"orientation consistency needs at most 2"), s, n - 1)
    total = np.bincount(fc.ravel(), weights=induced.ravel(), minlength=nf)
    bad = np.nonzero((used == 2) & (total != 0))[0]
    if bad.size:
        return False, simplex_labels(X, n - 1, int(bad[0]))
    return True, None
