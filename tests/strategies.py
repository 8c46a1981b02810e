"""Hypothesis strategies and known triangulations shared by the test-suite.

Known triangulations are plain functions returning lists of vertex tuples (top simplices);
strategies draw random complexes, random closed surfaces (known triangulations changed by
random edge flips and stellar subdivisions), random manifolds of dimension 1..4, random pure
complexes, and random relabelings. Import as ``from tests.strategies import ...``.
"""

from __future__ import annotations

import itertools

import numpy as np
from hypothesis import strategies as st

from dhlb import SimplicialComplex

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
    """Kuhn (Freudenthal) triangulation of a d-dimensional grid of unit cubes; a d-ball, or the
    d-torus when ``periodic`` (every side >= 3)."""
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
    """2-2 move on a surface: replace abc, abd by acd, bcd if ab has exactly two triangles and
    cd is not an edge; otherwise return the input unchanged."""
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
    """Stellar subdivision of the edge e (any dimension): a new vertex w replaces the simplices
    ρ ⊇ e by (ρ − a) ∪ w and (ρ − b) ∪ w. Preserves the PL homeomorphism type."""
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


# ---------------------------------------------------------------------------- strategies
@st.composite
def relabelings(draw, simplices, max_label: int = 60):
    """The same complex with vertices renamed by a random injective map into 0..max_label."""
    verts = sorted({v for s in simplices for v in s})
    new = draw(st.lists(st.integers(0, max(max_label, len(verts))), min_size=len(verts),
                        max_size=len(verts), unique=True))
    m = dict(zip(verts, new))
    return [tuple(m[v] for v in s) for s in simplices]


@st.composite
def simplex_lists(draw, max_vertices: int = 7, max_dim: int = 4, min_size: int = 1, max_size: int = 10):
    """Random subsets of the faces (of dimension <= max_dim) of the simplex on max_vertices
    vertices, as a list of vertex tuples with random (non-contiguous) labels."""
    n = draw(st.integers(1, max_vertices))
    faces = [s for r in range(1, min(max_dim, n - 1) + 2) for s in itertools.combinations(range(n), r)]
    size = draw(st.integers(min(min_size, len(faces)), min(max_size, len(faces))))
    chosen = draw(st.lists(st.sampled_from(faces), min_size=size, max_size=size, unique=True))
    return draw(relabelings(chosen))


def complexes(**kwargs):
    """Random SimplicialComplex from :func:`simplex_lists`."""
    return simplex_lists(**kwargs).map(SimplicialComplex)


@st.composite
def pure_simplex_lists(draw, dim: int = 3, max_vertices: int = 7, min_size: int = 1, max_size: int = 12,
                       min_vertices: int = 0):
    """Random pure dim-complexes: subsets of the dim-faces of a simplex on ``min_vertices`` ..
    ``max_vertices`` vertices (at least ``min_size`` of them when there are that many)."""
    n = draw(st.integers(max(dim + 1, min_vertices), max(dim + 1, min_vertices, max_vertices)))
    faces = list(itertools.combinations(range(n), dim + 1))
    size = draw(st.integers(min(min_size, len(faces)), min(max_size, len(faces))))
    chosen = draw(st.lists(st.sampled_from(faces), min_size=size, max_size=size, unique=True))
    return draw(relabelings(chosen))


_SURFACES = {  # name: (triangles, Euler characteristic, orientable)
    "sphere": (sphere(2), 2, True),
    "octahedron": (octahedron(), 2, True),
    "torus7": (torus7(), 0, True),
    "torus3x4": (torus_grid(3, 4), 0, True),
    "klein": (klein_bottle(3, 3), 0, False),
    "rp2": (rp2(), 1, False),
    "genus2": (None, -2, True),  # filled in below (connected sum of two tori)
}


def connected_sum(A, B) -> list[tuple]:
    """Connected sum of two closed surfaces: remove a triangle from each and glue the holes."""
    shift = 1 + max(v for s in A for v in s)
    B = [tuple(v + shift for v in s) for s in B]
    ta, tb = A[0], B[0]
    gl = dict(zip(tb, ta))
    return A[1:] + [tuple(sorted(gl.get(v, v) for v in s)) for s in B[1:]]


_SURFACES["genus2"] = (connected_sum(torus7(), torus7()), -2, True)


@st.composite
def closed_surfaces(draw, max_moves: int = 6):
    """(triangles, χ, orientable): a known closed surface changed by random edge flips and
    stellar subdivisions, then randomly relabeled."""
    name = draw(st.sampled_from(sorted(_SURFACES)))
    tris, chi, orientable = _SURFACES[name]
    tris = list(tris)
    for _ in range(draw(st.integers(0, max_moves))):
        move = draw(st.sampled_from(["flip", "flip", "edge", "face"]))
        if move == "face":
            tris = stellar_simplex(tris, draw(st.integers(0, len(tris) - 1)))
        else:
            e = draw(st.sampled_from(_edges_of(tris)))
            tris = edge_flip(tris, e) if move == "flip" else stellar_edge(tris, e)
    return draw(relabelings(tris, max_label=200)), chi, orientable


def _closed_manifold_seeds(dim: int):
    seeds = [(sphere(dim), "sphere")]
    if dim == 1:
        seeds.append((cycle(5), "sphere"))
    if dim == 2:
        seeds += [(s[0], n) for n, s in _SURFACES.items()]
    if dim == 3:
        seeds += [(join(cycle(3), cycle(4)), "sphere"), (suspension(octahedron()), "sphere"),
                  (kuhn_cubes((3, 3, 3), periodic=True), "torus")]
    if dim == 4:
        seeds += [(join(sphere(2), cycle(3)), "sphere"), (suspension(sphere(3)), "sphere")]
    return seeds


@st.composite
def closed_manifolds(draw, dim: int, max_moves: int = 3):
    """(top simplices, name): a closed dim-manifold (dim 1..4) from known triangulations changed
    by random stellar subdivisions, randomly relabeled."""
    simplices, name = draw(st.sampled_from(_closed_manifold_seeds(dim)))
    for _ in range(draw(st.integers(0, max_moves))):
        if draw(st.booleans()):
            simplices = stellar_edge(simplices, draw(st.sampled_from(_edges_of(simplices))))
        else:
            simplices = stellar_simplex(simplices, draw(st.integers(0, len(simplices) - 1)))
    return draw(relabelings(simplices, max_label=10 * len(simplices))), name


@st.composite
def balls(draw, dim: int, max_moves: int = 4):
    """A triangulated dim-ball: a simplex or a Kuhn cube grid, stellar-subdivided and relabeled."""
    simplices = draw(st.sampled_from([ball(dim), kuhn_cubes((1,) * dim), kuhn_cubes((2,) + (1,) * (dim - 1))]))
    for _ in range(draw(st.integers(0, max_moves))):
        if draw(st.booleans()):
            simplices = stellar_edge(simplices, draw(st.sampled_from(_edges_of(simplices))))
        else:
            simplices = stellar_simplex(simplices, draw(st.integers(0, len(simplices) - 1)))
    return draw(relabelings(simplices, max_label=10 * len(simplices)))

def rich_complexes(max_dim: int = 4):
    """Random complexes of dimension 2..max_dim with enough simplices to have loops and cycles."""
    options = [pure_simplex_lists(dim=2, max_vertices=8, min_size=4, max_size=18),
               simplex_lists(max_vertices=7, max_dim=max_dim, min_size=5, max_size=16)]
    if max_dim >= 3:
        options.append(pure_simplex_lists(dim=3, max_vertices=7, min_size=2, max_size=10))
    return st.one_of(*options).map(SimplicialComplex)
