"""Pseudomanifold / manifold checks, orientation, consistency of user orientations."""

from collections import Counter
from itertools import combinations

import networkx as nx
import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from dhlb import SimplicialComplex
from dhlb.errors import InvalidSimplexError, NonManifoldError, NonOrientableError, SimplexNotFoundError
from dhlb.topology.manifold import (
    fundamental_cycle,
    is_consistently_oriented,
    is_manifold,
    is_orientable,
    is_pseudomanifold,
    manifold_report,
    orientation,
    require_manifold,
)
from dhlb.topology.structure import boundary_complex, connected_components
from tests.strategies import (
    balls,
    closed_manifolds,
    closed_surfaces,
    complexes,
    cone,
    klein_bottle,
    kuhn_cubes,
    mobius,
    octahedron,
    pure_simplex_lists,
    rp2,
    sphere,
    suspension,
    torus7,
    torus_grid,
)

# ---------------------------------------------------------------------------- brute-force references


def closure(tops):
    return {f for s in tops for r in range(1, len(s) + 1) for f in combinations(sorted(s), r)}


def chi(S):
    return sum((-1) ** (len(s) - 1) for s in S)


def connected(S):
    g = nx.Graph()
    g.add_nodes_from(s[0] for s in S if len(s) == 1)
    g.add_edges_from(s for s in S if len(s) == 2)
    return g.number_of_nodes() > 0 and nx.is_connected(g)


def vertex_link(S, v):
    return {tuple(x for x in s if x != v) for s in S if v in s and len(s) > 1}


def sphere_or_ball(S, d):
    """'sphere', 'ball' or None for a closed set S of simplices; d <= 2, straight from the definition."""
    tops = [s for s in S if len(s) == d + 1]
    if not S or max(map(len, S)) != d + 1 or closure(tops) != S:
        return None
    if d == 0:
        return {1: "ball", 2: "sphere"}.get(len(tops))
    ridges = Counter(f for t in tops for f in combinations(t, d))
    if not connected(S) or max(ridges.values()) > 2:
        return None
    if any(sphere_or_ball(vertex_link(S, v), d - 1) is None for (v,) in (s for s in S if len(s) == 1)):
        return None
    boundary = 1 in ridges.values()
    if d == 1:
        return "ball" if boundary else "sphere"
    return {(True, 1): "ball", (False, 2): "sphere"}.get((boundary, chi(S)))


def simplex_set(X):
    return {tuple(X.vertex_labels[r].tolist()) for k in range(X.dim + 1) for r in X.simplices(k)}


def brute_is_manifold(X):
    S, n = simplex_set(X), X.dim
    return n == 0 or all(sphere_or_ball(vertex_link(S, v), n - 1) for (v,) in (s for s in S if len(s) == 1))


def brute_pseudomanifold(X):
    S, n = simplex_set(X), X.dim
    if n == 0:
        return X.n_vertices <= 2
    tops = [s for s in S if len(s) == n + 1]
    ridges = Counter(f for t in tops for f in combinations(t, n))
    if closure(tops) != S or max(ridges.values()) > 2:
        return False
    g = nx.Graph()
    g.add_nodes_from(tops)
    g.add_edges_from((a, b) for a, b in combinations(tops, 2) if len(set(a) & set(b)) == n)
    return nx.is_connected(g)


def brute_orientable(X):
    n, m = X.dim, X.n_simplices(X.dim)
    if n == 0:
        return True
    B = X.boundary(n).toarray()
    cof = np.abs(B).sum(axis=1)
    if not X.is_pure or cof.max() > 2:
        return False
    signs = 1 - 2 * ((np.arange(2 ** m)[:, None] >> np.arange(m)) & 1)
    return bool(np.any(np.all((signs @ B.T)[:, cof == 2] == 0, axis=1)))


def shifted(simplices, by=10):
    return [tuple(v + by for v in s) for s in simplices]


