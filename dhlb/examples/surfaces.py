"""Small named surfaces (and the dunce hat) with explicit, documented triangle lists."""

from __future__ import annotations

import numpy as np

from dhlb.topology.complex import SimplicialComplex

__all__ = ["torus", "klein_bottle", "projective_plane", "moebius_strip", "dunce_hat"]


def _complex(triangles) -> SimplicialComplex:
    return SimplicialComplex(np.asarray(triangles, dtype=np.int64))


def torus() -> SimplicialComplex:
    """Möbius' 7-vertex torus (Möbius 1861; realised as the Császár polyhedron, 1949).

    Vertices ``0 .. 6`` (read modulo 7); the 14 triangles are ``(i, i+1, i+3)`` and
    ``(i, i+3, i+2)`` for ``i = 0 .. 6``. Its 1-skeleton is the complete graph ``K_7``; it is the
    unique 7-vertex torus and the minimal triangulation of the torus. Each listed triple is
    positively oriented for one orientation of the torus.

    Returns
    -------
    T : SimplicialComplex
        The 7-vertex torus: vertices ``0 .. 6``, 21 edges, 14 triangles.

    Examples
    --------
    >>> from dhlb.examples import torus
    >>> T = torus()
    >>> T.counts, T.euler_characteristic
    ((7, 21, 14), 0)
    """
    i = np.arange(7)
    rows = np.concatenate([np.stack([i, i + 1, i + 3], 1), np.stack([i, i + 3, i + 2], 1)]) % 7
    return _complex(rows)


# The 6-vertex RP^2 as the antipodal quotient of the icosahedron: pole 0 over the pentagon 1..5.
_RP2 = [(0, 1, 2), (0, 2, 3), (0, 3, 4), (0, 4, 5), (0, 5, 1), (1, 2, 4), (2, 3, 5), (3, 4, 1), (4, 5, 2), (5, 1, 3)]


def projective_plane() -> SimplicialComplex:
    """The 6-vertex real projective plane (hemi-icosahedron), the minimal triangulation of RP².

    The antipodal map of the icosahedron is free and its quotient is a simplicial complex.
    Labelling: vertex 0 is (the class of) a pole, ``1 .. 5`` its neighbours in cyclic order. The
    triangles are the fan ``(0, i, i+1)`` and the five triangles ``(i, i+1, i+3)``
    (``i = 1 .. 5``, indices in ``1 .. 5`` read cyclically). The 1-skeleton is ``K_6``. Deleting
    the open star of vertex 0 (a disk) leaves :func:`moebius_strip`, via ``i -> 2 (i - 1) mod 5``.

    Returns
    -------
    P : SimplicialComplex
        The 6-vertex projective plane: vertices ``0 .. 5``, 15 edges, 10 triangles.

    Examples
    --------
    >>> from dhlb.examples import projective_plane
    >>> P = projective_plane()
    >>> P.counts, P.euler_characteristic
    ((6, 15, 10), 1)
    """
    return _complex(_RP2)


def moebius_strip() -> SimplicialComplex:
    """The 5-vertex Möbius strip, the minimal triangulation of the Möbius band.

    Vertices ``0 .. 4`` (read modulo 5), triangles ``(i, i+1, i+2)``. The edges ``(i, i+1)`` are
    interior; the boundary is the single pentagon ``0, 2, 4, 1, 3`` of edges ``(i, i+2)`` (an
    annulus would have two boundary circles). It is :func:`projective_plane` minus the open star
    of vertex 0, relabelled by ``i -> 2 (i - 1) mod 5``.

    Returns
    -------
    M : SimplicialComplex
        The 5-vertex Möbius strip: vertices ``0 .. 4``, 10 edges, 5 triangles.

    Examples
    --------
    >>> from dhlb.examples import moebius_strip
    >>> M = moebius_strip()
    >>> M.counts, M.euler_characteristic
    ((5, 10, 5), 0)
    >>> M.simplices(2).tolist()
    [[0, 1, 2], [0, 1, 4], [0, 3, 4], [1, 2, 3], [2, 3, 4]]
    """
    i = np.arange(5)
    return _complex(np.stack([i, i + 1, i + 2], 1) % 5)


