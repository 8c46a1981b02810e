"""Pseudomanifold and manifold checks, orientation and the fundamental cycle.

What :func:`is_manifold` certifies
----------------------------------
X (of dimension n) is pure, every (n−1)-simplex has one or two cofaces, and the link of every
k-simplex is a sphere or a ball of dimension d = n−k−1 (a ball exactly when the simplex lies in
a boundary face). The link tests are vectorized over all simplices:

* d = 0 (links of (n−1)-simplices): one or two points, i.e. one or two cofaces;
* d = 1: the link is connected (given d = 0, it is then a path or a cycle);
* d = 2: the link is connected and has Euler characteristic 2 (no boundary) or 1 (boundary);
  given d ≤ 1 it is a connected surface, and these are exactly the 2-sphere and the disk;
* d ≥ 3 (only for n ≥ 4): the link is connected and has the **integer homology** of S^d
  (no boundary) or of a point (boundary), computed per simplex by Smith normal form.

For n ≤ 3 this is the definition of a combinatorial (PL) manifold, possibly with boundary.
For n ≥ 4 it certifies a **homology manifold** whose links of dimension ≤ 2 are PL spheres or
balls; it cannot tell a PL 3-sphere from a homology 3-sphere such as Poincaré's.
Every 0-dimensional complex is a 0-manifold. Manifolds need not be connected.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import breadth_first_order
from scipy.sparse.csgraph import connected_components as _cc

from dhlb.errors import InvalidSimplexError, NonManifoldError, NonOrientableError
from dhlb.topology.complex import SimplicialComplex
from dhlb.topology.structure import (
    coface_counts,
    incidence,
    link_component_counts,
    maximal_mask,
    simplex_labels,
    subfaces,
)

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = [
    "Offense", "ManifoldReport", "manifold_report", "is_pseudomanifold", "is_manifold",
    "require_manifold", "is_orientable", "orientation", "is_consistently_oriented",
    "fundamental_cycle", "interior_pairs",
]

_NAMES = {0: "vertex", 1: "edge", 2: "triangle", 3: "tetrahedron"}


def _name(k: int) -> str:
    return _NAMES.get(k, f"{k}-simplex")


def _raise(err: Exception, simplex: tuple, k: int):
    """Attach the offending simplex (input labels) and its dimension to a typed error and raise it."""
    err.simplex, err.k = simplex, k
    raise err


@dataclass(frozen=True)
class Offense:
    """One simplex violating a manifold condition: dimension k, row, input labels and why."""

    check: str
    k: int
    row: int
    simplex: tuple
    reason: str

    def __str__(self) -> str:
        return f"the {_name(self.k)} {self.simplex} (input labels) {self.reason}"


@dataclass(frozen=True)
class ManifoldReport:
    """Result of :func:`manifold_report`; ``offenses`` lists the first offending simplices.

    The checks run in order (purity, branching (n−1)-faces, then links of increasing dimension)
    and ``offenses`` holds the simplices failing the first check that fails.

    Examples
    --------
    >>> from dhlb.examples import torus
    >>> rep = manifold_report(torus())
    >>> rep.is_manifold, rep.has_boundary, rep.n_strong_components, rep.first() is None
    (True, False, 1, True)
    """

    dim: int
    is_pure: bool
    is_pseudomanifold: bool
    is_manifold: bool
    has_boundary: bool
    n_strong_components: int
    criterion: str
    offenses: tuple = ()

    def first(self) -> Offense | None:
        """The first offending simplex, or ``None`` for a manifold."""
        return self.offenses[0] if self.offenses else None

    def __str__(self) -> str:
        head = f"{self.dim}-dimensional complex: " + ("a manifold" if self.is_manifold else "not a manifold")
        return "\n".join([head + f" ({self.criterion})"] + [f"  {o}" for o in self.offenses])


# ---------------------------------------------------------------------------- dual graph
def interior_pairs(X: SimplicialComplex):
    """The dual graph: pairs of top simplices sharing an (n−1)-face that has exactly two cofaces.

    Returns
    -------
    pairs : (E, 2) rows of the two n-simplices
    positions : (E, 2) position (in each) of the vertex not on the shared face
    faces : (E,) row of the shared (n−1)-face
    counts : (n_{n-1},) number of cofaces of every (n−1)-simplex

    Examples
    --------
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


def _strong_components(X: SimplicialComplex, pairs: np.ndarray) -> tuple[int, np.ndarray]:
    m = X.n_simplices(X.dim)
    g = sp.csr_matrix((np.ones(len(pairs), np.int8), (pairs[:, 0], pairs[:, 1])), shape=(m, m))
    return _cc(g, directed=False)


