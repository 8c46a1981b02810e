"""Pseudomanifold and manifold checks.

The orientation functions (:func:`orientation`, :func:`is_orientable`, :func:`fundamental_cycle`,
:func:`is_consistently_oriented`) live in :mod:`dhlb.topology.orientation` and are re-exported
here; :func:`interior_pairs` (the dual graph) lives in a private module shared by both.

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

from dhlb.errors import NonManifoldError
from dhlb.topology._dual_graph import interior_pairs
from dhlb.topology._dual_graph import strong_components as _strong_components
from dhlb.topology._names import kind_name as _name
from dhlb.topology._names import raise_at as _raise
from dhlb.topology._names import simplex_labels
from dhlb.topology.homology import homology
from dhlb.topology.orientation import (
    fundamental_cycle,
    is_consistently_oriented,
    is_orientable,
    orientation,
)
from dhlb.topology.structure import (
    coface_counts,
    incidence,
    link_component_counts,
    maximal_mask,
    subfaces,
)

if TYPE_CHECKING:
    from dhlb.topology._protocol import ComplexLike

__all__ = [
    "Offense", "ManifoldReport", "manifold_report", "is_pseudomanifold", "is_manifold",
    "require_manifold", "is_orientable", "orientation", "is_consistently_oriented",
    "fundamental_cycle", "interior_pairs",
]


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
    and ``offenses`` holds the simplices failing the first check that fails. Every parameter is
    kept as the attribute of the same name.

    Parameters
    ----------
    dim : int
        The dimension ``n`` of the complex.
    is_pure : bool
        Every simplex is a face of an n-simplex.
    is_pseudomanifold : bool
        Pure, every (n−1)-simplex has one or two cofaces, and strongly connected (for ``n = 0``:
        one or two vertices).
    is_manifold : bool
        A manifold, possibly with boundary, in the sense of the module docstring.
    has_boundary : bool
        Some (n−1)-simplex has exactly one coface.
    n_strong_components : int
        The number of connected components of the dual graph of the n-simplices (for ``n = 0``:
        the number of vertices).
    criterion : str
        What ``is_manifold`` certifies: ``"combinatorial manifold"`` for ``n <= 3``, a homology
        manifold with PL links of dimension <= 2 above.
    offenses : tuple of Offense, default ()
        The first offending simplices (at most ``limit`` of :func:`manifold_report`), empty for a
        manifold.

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


# ---------------------------------------------------------------------------- the checks
def _offenses(X, check, k, rows, reasons, limit):
    return [Offense(check, k, int(r), simplex_labels(X, k, int(r)), reasons(int(r))) for r in rows[:limit]]


def _sphere_homology(L: ComplexLike, d: int, closed: bool) -> bool:
    """True if L has the integer homology of S^d (closed) or of a point."""
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
            L = type(X)(star_rows[~np.isin(star_rows, verts[r])].reshape(len(star_rows), d + 1))
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


def manifold_report(X: ComplexLike, limit: int = 10) -> ManifoldReport:
    """Check the (pseudo)manifold conditions and list the first offending simplices.

    Parameters
    ----------
    X : SimplicialComplex
        Any complex.
    limit : int, default 10
        The largest number of offending simplices listed in the report.

    Returns
    -------
    ManifoldReport
        The outcome of every check, and the simplices (at most ``limit``) failing the first check
        that fails.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
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


def is_pseudomanifold(X: ComplexLike) -> bool:
    """Pure, every (n−1)-simplex has one or two cofaces, and strongly connected.

    A 0-dimensional pseudomanifold is one point or two (S⁰).

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> is_pseudomanifold(SimplicialComplex([(0, 1, 2), (0, 3, 4)]))
    False
    """
    if X.dim == 0:
        return X.n_vertices <= 2
    if not X.is_pure:
        return False
    pairs, _, _, counts = interior_pairs(X)
    return bool(np.all(counts <= 2)) and _strong_components(X, pairs)[0] == 1


def is_manifold(X: ComplexLike) -> bool:
    """True if X is a manifold, possibly with boundary, in the sense of the module docstring.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> is_manifold(SimplicialComplex([(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)]))
    True
    """
    return manifold_report(X, limit=1).is_manifold


def require_manifold(X: ComplexLike) -> ManifoldReport:
    """Return the report of a manifold, raise :class:`NonManifoldError` naming an offending simplex.

    The error has attributes ``simplex`` (input labels), ``k`` and ``report``.

    Parameters
    ----------
    X : SimplicialComplex
        Any complex.

    Returns
    -------
    ManifoldReport
        The report of :func:`manifold_report`, with ``is_manifold`` true.

    Raises
    ------
    NonManifoldError
        ``X`` is not a manifold; the message and the attributes ``simplex``, ``k`` name the first
        offending simplex, ``report`` is the whole :class:`ManifoldReport`.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
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
