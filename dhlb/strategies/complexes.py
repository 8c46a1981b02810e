"""Hypothesis strategies for simplicial complexes and for manifolds with known invariants.

:func:`simplicial_complexes` draws arbitrary complexes; :func:`closed_surfaces`,
:func:`closed_manifolds` and :func:`balls` draw triangulations of known spaces, changed by random
local moves (edge flips, stellar subdivisions) and relabeled, and return a :class:`Known` record
whose invariants come from the construction (classification of surfaces, Künneth's formula,
tables of classical spaces), never from dhlb's own algorithms.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field
from functools import cached_property

from hypothesis import strategies as st

from dhlb._coerce import check_int
from dhlb.errors import InvalidParameterError
from dhlb.strategies import _seeds as sd
from dhlb.topology.complex import SimplicialComplex

__all__ = [
    "Known",
    "relabelings",
    "simplex_lists",
    "pure_simplex_lists",
    "simplicial_complexes",
    "closed_surfaces",
    "closed_manifolds",
    "balls",
]


# ---------------------------------------------------------------------------- the record
@dataclass(frozen=True)
class Known:
    """A triangulated space together with what is known about it from its construction.

    Every parameter is kept as the attribute of the same name.

    Parameters
    ----------
    simplices : tuple of tuple of int
        The top simplices with their (random, non-contiguous) vertex labels, in the order the
        construction produced them.
    name : str
        The space, e.g. ``"S^2"``, ``"T^2"``, ``"RP^2"``, ``"Klein bottle"``, ``"RP^2 x S^1"``, ``"B^3"``.
    dim : int
        Its dimension.
    euler_characteristic : int
        Its Euler characteristic.
    orientable : bool
        Whether it is orientable.
    homology : tuple of (int, tuple of int)
        Integer homology ``H_k`` for ``k = 0 .. dim`` as ``(rank, torsion coefficients)``;
        e.g. ``((1, ()), (0, (2,)), (0, ()))`` for RP².
    seed : str, optional
        The starting triangulation (``"rp2"``, ``"torus7"``, ``"kuhn(3,3,3)"``, …).
    moves : tuple of str, optional
        The local moves applied to the seed, in order (``"flip(3,5)"``, ``"stellar_edge(0,2)"``,
        ``"stellar_simplex(4)"``); the vertex numbers are those before the final relabeling.

    Notes
    -----
    ``complex`` (a :class:`~dhlb.SimplicialComplex`) is built on first access. The invariants
    come from the seed: the classification of surfaces (``H_1`` of a closed surface of Euler
    characteristic χ is ``Z^{2-χ}`` if orientable, ``Z^{1-χ} ⊕ Z/2`` if not), Künneth's formula for
    products, and the classical homology of spheres, tori, balls and ``RP^3``; flips and stellar
    subdivisions preserve the PL homeomorphism type, so they stay true.

    Examples
    --------
    >>> from hypothesis import find
    >>> k = find(closed_surfaces(orientable=False), lambda k: True)   # the simplest one
    >>> k.name, k.euler_characteristic, k.homology
    ('RP^2', 1, ((1, ()), (0, (2,)), (0, ())))
    >>> k.complex.counts
    (6, 15, 10)
    """

    simplices: tuple
    name: str
    dim: int
    euler_characteristic: int
    orientable: bool
    homology: tuple
    seed: str = ""
    moves: tuple = field(default=())

    @cached_property
    def complex(self) -> SimplicialComplex:
        """The :class:`~dhlb.SimplicialComplex` spanned by :attr:`simplices`."""
        return SimplicialComplex(list(self.simplices))

    @property
    def betti_numbers(self) -> tuple:
        """The ranks of the homology groups, ``k = 0 .. dim``."""
        return tuple(r for r, _ in self.homology)

    @property
    def torsion(self) -> tuple:
        """The torsion coefficients of the homology groups, ``k = 0 .. dim``."""
        return tuple(t for _, t in self.homology)

    def __repr__(self) -> str:
        moves = f", moves={len(self.moves)}" if self.moves else ""
        return (f"Known(name={self.name!r}, seed={self.seed!r}{moves}, n_top={len(self.simplices)}, "
                f"euler_characteristic={self.euler_characteristic}, orientable={self.orientable})")


# ---------------------------------------------------------------------------- basic strategies
@st.composite
def relabelings(draw, simplices, max_label: int = 60):
    """The same complex with its vertices renamed by a random injective map into ``0 .. max_label``.

    Parameters
    ----------
    simplices : list of tuple of int
        Top simplices (or any simplices) of a complex.
    max_label : int
        The largest new label (raised to the number of vertices if smaller).

    Returns
    -------
    SearchStrategy of list of tuple of int
        The simplices in the same order, vertices renamed. Shrinks towards small labels.

    Examples
    --------
    >>> from hypothesis import given, settings
    >>> @settings(max_examples=20)
    ... @given(relabelings([(0, 1, 2), (0, 2, 3)], max_label=9))
    ... def shares_an_edge(s):
    ...     assert len(set(s[0]) & set(s[1])) == 2 and max(max(t) for t in s) <= 9
    >>> shares_an_edge()
    """
    verts = sorted({v for s in simplices for v in s})
    new = draw(st.lists(st.integers(0, max(max_label, len(verts))), min_size=len(verts),
                        max_size=len(verts), unique=True))
    m = dict(zip(verts, new))
    return [tuple(m[v] for v in s) for s in simplices]


@st.composite
def simplex_lists(draw, max_vertices: int = 7, max_dim: int = 4, min_size: int = 1, max_size: int = 10):
    """Random sets of simplices, as lists of vertex tuples with random non-contiguous labels.

    Parameters
    ----------
    max_vertices : int
        The simplices are faces of the simplex on ``1 .. max_vertices`` vertices.
    max_dim : int
        Largest dimension of a drawn simplex.
    min_size, max_size : int
        Bounds on the number of drawn simplices (capped by the number of faces available).

    Returns
    -------
    SearchStrategy of list of tuple of int
        Possibly disconnected, possibly with isolated vertices; the complex they span may have
        more simplices (their faces). Shrinks towards few, small simplices.

    Examples
    --------
    >>> from hypothesis import given, settings
    >>> @settings(max_examples=20)
    ... @given(simplex_lists(max_dim=2))
    ... def check(simplices):
    ...     assert all(len(s) <= 3 for s in simplices)
    >>> check()
    """
    n = draw(st.integers(1, max_vertices))
    faces = [s for r in range(1, min(max_dim, n - 1) + 2) for s in itertools.combinations(range(n), r)]
    size = draw(st.integers(min(min_size, len(faces)), min(max_size, len(faces))))
    chosen = draw(st.lists(st.sampled_from(faces), min_size=size, max_size=size, unique=True))
    return draw(relabelings(chosen))


@st.composite
def pure_simplex_lists(draw, dim: int = 3, max_vertices: int = 7, min_size: int = 1, max_size: int = 12,
                       min_vertices: int = 0):
    """Random pure ``dim``-complexes as lists of vertex tuples.

    Subsets of the ``dim``-faces of a simplex on ``min_vertices .. max_vertices`` vertices (at
    least ``dim + 1``), with at least ``min_size`` of them when there are that many.

    Parameters
    ----------
    dim : int
    max_vertices, min_vertices : int
    min_size, max_size : int
        Bounds on the number of top simplices.

    Returns
    -------
    SearchStrategy of list of tuple of int

    Examples
    --------
    >>> from hypothesis import given, settings
    >>> @settings(max_examples=20)
    ... @given(pure_simplex_lists(dim=2, min_vertices=5, min_size=3))
    ... def check(simplices):
    ...     assert len(simplices) >= 3 and all(len(s) == 3 for s in simplices)
    >>> check()
    """
    n = draw(st.integers(max(dim + 1, min_vertices), max(dim + 1, min_vertices, max_vertices)))
    faces = list(itertools.combinations(range(n), dim + 1))
    size = draw(st.integers(min(min_size, len(faces)), min(max_size, len(faces))))
    chosen = draw(st.lists(st.sampled_from(faces), min_size=size, max_size=size, unique=True))
    return draw(relabelings(chosen))


def simplicial_complexes(max_dim: int = 4, max_vertices: int = 8, min_simplices: int = 1,
                         max_simplices: int = 10) -> st.SearchStrategy:
    """Random :class:`~dhlb.SimplicialComplex` es (see :func:`simplex_lists`).

    Parameters
    ----------
    max_dim : int
        Largest dimension of a generating simplex (so of the complex).
    max_vertices : int
        At most this many vertices; labels are random and non-contiguous.
    min_simplices, max_simplices : int
        Bounds on the number of generating simplices.

    Returns
    -------
    SearchStrategy of SimplicialComplex
        Possibly disconnected, not necessarily pure; shrinks towards a single vertex.

    Raises
    ------
    InvalidParameterError
        a bound is not a positive integer or ``max_simplices < min_simplices``.

    Examples
    --------
    >>> from hypothesis import given, settings
    >>> @settings(max_examples=30)
    ... @given(simplicial_complexes(max_dim=3))
    ... def euler_is_alternating_sum(X):
    ...     assert X.euler_characteristic == sum((-1) ** k * n for k, n in enumerate(X.counts))
    >>> euler_is_alternating_sum()
    """
    check_int(max_dim, "max_dim", 0)
    check_int(max_vertices, "max_vertices", 1)
    check_int(min_simplices, "min_simplices", 1)
    check_int(max_simplices, "max_simplices", 1)
    if max_simplices < min_simplices:
        raise InvalidParameterError(f"max_simplices ({max_simplices}) < min_simplices ({min_simplices})")
    return simplex_lists(max_vertices=max_vertices, max_dim=max_dim, min_size=min_simplices,
                         max_size=max_simplices).map(SimplicialComplex)


# ---------------------------------------------------------------------------- known spaces
def _surface_homology(chi: int, orientable: bool) -> tuple:
    if orientable:
        return ((1, ()), (2 - chi, ()), (1, ()))
    return ((1, ()), (1 - chi, (2,)), (0, ()))


def _sphere_homology(n: int) -> tuple:
    return tuple((1 if k in (0, n) else 0, ()) for k in range(n + 1)) if n else ((2, ()),)


def _torus_homology(n: int) -> tuple:  # Künneth: H_k(T^n) = Z^(n choose k)
    from math import comb

    return tuple((comb(n, k), ()) for k in range(n + 1))


def _rows(X: SimplicialComplex) -> list:
    return [tuple(int(v) for v in r) for r in X.vertex_labels[X.simplices(X.dim)]]


@dataclass(frozen=True)
class _Seed:
    key: str
    name: str
    build: object  # () -> list of top simplices (built lazily, cached)
    euler: int
    orientable: bool
    homology: tuple
    legacy: bool = True  # part of the seeds the package's own tests were written for

    def simplices(self) -> list:
        if self.key not in _SEED_CACHE:
            _SEED_CACHE[self.key] = self.build()
        return _SEED_CACHE[self.key]


_SEED_CACHE: dict = {}


def _product(a, b):
    def build():
        from dhlb.examples import product, sphere

        from_ = {"S1": lambda: sphere(1), "S2": lambda: sphere(2), "S3": lambda: sphere(3)}
        A = from_[a]() if isinstance(a, str) else SimplicialComplex(a())
        return _rows(product(A, from_[b]()))

    return build


def _lens(p):
    def build():
        from dhlb.examples import lens_space

        return _rows(lens_space(p))

    return build


_SURFACE_SEEDS = [  # key, name, triangles, χ, orientable; ordered simplest first (shrinking target)
    ("sphere", "S^2", lambda: sd.sphere(2), 2, True),
    ("octahedron", "S^2", sd.octahedron, 2, True),
    ("rp2", "RP^2", sd.rp2, 1, False),
    ("torus7", "T^2", sd.torus7, 0, True),
    ("torus3x4", "T^2", lambda: sd.torus_grid(3, 4), 0, True),
    ("klein", "Klein bottle", lambda: sd.klein_bottle(3, 3), 0, False),
    ("genus2", "genus-2 surface", lambda: sd.connected_sum(sd.torus7(), sd.torus7()), -2, True),
]
_NEW_SURFACE_SEEDS = [
    ("rp2#torus7", "RP^2 # T^2", lambda: sd.connected_sum(sd.rp2(), sd.torus7()), -1, False),
]


def _seeds(dim: int) -> list:
    if dim == 2:
        out = [_Seed(k, n, b, e, o, _surface_homology(e, o)) for k, n, b, e, o in _SURFACE_SEEDS]
        return out + [_Seed(k, n, b, e, o, _surface_homology(e, o), legacy=False)
                      for k, n, b, e, o in _NEW_SURFACE_SEEDS]
    sph = _sphere_homology(dim)
    euler = 1 + (-1) ** dim
    out = [_Seed(f"sphere({dim})", f"S^{dim}", lambda: sd.sphere(dim), euler, True, sph)]
    if dim == 1:
        out.append(_Seed("cycle(5)", "S^1", lambda: sd.cycle(5), 0, True, sph))
    if dim == 3:
        out += [
            _Seed("join(C3,C4)", "S^3", lambda: sd.join(sd.cycle(3), sd.cycle(4)), 0, True, sph),
            _Seed("suspension(octahedron)", "S^3", lambda: sd.suspension(sd.octahedron()), 0, True, sph),
            _Seed("kuhn(3,3,3)", "T^3", lambda: sd.kuhn_cubes((3, 3, 3), periodic=True), 0, True, _torus_homology(3)),
            _Seed("product(S1,S2)", "S^1 x S^2", _product("S1", "S2"), 0, True,
                  ((1, ()), (1, ()), (1, ()), (1, ())), legacy=False),
            # Künneth: H_1 = Z/2 ⊕ Z, H_2 = Z/2 (H_1(RP²) ⊗ H_1(S¹)), H_3 = 0; Tor terms vanish
            _Seed("product(rp2,S1)", "RP^2 x S^1", _product(sd.rp2, "S1"), 0, False,
                  ((1, ()), (1, (2,)), (0, (2,)), (0, ())), legacy=False),
            _Seed("lens_space(2,1)", "RP^3", _lens(2), 0, True, ((1, ()), (0, (2,)), (0, ()), (1, ())),
                  legacy=False),
        ]
    if dim == 4:
        out += [
            _Seed("join(S2,C3)", "S^4", lambda: sd.join(sd.sphere(2), sd.cycle(3)), 2, True, sph),
            _Seed("suspension(S3)", "S^4", lambda: sd.suspension(sd.sphere(3)), 2, True, sph),
            _Seed("product(S1,S3)", "S^1 x S^3", _product("S1", "S3"), 0, True,
                  ((1, ()), (1, ()), (0, ()), (1, ()), (1, ())), legacy=False),
            _Seed("product(S2,S2)", "S^2 x S^2", _product("S2", "S2"), 4, True,
                  ((1, ()), (0, ()), (2, ()), (0, ()), (1, ())), legacy=False),
        ]
    return out


def _select(dim: int, names, orientable, legacy_only: bool) -> list:
    seeds = _seeds(dim)
    if legacy_only:
        seeds = [s for s in seeds if s.legacy]
    if names is not None:
        names = [names] if isinstance(names, str) else list(names)
        known = sorted({s.name for s in _seeds(dim)} | {s.key for s in _seeds(dim)})
        bad = [n for n in names if n not in known]
        if bad:
            raise InvalidParameterError(f"unknown space {bad[0]!r} in dimension {dim}; choose from {known}")
        seeds = [s for s in seeds if s.name in names or s.key in names]
    if orientable is not None:
        seeds = [s for s in seeds if s.orientable == bool(orientable)]
    if not seeds:
        raise InvalidParameterError(f"no known {dim}-manifold matches names={names!r}, orientable={orientable!r}")
    return seeds


def _edge_key(e) -> str:
    return f"({e[0]},{e[1]})"


@st.composite
def _moved(draw, seed: _Seed, max_moves: int, kinds: tuple, max_label, legacy_labels: bool = False):
    simplices = list(seed.simplices())
    moves = []
    for _ in range(draw(st.integers(0, max_moves))):
        move = draw(st.sampled_from(kinds))
        if move == "face":
            i = draw(st.integers(0, len(simplices) - 1))
            simplices = sd.stellar_simplex(simplices, i)
            moves.append(f"stellar_simplex({i})")
        else:
            e = draw(st.sampled_from(sd._edges_of(simplices)))
            if move == "flip":
                new = sd.edge_flip(simplices, e)
                if new is not simplices:
                    moves.append(f"flip{_edge_key(e)}")
                simplices = new
            else:
                simplices = sd.stellar_edge(simplices, e)
                moves.append(f"stellar_edge{_edge_key(e)}")
    label = max_label if isinstance(max_label, int) else max_label(simplices)
    simplices = draw(relabelings(simplices, max_label=label))
    return Known(tuple(simplices), seed.name, len(simplices[0]) - 1, seed.euler, seed.orientable, seed.homology,
                 seed.key, tuple(moves))


def closed_surfaces(orientable: bool | None = None, max_moves: int = 6, names=None, *,
                    _legacy: bool = False) -> st.SearchStrategy:
    """Closed surfaces with known Euler characteristic, orientability and homology.

    A known triangulation (the 4-vertex and the 6-vertex sphere, the 6-vertex RP², the 7-vertex
    torus, a 3×4 torus grid, a 3×3 Klein bottle, connected sums of two 7-vertex tori and of RP²
    with a torus) changed by up to ``max_moves`` random edge flips and stellar subdivisions of
    edges and triangles, then randomly relabeled.

    Parameters
    ----------
    orientable : bool, optional
        Only orientable (True) or only non-orientable (False) surfaces; default both.
    max_moves : int
        Largest number of local moves.
    names : str or list of str, optional
        Restrict to these spaces (``"S^2"``, ``"T^2"``, ``"RP^2"``, ``"Klein bottle"``,
        ``"genus-2 surface"``, ``"RP^2 # T^2"``) or seeds (``"torus7"``, …).

    Other Parameters
    ----------------
    _legacy : bool, optional
        For the adapters in the test suite (``tests/strategies.py``) only: only the original seed
        spaces and the vertex-label range of the former strategy, so that the examples of the
        former strategies keep their shapes.

    Returns
    -------
    SearchStrategy of Known
        Shrinks towards the unmoved 4-vertex sphere (or, when non-orientable, the 6-vertex RP²).

    Raises
    ------
    InvalidParameterError
        unknown name, negative ``max_moves``, or no surface left after the filters.

    Examples
    --------
    >>> from hypothesis import given, settings
    >>> @settings(max_examples=20)
    ... @given(closed_surfaces(orientable=False))
    ... def check(k):
    ...     assert k.complex.euler_characteristic == k.euler_characteristic
    ...     assert k.homology[1][1] == (2,)             # H_1 has Z/2 torsion
    >>> check()
    """
    check_int(max_moves, "max_moves", 0)
    seeds = _select(2, names, orientable, _legacy)
    label = 200 if _legacy else (lambda s: 3 * len({v for t in s for v in t}))
    return st.sampled_from(seeds).flatmap(
        lambda s: _moved(s, max_moves, ("flip", "flip", "edge", "face"), label))


def closed_manifolds(dim: int, max_moves: int = 3, names=None, orientable: bool | None = None, *,
                     _legacy: bool = False) -> st.SearchStrategy:
    """Closed ``dim``-manifolds (``dim`` = 1 … 4) with known invariants.

    Seeds: spheres (boundaries of simplices, joins, suspensions), the 3-torus (Kuhn triangulation
    of a periodic 3×3×3 grid), ``S^1 × S^2``, ``RP^2 × S^1``, ``RP^3 = L(2, 1)``, ``S^1 × S^3``,
    ``S^2 × S^2`` (shuffle products of :mod:`dhlb.examples`), and in dimension 2 the surfaces of
    :func:`closed_surfaces`; changed by up to ``max_moves`` stellar subdivisions of edges and top
    simplices, then relabeled.

    Parameters
    ----------
    dim : int
        1, 2, 3 or 4.
    max_moves : int
    names : str or list of str, optional
        Restrict to these spaces (``"S^3"``, ``"T^3"``, ``"RP^3"``, ``"S^1 x S^2"``, …) or seeds.
    orientable : bool, optional

    Other Parameters
    ----------------
    _legacy : bool, optional
        For the adapters in the test suite (``tests/strategies.py``) only: only the original seed
        spaces and the vertex-label range of the former strategy, so that the examples of the
        former strategies keep their shapes.

    Returns
    -------
    SearchStrategy of Known
        Shrinks towards the boundary of the ``(dim+1)``-simplex.

    Raises
    ------
    InvalidParameterError
        ``dim`` outside 1 … 4, an unknown name, or nothing left after the filters.

    Examples
    --------
    >>> from hypothesis import find
    >>> k = find(closed_manifolds(3), lambda k: any(t for _, t in k.homology))   # some torsion
    >>> k.name, k.homology
    ('RP^2 x S^1', ((1, ()), (1, (2,)), (0, (2,)), (0, ())))
    """
    if isinstance(dim, bool) or dim not in (1, 2, 3, 4):
        raise InvalidParameterError(f"dim must be 1, 2, 3 or 4, got {dim!r}")
    check_int(max_moves, "max_moves", 0)
    seeds = _select(dim, names, orientable, _legacy)
    label = (lambda s: 10 * len(s)) if _legacy else (lambda s: 3 * len({v for t in s for v in t}))
    return st.sampled_from(seeds).flatmap(lambda s: _moved(s, max_moves, ("edge", "face"), label))


def balls(dim: int, max_moves: int = 4, *, _legacy: bool = False) -> st.SearchStrategy:
    """Triangulated ``dim``-balls: a simplex or a Kuhn-triangulated box, subdivided and relabeled.

    Parameters
    ----------
    dim : int, >= 1
    max_moves : int
        Largest number of stellar subdivisions (of edges and top simplices).

    Other Parameters
    ----------------
    _legacy : bool, optional
        For the adapters in the test suite (``tests/strategies.py``) only: the vertex-label range
        of the former strategy, so that the examples of the former strategy keep their shapes.

    Returns
    -------
    SearchStrategy of Known
        ``name = "B^dim"``, Euler characteristic 1, orientable, homology ``Z`` in degree 0 and
        0 elsewhere. Shrinks towards the ``dim``-simplex.

    Raises
    ------
    InvalidParameterError
        ``dim`` is not an integer >= 1, or ``max_moves`` not an integer >= 0.

    Examples
    --------
    >>> from hypothesis import given, settings
    >>> @settings(max_examples=10)
    ... @given(balls(3))
    ... def check(k):
    ...     assert k.complex.euler_characteristic == 1 and k.homology[0] == (1, ())
    >>> check()
    """
    dim = check_int(dim, "dim", 1)
    check_int(max_moves, "max_moves", 0)
    hom = ((1, ()),) + ((0, ()),) * dim
    seeds = [_Seed(f"simplex({dim})", f"B^{dim}", lambda: sd.ball(dim), 1, True, hom),
             _Seed(f"kuhn({dim}-cube)", f"B^{dim}", lambda: sd.kuhn_cubes((1,) * dim), 1, True, hom),
             _Seed(f"kuhn(2x{dim}-cube)", f"B^{dim}", lambda: sd.kuhn_cubes((2,) + (1,) * (dim - 1)), 1, True, hom)]
    label = (lambda s: 10 * len(s)) if _legacy else (lambda s: 3 * len({v for t in s for v in t}))
    return st.sampled_from(seeds).flatmap(lambda s: _moved(s, max_moves, ("edge", "face"), label))