# ---------------------------------------------------------------------------- the checks
def _offenses(X, check, k, rows, reasons, limit):
    return [Offense(check, k, int(r), simplex_labels(X, k, int(r)), reasons(int(r))) for r in rows[:limit]]


def _sphere_homology(L: SimplicialComplex, d: int, closed: bool) -> bool:
    """True if L has the integer homology of S^d (closed) or of a point."""
    from dhlb.topology.homology import homology

    got = [(g.rank, tuple(g.torsion)) for g in homology(L)]
    return got == [(1, ())] + [(0, ())] * (d - 1) + [(1 if closed else 0, ())]


def _link_offenses(X, k, on_bd, limit):
    """Simplices of dimension k whose link (dimension d = n−k−1 >= 1) is no sphere or ball."""
    d = X.dim - k - 1
    comps = link_component_counts(X, k)
    bad = comps != 1
    chi = expected = None
    if d >= 2:
        cc = coface_counts(X, k)
        chi = sum((-1) ** (j - k - 1) * cc[:, j] for j in range(k + 1, X.dim + 1))
        expected = np.where(on_bd, 1, 1 + (-1) ** d)
        bad |= chi != expected
    rows = np.nonzero(bad)[0]
    if d >= 3 and rows.size == 0:  # cheap tests passed: integer homology, one link at a time
        inc = incidence(X, k, X.dim)  # X is pure here: links are generated by the top simplices
        tops, verts = X.simplices(X.dim), X.simplices(k)
        rows = []
        for r in range(X.n_simplices(k)):
            star_rows = tops[inc.indices[inc.indptr[r]:inc.indptr[r + 1]]]
            L = SimplicialComplex(star_rows[~np.isin(star_rows, verts[r])].reshape(len(star_rows), d + 1))
            if not _sphere_homology(L, d, not on_bd[r]):
                rows.append(r)
        rows = np.array(rows, np.int64)

    def reason(r):
        shape = "ball" if on_bd[r] else "sphere"
        if comps[r] != 1:
            return f"has a link with {comps[r]} connected components; in a manifold it is a {d}-{shape}"
        if chi is not None and chi[r] != expected[r]:
            return (f"has a link with Euler characteristic {chi[r]}; a {d}-{shape} has {expected[r]}"
                    + (" (e.g. the cone point over a torus)" if d == 2 and chi[r] == 0 else ""))
        return f"has a link without the integer homology of a {d}-{shape}"

    return _offenses(X, "link", k, rows, reason, limit)


def manifold_report(X: SimplicialComplex, limit: int = 10) -> ManifoldReport:
    """Check the (pseudo)manifold conditions and list the first offending simplices.

    Examples
    --------
    >>> X = SimplicialComplex([(0, 1, 2), (0, 3, 4)])   # two triangles sharing a vertex
    >>> rep = manifold_report(X)
    >>> rep.is_manifold, rep.is_pseudomanifold
    (False, False)
    >>> print(rep.first())
    the vertex (0,) (input labels) has a link with 2 connected components; in a manifold it is a 1-ball
    """
    n = X.dim
    if n == 0:
        return ManifoldReport(0, True, X.n_vertices <= 2, True, False, X.n_vertices,
                              "every 0-dimensional complex is a 0-manifold")
    criterion = "combinatorial manifold" if n <= 3 else "homology manifold with PL links of dimension <= 2"
    off = []
    for j in range(n):
        rows = np.nonzero(maximal_mask(X, j))[0]
        off += _offenses(X, "pure", j, rows, lambda r: f"is a face of no {_name(n)}; the complex is not pure",
                         limit - len(off))
    is_pure = not off
    pairs, _, _, counts = interior_pairs(X)
    has_boundary = bool(np.any(counts == 1))
    branching = np.nonzero(counts > 2)[0]
    n_strong = _strong_components(X, pairs)[0]
    is_pseudo = is_pure and branching.size == 0 and n_strong == 1
    if not off:
        off = _offenses(X, "branching", n - 1, branching,
                        lambda r: f"is a face of {counts[r]} {_name(n)}s; a manifold allows at most 2", limit)
    if not off:
        bd_faces = counts == 1
        for k in range(n - 2, -1, -1):
            on_bd = np.zeros(X.n_simplices(k), bool)
            on_bd[subfaces(X, n - 1, k)[bd_faces].ravel()] = True
            off = _link_offenses(X, k, on_bd, limit)
            if off:
                break
    return ManifoldReport(n, is_pure, is_pseudo, not off, has_boundary, int(n_strong), criterion, tuple(off))