# An 8-vertex Klein bottle: the connected sum RP^2 # RP^2 of two 6-vertex projective planes
# (9 vertices) after four edge flips admits an edge contraction that keeps it a manifold.
_KLEIN = [
    (0, 1, 4), (0, 1, 7), (0, 2, 3), (0, 2, 5), (0, 3, 4), (0, 5, 6), (0, 6, 7), (1, 2, 3),
    (1, 2, 4), (1, 3, 6), (1, 5, 6), (1, 5, 7), (2, 4, 5), (3, 4, 5), (3, 5, 7), (3, 6, 7),
]


def klein_bottle() -> SimplicialComplex:
    """An 8-vertex Klein bottle; 8 vertices is the minimum (Franklin 1934).

    Derived here (not copied): start from the connected sum ``RP² # RP²`` of two copies of
    :func:`projective_plane` glued along a triangle (9 vertices, 18 triangles), apply four edge
    flips, then contract an edge satisfying the link condition ``lk(u) ∩ lk(w) = lk(uw)``, which
    preserves the homeomorphism type. The result has 16 triangles; vertices 0, 1, 3, 5 have
    degree 7 and 2, 4, 6, 7 degree 5. It is a closed, non-orientable surface with ``χ = 0``, which
    by the classification of surfaces is the Klein bottle (checked in the tests).

    Triangles (vertex labels ``0 .. 7``)::

        014 017 023 025 034 056 067 123 124 136 156 157 245 345 357 367

    Returns
    -------
    K : SimplicialComplex
        The 8-vertex Klein bottle: vertices ``0 .. 7``, 24 edges, 16 triangles.

    Examples
    --------
    >>> from dhlb.examples import klein_bottle
    >>> K = klein_bottle()
    >>> K.counts, K.euler_characteristic
    ((8, 24, 16), 0)
    """
    return _complex(_KLEIN)


# The dunce hat: a triangle P Q R with boundary word a a a^{-1} (P->Q: a, Q->R: a, P->R: a).
# The curve a is subdivided as 0 -> 1 -> 2 -> 0, so the 9-gon boundary of the disk reads
# P=0, 1, 2, Q=0, 1, 2, R=0, 2, 1 (counter-clockwise). Interior vertices u_0..u_4 = 3..7:
# u_0 sees boundary positions P,1,2 of side PQ; u_1 positions 2,Q,1; u_2 positions 1,2,R;
# u_3 positions R,2,1 of side RP; u_4 positions 1,P. Five triangles join consecutive u's at
# the shared boundary position, and the pentagon u_0..u_4 is fanned from u_0.
_DUNCE = [
    (0, 1, 3), (1, 2, 3), (2, 0, 4), (0, 1, 4), (1, 2, 5), (2, 0, 5), (0, 2, 6), (2, 1, 6), (1, 0, 7),
    (2, 4, 3), (1, 5, 4), (0, 6, 5), (1, 7, 6), (0, 3, 7),
    (3, 4, 5), (3, 5, 6), (3, 6, 7),
]


def dunce_hat() -> SimplicialComplex:
    """An 8-vertex dunce hat: a triangle whose sides are glued by the word ``a a a^{-1}``.

    Contractible (homology ``Z, 0, 0``) but not collapsible, and not a manifold: the three edges
    of the curve ``a`` lie in three triangles each.

    Construction (our own, with the minimal vertex count 8 of Hachimori's triangulation): the
    disk is a 9-gon whose boundary reads ``0 1 2 0 1 2 0 2 1`` (sides ``PQ = a``, ``QR = a``,
    ``RP = a^{-1}``, with ``a`` subdivided as ``0 -> 1 -> 2 -> 0``). Interior vertices ``3 .. 7``
    each see at most three consecutive boundary positions with distinct labels, so no two
    triangles or edges get identified beyond the boundary gluing:

    * boundary triangles ``013 123 204 014 125 205 026 216 107`` (one per boundary edge),
    * connecting triangles ``243 154 065 176 037``,
    * the inner pentagon ``345 356 367``.

    All 17 triples are listed counter-clockwise in the disk.

    Returns
    -------
    D : SimplicialComplex
        The 8-vertex dunce hat: vertices ``0 .. 7``, 24 edges, 17 triangles.

    Examples
    --------
    >>> from dhlb.examples import dunce_hat
    >>> D = dunce_hat()
    >>> D.counts, D.euler_characteristic
    ((8, 24, 17), 1)
    """
    return _complex(_DUNCE)
