"""Known triangulations as lists of vertex tuples, and local moves that keep the PL type.

Plain functions without hypothesis (the seeds of :mod:`dhlb.strategies`): each returns the top
simplices of a triangulation as a list of vertex tuples; the moves (edge flips, stellar
subdivisions) change a triangulation without changing its PL homeomorphism type, so everything
known about the seed (Euler characteristic, orientability, homology) stays true.
"""

from __future__ import annotations

import itertools

import numpy as np

# ---------------------------------------------------------------------------- known triangulations


def sphere(n: int) -> list[tuple]:
    """S^n as the boundary of the (n+1)-simplex on vertices 0..n+1."""
    return list(itertools.combinations(range(n + 2), n + 1))


def ball(n: int) -> list[tuple]:
    """The n-simplex."""
    return [tuple(range(n + 1))]


def octahedron() -> list[tuple]:
    """S² with 6 vertices (±e_i = 2i, 2i+1)."""
    return [(a, b, c) for a in (0, 1) for b in (2, 3) for c in (4, 5)]


def torus7() -> list[tuple]:
    """The 7-vertex (Möbius–Császár) torus."""
    return [tuple(sorted((i, (i + 1) % 7, (i + 3) % 7))) for i in range(7)] + \
           [tuple(sorted((i, (i + 2) % 7, (i + 3) % 7))) for i in range(7)]


def _grid_surface(a: int, b: int, twist: bool) -> list[tuple]:
    def v(i, j):
        if i == a:
            i, j = 0, (-j if twist else j)
        return i * b + j % b

    tris = []
    for i in range(a):
        for j in range(b):
            tris += [(v(i, j), v(i + 1, j), v(i + 1, j + 1)), (v(i, j), v(i, j + 1), v(i + 1, j + 1))]
    return tris


def torus_grid(a: int = 3, b: int = 3) -> list[tuple]:
    """Torus from an a×b periodic grid of squares cut into two triangles (a, b >= 3)."""
    return _grid_surface(a, b, twist=False)


def klein_bottle(a: int = 3, b: int = 3) -> list[tuple]:
    """Klein bottle: the a×b grid with one side glued with a flip (a, b >= 3)."""
    return _grid_surface(a, b, twist=True)


def rp2() -> list[tuple]:
    """The 6-vertex real projective plane (hemi-icosahedron)."""
    return [(0, 1, 2), (0, 2, 3), (0, 3, 4), (0, 4, 5), (0, 1, 5), (1, 2, 4), (2, 3, 5), (1, 3, 4), (2, 4, 5),
            (1, 3, 5)]


def mobius() -> list[tuple]:
    """The 5-vertex Möbius band."""
    return [tuple(sorted((i, (i + 1) % 5, (i + 2) % 5))) for i in range(5)]


def cone(simplices, apex: int | None = None) -> list[tuple]:
    """Cone over a complex given by its top simplices (apex: a new vertex by default)."""
    if apex is None:
        apex = 1 + max(v for s in simplices for v in s)
    return [tuple(s) + (apex,) for s in simplices]


def suspension(simplices) -> list[tuple]:
    """Suspension (two cone points)."""
    top = 1 + max(v for s in simplices for v in s)
    return cone(simplices, top) + cone(simplices, top + 1)


def join(A, B) -> list[tuple]:
    """Join of two complexes on disjoint vertex sets (B is shifted)."""
    shift = 1 + max(v for s in A for v in s)
    return [tuple(a) + tuple(v + shift for v in b) for a in A for b in B]


def cycle(n: int) -> list[tuple]:
    """The circle as an n-gon (n >= 3)."""
    return [tuple(sorted((i, (i + 1) % n))) for i in range(n)]


def kuhn_cubes(shape, periodic: bool = False) -> list[tuple]:
    """Kuhn (Freudenthal) triangulation of a d-dimensional grid of unit cubes.

    A d-ball, or the d-torus when ``periodic`` (every side >= 3).
    """
    shape = tuple(shape)
    d = len(shape)
    size = tuple(s if periodic else s + 1 for s in shape)
    idx = np.arange(int(np.prod(size))).reshape(size)
    out = []
    for corner in itertools.product(*(range(s) for s in shape)):
        for perm in itertools.permutations(range(d)):
            p, verts = list(corner), []
            verts.append(idx[tuple(c % s for c, s in zip(p, size))])
            for axis in perm:
                p[axis] += 1
                verts.append(idx[tuple(c % s for c, s in zip(p, size))])
            out.append(tuple(int(x) for x in verts))
    return out


# ---------------------------------------------------------------------------- local moves
def edge_flip(tris: list[tuple], e: tuple) -> list[tuple]:
    """2-2 move on a surface: replace abc, abd by acd, bcd.

    Only if ab has exactly two triangles and cd is not an edge; otherwise the input is returned
    unchanged.
    """
    a, b = e
    on = [t for t in tris if a in t and b in t]
    if len(on) != 2:
        return tris
    c = next(x for x in on[0] if x not in e)
    d = next(x for x in on[1] if x not in e)
    if c == d or any(c in t and d in t for t in tris):
        return tris
    rest = [t for t in tris if t not in on]
    return rest + [tuple(sorted((a, c, d))), tuple(sorted((b, c, d)))]


def stellar_edge(simplices: list[tuple], e: tuple) -> list[tuple]:
    """Stellar subdivision of the edge e (any dimension).

    A new vertex w replaces the simplices ρ ⊇ e by (ρ − a) ∪ w and (ρ − b) ∪ w. Preserves the PL
    homeomorphism type.
    """
    a, b = e
    w = 1 + max(v for s in simplices for v in s)
    out = []
    for s in simplices:
        if a in s and b in s:
            out.append(tuple(sorted([v for v in s if v != a] + [w])))
            out.append(tuple(sorted([v for v in s if v != b] + [w])))
        else:
            out.append(tuple(s))
    return out


def stellar_simplex(simplices: list[tuple], i: int) -> list[tuple]:
    """Cone off the i-th (maximal) simplex from a new interior vertex."""
    w = 1 + max(v for s in simplices for v in s)
    s = simplices[i]
    return simplices[:i] + simplices[i + 1:] + [tuple(f) + (w,) for f in itertools.combinations(s, len(s) - 1)]


def _edges_of(simplices):
    return sorted({e for s in simplices for e in itertools.combinations(sorted(s), 2)})


def connected_sum(A, B) -> list[tuple]:
    """Connected sum of two closed surfaces: remove a triangle from each and glue the holes."""
    shift = 1 + max(v for s in A for v in s)
    B = [tuple(v + shift for v in s) for s in B]
    ta, tb = A[0], B[0]
    gl = dict(zip(tb, ta))
    return A[1:] + [tuple(sorted(gl.get(v, v) for v in s)) for s in B[1:]]
