"""The test-suite's view of :mod:`dhlb.strategies` (the generators live there; nothing is duplicated).

``from tests.strategies import ...`` keeps working for every test file:

* everything public in :mod:`dhlb.strategies` is re-exported;
* the known triangulations and local moves (``sphere``, ``torus7``, ``rp2``, ``edge_flip``, …),
  plain functions returning lists of vertex tuples, come from :mod:`dhlb.strategies._seeds`;
* ``closed_surfaces``, ``closed_manifolds`` and ``balls`` are thin adapters that return the bare
  tuples the tests were written for — ``(triangles, χ, orientable)``, ``(simplices, name)`` and
  ``simplices`` — drawn from the same seeds as before (the public strategies return
  :class:`dhlb.strategies.Known` records and know a few more spaces);
* ``complexes`` and ``rich_complexes`` are test-only mixtures of the public strategies.
"""

from __future__ import annotations

from hypothesis import strategies as st

from dhlb import SimplicialComplex
from dhlb.strategies import *  # noqa: F403
from dhlb.strategies import balls as _balls
from dhlb.strategies import closed_manifolds as _closed_manifolds
from dhlb.strategies import closed_surfaces as _closed_surfaces
from dhlb.strategies import pure_simplex_lists, simplex_lists
from dhlb.strategies._seeds import (  # noqa: F401  (re-exported for the tests)
    ball,
    cone,
    connected_sum,
    cycle,
    edge_flip,
    join,
    klein_bottle,
    kuhn_cubes,
    mobius,
    octahedron,
    rp2,
    sphere,
    stellar_edge,
    stellar_simplex,
    suspension,
    torus7,
    torus_grid,
)


def complexes(**kwargs):
    """Random SimplicialComplex from :func:`dhlb.strategies.simplex_lists` (its keyword arguments)."""
    return simplex_lists(**kwargs).map(SimplicialComplex)


def closed_surfaces(max_moves: int = 6):
    """(triangles, χ, orientable) of the seven original seed surfaces, moved and relabeled."""
    return _closed_surfaces(max_moves=max_moves, _legacy=True).map(
        lambda k: (list(k.simplices), k.euler_characteristic, k.orientable))


def _legacy_name(k) -> str:
    if k.dim == 2:
        return k.seed  # "sphere", "octahedron", "torus7", "torus3x4", "klein", "rp2", "genus2"
    return "torus" if k.name.startswith("T^") else "sphere"


def closed_manifolds(dim: int, max_moves: int = 3):
    """(top simplices, name): spheres, the 3-torus and the seed surfaces, moved and relabeled."""
    return _closed_manifolds(dim, max_moves=max_moves, _legacy=True).map(
        lambda k: (list(k.simplices), _legacy_name(k)))


def balls(dim: int, max_moves: int = 4):
    """Top simplices of a triangulated dim-ball, moved and relabeled."""
    return _balls(dim, max_moves=max_moves, _legacy=True).map(lambda k: list(k.simplices))


def rich_complexes(max_dim: int = 4):
    """Random complexes of dimension 2..max_dim with enough simplices to have loops and cycles."""
    options = [pure_simplex_lists(dim=2, max_vertices=8, min_size=4, max_size=18),
               simplex_lists(max_vertices=7, max_dim=max_dim, min_size=5, max_size=16)]
    if max_dim >= 3:
        options.append(pure_simplex_lists(dim=3, max_vertices=7, min_size=2, max_size=10))
    return st.one_of(*options).map(SimplicialComplex)