# ---------------------------------------------------------------------------- known examples
CASES = {  # name: (simplices, manifold, pseudomanifold, orientable, has boundary)
    "S2": (sphere(2), True, True, True, False),
    "octahedron": (octahedron(), True, True, True, False),
    "torus": (torus7(), True, True, True, False),
    "rp2": (rp2(), True, True, False, False),
    "klein": (klein_bottle(4, 3), True, True, False, False),
    "mobius": (mobius(), True, True, False, True),
    "disk": ([(0, 1, 2), (0, 2, 3)], True, True, True, True),
    "two triangles at a vertex": ([(0, 1, 2), (0, 3, 4)], False, False, True, True),
    "three triangles on an edge": ([(0, 1, 2), (0, 1, 3), (0, 1, 4)], False, False, False, True),
    "two spheres": (sphere(2) + shifted(sphere(2)), True, False, True, False),
    "pinched spheres": (sphere(2) + shifted(sphere(2), 3), False, False, True, False),
    "triangle with a tail": ([(0, 1, 2), (2, 3)], False, False, False, True),
    "cone over torus": (cone(torus7()), False, True, True, True),
    "suspended torus": (suspension(torus7()), False, True, True, False),
    "S3": (sphere(3), True, True, True, False),
    "3-torus": (kuhn_cubes((3, 3, 3), periodic=True), True, True, True, False),
    "3-ball": (kuhn_cubes((2, 1, 1)), True, True, True, True),
    "cone over rp2": (cone(rp2()), False, True, False, True),
    "S4": (sphere(4), True, True, True, False),
    "4-ball": (kuhn_cubes((2, 1, 1, 1)), True, True, True, True),
    "cone over 3-torus": (cone(kuhn_cubes((3, 3, 3), periodic=True)), False, True, True, True),
    "suspended S3": (suspension(sphere(3)), True, True, True, False),
    "circle": ([(0, 1), (1, 2), (0, 2)], True, True, True, False),
    "Y graph": ([(0, 1), (0, 2), (0, 3)], False, False, False, True),
    "two points": ([(0,), (5,)], True, True, True, False),
    "three points": ([(0,), (1,), (2,)], True, False, True, False),
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_known_examples(name):
    simplices, manifold, pseudo, orientable, boundary = CASES[name]
    X = SimplicialComplex(shifted(simplices, 3))
    rep = manifold_report(X)
    assert (is_manifold(X), rep.is_manifold, is_pseudomanifold(X), is_orientable(X)) == \
        (manifold, manifold, pseudo, orientable)
    assert rep.is_pseudomanifold == pseudo
    assert rep.has_boundary == boundary
    assert (rep.first() is None) == manifold
    if X.dim <= 3:
        assert brute_is_manifold(X) == manifold
    assert brute_pseudomanifold(X) == pseudo
    if X.n_simplices(X.dim) <= 14:
        assert brute_orientable(X) == orientable


@pytest.mark.parametrize("name, simplices, k, culprit, text", [
    ("two triangles at a vertex", [(0, 1, 2), (0, 3, 4)], 0, (10,), "2 connected components"),
    ("three triangles on an edge", [(0, 1, 2), (0, 1, 3), (0, 1, 4)], 1, (10, 11), "face of 3 triangles"),
    ("cone over torus", cone(torus7()), 0, (17,), "Euler characteristic 0"),
    ("triangle with a tail", [(0, 1, 2), (2, 3)], 1, (12, 13), "not pure"),
    ("cone over 3-torus", cone(kuhn_cubes((3, 3, 3), periodic=True)), 0, (37,), "integer homology"),
    ("pinched spheres", sphere(2) + shifted(sphere(2), 3), 0, (13,), "2 connected components"),
])
def test_require_manifold_names_the_simplex(name, simplices, k, culprit, text):
    X = SimplicialComplex(shifted(simplices))
    with pytest.raises(NonManifoldError, match=text) as info:
        require_manifold(X)
    assert info.value.simplex == culprit and info.value.k == k
    assert str(culprit) in str(info.value)
    assert info.value.report.first().simplex == culprit


# ---------------------------------------------------------------------------- random complexes
@settings(max_examples=60)
@given(complexes(max_vertices=6, max_dim=3, min_size=2, max_size=8)
       | pure_simplex_lists(dim=2, max_vertices=6, min_size=3).map(SimplicialComplex)
       | pure_simplex_lists(dim=3, max_vertices=7, min_vertices=6, min_size=3).map(SimplicialComplex)
       | pure_simplex_lists(dim=1, max_vertices=6, min_size=2).map(SimplicialComplex))
def test_checks_agree_with_definitions(X):
    assert is_manifold(X) == brute_is_manifold(X)
    assert is_pseudomanifold(X) == brute_pseudomanifold(X)
    assume(X.n_simplices(X.dim) <= 14)
    assert is_orientable(X) == brute_orientable(X)


def check_orientation(X, o):
    n = X.dim
    assert o.dtype == np.int64 and set(np.unique(o)) <= {-1, 1}
    cof = np.bincount(np.asarray(X.faces(n)).ravel(), minlength=X.n_simplices(n - 1))
    d = X.boundary(n) @ o
    assert np.all(d[cof == 2] == 0)  # interior faces cancel
    assert np.all(np.abs(d[cof == 1]) == 1)
    _, lab = connected_components(X)
    comp = lab[X.simplices(n)[:, 0]]
    _, first = np.unique(comp, return_index=True)
    assert np.all(o[first] == 1)


@settings(max_examples=30)
@given(closed_surfaces())
def test_random_closed_surfaces(case):
    tris, euler, orientable = case
    X = SimplicialComplex(tris)
    assert X.euler_characteristic == euler
    assert is_manifold(X) and is_pseudomanifold(X) and not manifold_report(X).has_boundary
    assert boundary_complex(X) is None
    assert is_orientable(X) == orientable
    if orientable:
        check_orientation(X, orientation(X))
        assert not np.any(X.boundary(2) @ fundamental_cycle(X))
    else:
        with pytest.raises(NonOrientableError) as info:
            orientation(X)
        assert X.contains(1, [info.value.simplex])[0] and str(info.value.simplex) in str(info.value)
    holed = SimplicialComplex(tris[1:])  # remove a triangle: a surface with one boundary circle
    assert is_manifold(holed) and manifold_report(holed).has_boundary
    assert is_orientable(holed) == orientable
    assert boundary_complex(holed).counts == (3, 3)


@settings(max_examples=20)
@given(st.integers(1, 4).flatmap(lambda d: closed_manifolds(d, max_moves=2)))
def test_random_closed_manifolds(case):
    simplices, name = case
    X = SimplicialComplex(simplices)
    rep = manifold_report(X)
    assert rep.is_manifold and rep.is_pseudomanifold and not rep.has_boundary
    if name in ("klein", "rp2"):
        assert not is_orientable(X)
    else:
        o = orientation(X)
        check_orientation(X, o)
        assert not np.any(X.boundary(X.dim) @ o)
    holed = SimplicialComplex(simplices[1:])
    assert is_manifold(holed) and manifold_report(holed).has_boundary


@settings(max_examples=12)
@given(st.integers(1, 4).flatmap(lambda d: balls(d, max_moves=3)))
def test_random_balls(simplices):
    X = SimplicialComplex(simplices)
    assert is_manifold(X) and manifold_report(X).has_boundary
    check_orientation(X, orientation(X))
    B = boundary_complex(X)
    assert B.euler_characteristic == 1 + (-1) ** (X.dim - 1)
    if X.dim > 1:
        assert is_manifold(B) and is_orientable(B)


@settings(max_examples=30)
@given(closed_surfaces() | st.tuples(pure_simplex_lists(dim=2, max_vertices=6), st.none(), st.none()),
       st.randoms(use_true_random=False))
def test_relabeling_invariance(case, rnd):
    X = SimplicialComplex(case[0])
    perm = np.array(rnd.sample(range(3 * X.n_vertices), X.n_vertices))
    Y = SimplicialComplex(perm[X.simplices(X.dim)])
    assert (is_manifold(X), is_pseudomanifold(X), is_orientable(X)) == \
        (is_manifold(Y), is_pseudomanifold(Y), is_orientable(Y))
    if is_orientable(X):
        images = perm[X.simplices(2)]
        ratio = orientation(Y)[Y.index(2, images)] * SimplicialComplex.orientation_of(images) * orientation(X)
        _, lab = connected_components(X)
        comp = lab[X.simplices(2)[:, 0]]
        for c in np.unique(comp):  # the same orientation class, up to one sign per component
            assert len(set(ratio[comp == c].tolist())) == 1


@settings(max_examples=25)
@given(closed_surfaces(), st.data())
def test_is_consistently_oriented(case, data):
    tris, _, orientable = case
    assume(orientable)
    X = SimplicialComplex(tris)
    F = X.vertex_labels[X.simplices(2)].copy()
    o = orientation(X)
    F[o < 0] = F[o < 0][:, [1, 0, 2]]
    order = data.draw(st.permutations(range(len(F))))
    F = F[order]
    assert is_consistently_oriented(X, F) == (True, None)
    i = data.draw(st.integers(0, len(F) - 1))
    F[i] = F[i][::-1]
    ok, edge = is_consistently_oriented(X, F)
    assert not ok and set(edge) < set(F[i].tolist()) and X.contains(1, [edge])[0]


def test_orientation_examples_and_errors():
    X = SimplicialComplex(shifted(torus_grid(3, 3)))
    check_orientation(X, orientation(X))
    with pytest.raises(NonOrientableError, match="not orientable") as info:
        orientation(SimplicialComplex(shifted(mobius())))
    assert len(info.value.simplex) == 2 and min(info.value.simplex) >= 10
    with pytest.raises(NonManifoldError, match=r"\(10, 11\) .* face of 3 triangles") as info:
        orientation(SimplicialComplex(shifted([(0, 1, 2), (0, 1, 3), (0, 1, 4)])))
    assert info.value.simplex == (10, 11)
    with pytest.raises(NonManifoldError, match=r"edge \(12, 13\)"):
        orientation(SimplicialComplex(shifted([(0, 1, 2), (2, 3)])))
    two = SimplicialComplex(sphere(2) + shifted(sphere(2)))
    o = orientation(two)
    check_orientation(two, o)
    assert o[0] == 1 and o[4] == 1
    assert orientation(SimplicialComplex([(3,), (8,)])).tolist() == [1, 1]
    assert X.orientation().tolist() == orientation(X).tolist()


def test_consistency_bad_input():
    X = SimplicialComplex([(0, 1, 2), (0, 1, 3), (0, 1, 4), (2, 3, 4)])
    with pytest.raises(InvalidSimplexError, match=r"rows 0 and 2 .* \(0, 1, 2\)"):
        is_consistently_oriented(X, [(0, 1, 2), (2, 3, 4), (2, 1, 0)])
    with pytest.raises(NonManifoldError, match=r"edge \(0, 1\) .* shared by 3 rows"):
        is_consistently_oriented(X, [(0, 1, 2), (0, 1, 3), (0, 1, 4)])
    with pytest.raises(SimplexNotFoundError, match=r"\(1, 2, 3\)"):
        is_consistently_oriented(X, [(1, 2, 3)])
    with pytest.raises(InvalidSimplexError):
        is_consistently_oriented(X, [(0, 1)])


def test_medium_tet_mesh():
    X = SimplicialComplex(kuhn_cubes((12, 12, 12)))
    rep = manifold_report(X)
    assert rep.is_manifold and rep.is_pseudomanifold and rep.has_boundary
    check_orientation(X, orientation(X))
    assert boundary_complex(X).euler_characteristic == 2