def is_pseudomanifold(X: SimplicialComplex) -> bool:
    """Pure, every (n−1)-simplex has one or two cofaces, and strongly connected.

    A 0-dimensional pseudomanifold is one point or two (S⁰).

    Examples
    --------
    >>> is_pseudomanifold(SimplicialComplex([(0, 1, 2), (0, 3, 4)]))
    False
    """
    if X.dim == 0:
        return X.n_vertices <= 2
    if not X.is_pure:
        return False
    pairs, _, _, counts = interior_pairs(X)
    return bool(np.all(counts <= 2)) and _strong_components(X, pairs)[0] == 1


def is_manifold(X: SimplicialComplex) -> bool:
    """True if X is a manifold, possibly with boundary, in the sense of the module docstring.

    Examples
    --------
    >>> is_manifold(SimplicialComplex([(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)]))
    True
    """
    return manifold_report(X, limit=1).is_manifold


def require_manifold(X: SimplicialComplex) -> ManifoldReport:
    """Return the report of a manifold, raise :class:`NonManifoldError` naming an offending simplex.

    The error has attributes ``simplex`` (input labels), ``k`` and ``report``.

    Examples
    --------
    >>> require_manifold(SimplicialComplex([(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)])).is_manifold
    True
    >>> try:
    ...     require_manifold(SimplicialComplex([(0, 1, 2), (0, 3, 4)]))   # two triangles pinched at 0
    ... except NonManifoldError as err:
    ...     print(err.simplex, err.k)
    (0,) 0
    """
    rep = manifold_report(X)
    if not rep.is_manifold:
        o = rep.first()
        err = NonManifoldError(f"not a manifold: {o}. Fix the mesh there (split or remove simplices).")
        err.report = rep
        _raise(err, o.simplex, o.k)
    return rep


# ---------------------------------------------------------------------------- orientation
def _require_orientable_shape(X: SimplicialComplex):
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


def orientation(X: SimplicialComplex) -> np.ndarray:
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
    _, lab = _strong_components(X, pairs)
    _, roots = np.unique(lab, return_index=True)
    # BFS from a super-root m joined to the first simplex of every component; the symmetric
    # adjacency stores flip + 1 so that tree edges can be looked up.
    u = np.concatenate([pairs[:, 0], pairs[:, 1], np.full(roots.size, m), roots])
    v = np.concatenate([pairs[:, 1], pairs[:, 0], roots, np.full(roots.size, m)])
    w = np.concatenate([flip, flip, np.zeros(2 * roots.size, np.int64)]).astype(np.int8) + 1
    g = sp.csr_matrix((w, (u, v)), shape=(m + 1, m + 1))
    _, pred = breadth_first_order(g, m, directed=True, return_predecessors=True)
    parent = pred.astype(np.int64)
    parent[m] = m
    parity = np.zeros(m + 1, np.int64)
    parity[:m] = np.asarray(g[np.arange(m), parent[:m]]).ravel() - 1
    while np.any(parent != m):  # pointer jumping: parity relative to the super-root
        parity = (parity + parity[parent]) % 2
        parent = parent[parent]
    o = np.where(parity[:m] == 0, 1, -1).astype(np.int64)
    clash = np.nonzero(o[pairs[:, 1]] != o[pairs[:, 0]] * (1 - 2 * flip))[0]
    if clash.size:
        f = int(faces[clash].min())
        err = NonOrientableError(
            f"the complex is not orientable: no choice of orientations makes the two {_name(n)}s at the "
            f"{_name(n - 1)} {simplex_labels(X, n - 1, f)} (input labels) induce opposite orientations "
            f"(it lies on an orientation-reversing loop, as in a Möbius band)")
        _raise(err, simplex_labels(X, n - 1, f), n - 1)
    return o


def is_orientable(X: SimplicialComplex) -> bool:
    """True iff X is pure, no (n−1)-face has three or more cofaces, and an orientation exists.

    Examples
    --------
    >>> is_orientable(SimplicialComplex([(i, (i + 1) % 5, (i + 2) % 5) for i in range(5)]))  # Möbius
    False
    """
    try:
        orientation(X)
    except (NonManifoldError, NonOrientableError):
        return False
    return True


def fundamental_cycle(X: SimplicialComplex) -> np.ndarray:
    """The n-chain Σ o_σ σ of :func:`orientation` (int64, length n_n).

    On a closed oriented pseudomanifold it is a cycle; with boundary its boundary is the
    fundamental cycle of the boundary (interior faces cancel).

    Examples
    --------
    >>> X = SimplicialComplex([(0, 1), (1, 2), (0, 2)])
    >>> c = fundamental_cycle(X)
    >>> c.tolist(), (X.boundary(1) @ c).tolist()
    ([1, -1, 1], [0, 0, 0])
    """
    return orientation(X)


def is_consistently_oriented(X: SimplicialComplex, F: ArrayLike) -> tuple[bool, tuple | None]:
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
