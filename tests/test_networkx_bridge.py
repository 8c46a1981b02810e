"""dhlb.topology.networkx_bridge: flag complexes against networkx's clique enumeration; skeleton and dual graphs."""

import subprocess
import sys
from itertools import combinations
from math import comb

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from dhlb import SimplicialComplex, examples
from dhlb.errors import EmptyComplexError, InvalidParameterError, InvalidSimplexError, InvalidTypeError
from dhlb.topology import cliques
from dhlb.topology.networkx_bridge import NETWORKX_EXTRA, dual_graph, flag_complex, skeleton_graph
from tests.strategies import closed_surfaces, complexes

nx = pytest.importorskip("networkx")


@st.composite
def graphs(draw, max_nodes=12):
    """A simple graph on <= max_nodes nodes (integers, spread integers or strings, inserted in a random order)."""
    n = draw(st.integers(1, max_nodes))
    names = draw(st.sampled_from([list(range(n)), [f"v{i}" for i in range(n)], [3 * i + 1 for i in range(n)]]))
    names = draw(st.permutations(names))
    pairs = list(combinations(range(n), 2))
    mode = draw(st.sampled_from(["sparse", "dense", "complete"]))
    if mode == "complete" or not pairs:
        keep = pairs
    elif mode == "dense":   # a complete graph less a few edges: many large cliques
        drop = draw(st.sets(st.sampled_from(pairs), max_size=max(1, len(pairs) // 4)))
        keep = [p for p in pairs if p not in drop]
    else:
        keep = draw(st.lists(st.sampled_from(pairs), unique=True))
    G = nx.Graph()
    G.add_nodes_from(names)
    G.add_edges_from((names[a], names[b]) for a, b in keep)
    return G


def simplices_as_nodes(X, nodes, k):
    """The k-simplices of X as frozensets of graph nodes."""
    return {frozenset(nodes[v] for v in row) for row in X.simplices(k).tolist()}


def cliques_by_size(G):
    out = {}
    for c in nx.enumerate_all_cliques(G):
        out.setdefault(len(c), set()).add(frozenset(c))
    return out


# ---------------------------------------------------------------------------- flag complex vs networkx
@given(graphs(), st.one_of(st.none(), st.integers(0, 5)))
def test_k_simplices_are_the_k_plus_1_cliques(G, max_dim):
    X, nodes = flag_complex(G, max_dim)
    assert nodes == list(G.nodes)
    assert X.vertex_labels.tolist() == list(range(G.number_of_nodes()))
    cliques = cliques_by_size(G)
    omega = max(cliques)
    top = omega - 1 if max_dim is None else min(max_dim, omega - 1)
    assert X.dim == top
    for k in range(top + 1):
        assert simplices_as_nodes(X, nodes, k) == cliques[k + 1], k
    assert X.n_simplices(top + 1) == 0


@given(graphs())
def test_round_trip_skeleton_is_the_graph(G):
    X, nodes = flag_complex(G)
    S = skeleton_graph(X)
    assert nx.is_isomorphic(S, G)
    back = nx.relabel_nodes(S, dict(enumerate(nodes)))
    assert set(back.nodes) == set(G.nodes)
    assert {frozenset(e) for e in back.edges} == {frozenset(e) for e in G.edges}
    E = X.simplices(1)
    for u, v, i in S.edges(data="index"):
        assert sorted((u, v)) == E[i].tolist()
    assert sorted(i for _, _, i in S.edges(data="index")) == list(range(len(E)))


@given(graphs(max_nodes=9), st.data())
def test_directed_and_multigraphs_are_read_as_their_simple_graph(G, data):
    X, _ = flag_complex(G)
    D = nx.DiGraph()
    D.add_nodes_from(G.nodes)
    flips = data.draw(st.lists(st.booleans(), min_size=G.number_of_edges(), max_size=G.number_of_edges()))
    D.add_edges_from((v, u) if flip else (u, v) for (u, v), flip in zip(G.edges, flips))   # random directions
    D.add_edges_from(list(G.edges)[::3])                                                # some both ways
    M = nx.MultiGraph(G)
    M.add_edges_from(list(G.edges)[::2])                                                # parallel edges
    assert flag_complex(D)[0] == X
    assert flag_complex(M)[0] == X
    assert flag_complex(nx.MultiDiGraph(D))[0] == X


def test_node_order_gives_the_vertex_numbering():
    G = nx.Graph()
    G.add_nodes_from(["z", 7, ("t", 1)])
    G.add_edges_from([("z", ("t", 1)), (7, "z")])
    X, nodes = flag_complex(G)
    assert nodes == ["z", 7, ("t", 1)]
    assert X.simplices(1).tolist() == [[0, 1], [0, 2]]   # z-7, z-(t,1)


@pytest.mark.parametrize("n", [4, 5, 6, 9, 30])
def test_cycle_graph_is_a_circle(n):
    X, _ = flag_complex(nx.cycle_graph(n))
    assert X.counts == (n, n)
    assert X.euler_characteristic == 0
    assert [str(h) for h in X.homology()] == ["Z", "Z"]


def test_triangle_graph_is_a_filled_triangle():
    X, _ = flag_complex(nx.cycle_graph(3))
    assert X.counts == (3, 3, 1) and X.euler_characteristic == 1


@pytest.mark.parametrize("n", [1, 2, 3, 4, 7, 12])
def test_complete_graph_truncated_at_dimension_2(n):
    X, _ = flag_complex(nx.complete_graph(n), max_dim=2)
    assert X.euler_characteristic == n - comb(n, 2) + comb(n, 3)
    assert X.counts == tuple(comb(n, k + 1) for k in range(min(3, n)))


@pytest.mark.parametrize("n", [1, 5, 10])
def test_complete_graph_is_a_simplex(n):
    X, _ = flag_complex(nx.complete_graph(n))
    assert X.dim == n - 1 and X.counts == tuple(comb(n, k + 1) for k in range(n))
    assert X.euler_characteristic == 1


def test_isolated_nodes_are_vertices_and_max_dim_zero_keeps_only_vertices():
    G = nx.path_graph(3)
    G.add_node(10)
    X, nodes = flag_complex(G)
    assert nodes == [0, 1, 2, 10] and X.counts == (4, 2)
    assert flag_complex(G, 0)[0].counts == (4,)
    assert flag_complex(nx.empty_graph(3))[0].counts == (3,)


def test_a_hub_costs_no_candidates(monkeypatch):
    """Ranking by degree: the centre of a big star has no out-neighbours, so no candidate triangle is tried."""
    tried = []

    def counting(starts, sizes):
        a, b = group_pairs(starts, sizes)
        tried.append(a.size)
        return a, b

    group_pairs = cliques.group_pairs
    monkeypatch.setattr(cliques, "group_pairs", counting)
    G = nx.star_graph(2_000)
    G.add_edges_from([(1, 2), (2, 3)])   # two triangles through the centre: 0-1-2, 0-2-3
    X, _ = flag_complex(G)
    assert X.counts == (2_001, 2_002, 2)
    assert tried[0] <= 3 and len(tried) == 2    # dimension 2: the pairs among the leaves' out-edges; 3: none


def test_random_geometric_graph_matches_networkx_maximal_cliques():
    G = nx.random_geometric_graph(400, 0.12, seed=3)
    X, nodes = flag_complex(G)
    assert X.dim == max(len(c) for c in nx.find_cliques(G)) - 1 >= 4
    maximal = {frozenset(nodes[v] for v in row) for rows in X.maximal_simplices() for row in rows.tolist()}
    assert maximal == {frozenset(c) for c in nx.find_cliques(G)}


# ---------------------------------------------------------------------------- errors
def test_self_loop_is_refused_and_named():
    G = nx.Graph([(0, 1), ("a", "a")])
    with pytest.raises(InvalidSimplexError, match="self-loop at node 'a'"):
        flag_complex(G)
    with pytest.raises(InvalidSimplexError):
        SimplicialComplex.from_graph(G)


def test_bad_arguments():
    with pytest.raises(EmptyComplexError):
        flag_complex(nx.Graph())
    with pytest.raises(InvalidParameterError, match="max_dim"):
        flag_complex(nx.path_graph(3), -1)
    for bad in (1.5, True, "2"):
        with pytest.raises(InvalidTypeError, match="max_dim"):
            flag_complex(nx.path_graph(3), bad)
    with pytest.raises(InvalidTypeError, match="networkx graph"):
        flag_complex([(0, 1)])
    with pytest.raises(InvalidTypeError, match="SimplicialComplex"):
        skeleton_graph(nx.path_graph(3))
    with pytest.raises(InvalidTypeError, match="SimplicialComplex"):
        dual_graph([(0, 1, 2)])
    with pytest.raises(InvalidParameterError, match=r"\('clique',\).*'vietoris'"):
        SimplicialComplex.from_graph(nx.path_graph(3), kind="vietoris")
    with pytest.raises(InvalidParameterError, match=r"\('skeleton', 'dual'\).*'flag'"):
        examples.torus().to_networkx("flag")


def test_missing_networkx_names_the_extra(monkeypatch):
    X = examples.torus()
    monkeypatch.setitem(sys.modules, "networkx", None)   # `import networkx` now raises ImportError
    for call in (lambda: flag_complex(None), lambda: skeleton_graph(X), lambda: dual_graph(X),
                 lambda: X.to_networkx(), lambda: X.to_networkx("dual")):
        with pytest.raises(ImportError, match=r'pip install networkx .*pip install "\.\[graph\]"') as info:
            call()
        assert str(info.value) == NETWORKX_EXTRA


class PlainGraph:
    """A graph without networkx: nodes and an edges() method (a triangle a-b-c with a tail c-d)."""

    def __init__(self):
        self.nodes = ["a", "b", "c", "d"]

    def edges(self):
        return iter([("a", "b"), ("b", "c"), ("c", "a"), ("c", "d")])


def test_from_graph_reads_any_graph_like_object_without_networkx(monkeypatch):
    monkeypatch.setitem(sys.modules, "networkx", None)
    X = SimplicialComplex.from_graph(PlainGraph())
    assert X.counts == (4, 4, 1)
    assert X.simplices(2).tolist() == [[0, 1, 2]]
    with pytest.raises(InvalidTypeError, match="networkx graph"):
        SimplicialComplex.from_graph(None)
    G = PlainGraph()
    G.nodes = ["a", "b", "c"]                      # the tail ends at "d", not a node
    with pytest.raises(InvalidSimplexError, match=r"'d'.*not a node"):
        SimplicialComplex.from_graph(G)


def test_maximal_cliques_checks_its_arrays():
    assert [b.tolist() for b in cliques.maximal_cliques(3, np.zeros((0, 2), int))] == [[[0], [1], [2]]]
    with pytest.raises(InvalidSimplexError, match=r"outside 0 \.\. 2"):
        cliques.maximal_cliques(3, [[0, 3]])
    with pytest.raises(InvalidSimplexError, match="self-loop"):
        cliques.maximal_cliques(3, [[0, 1], [2, 2]])
    with pytest.raises(InvalidTypeError, match="edges"):
        cliques.maximal_cliques(3, [[0.0, 1.0]])
    with pytest.raises(InvalidTypeError, match="edges"):
        cliques.maximal_cliques(3, [0, 1, 2])
    with pytest.raises(InvalidParameterError, match="n must"):
        cliques.maximal_cliques(-1, [])


def test_importing_dhlb_topology_does_not_import_networkx():
    code = ("import sys, dhlb, dhlb.topology, dhlb.topology.networkx_bridge; "
            "X = dhlb.SimplicialComplex([(0, 1, 2)]); X.homology(); print('networkx' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split() == ["False"]


# ---------------------------------------------------------------------------- methods
@given(graphs(max_nodes=8), st.one_of(st.none(), st.integers(0, 3)))
def test_methods_are_the_bridge(G, max_dim):
    X = SimplicialComplex.from_graph(G, max_dim=max_dim)
    assert X == flag_complex(G, max_dim)[0]
    for kind, f in (("skeleton", skeleton_graph), ("dual", dual_graph)):
        H, K = X.to_networkx(kind), f(X)
        assert sorted(H.nodes) == sorted(K.nodes)
        assert sorted(H.edges(data=True)) == sorted(K.edges(data=True))
    assert sorted(X.to_networkx().edges) == sorted(skeleton_graph(X).edges)


# ---------------------------------------------------------------------------- dual graph
def check_faces(X, D):
    """Every dual edge joins two distinct top simplices whose shared codim-1 face is the 'face' attribute."""
    n = X.dim
    F = X.faces(n)
    for a, b, f in D.edges(data="face"):
        assert a != b
        assert set(F[a].tolist()) & set(F[b].tolist()) == {f}


def interior_face_count(X):
    counts = np.bincount(np.asarray(X.faces(X.dim)).ravel(), minlength=X.n_simplices(X.dim - 1))
    return int(np.sum(counts == 2)), counts


@pytest.mark.parametrize("X", [examples.torus(), examples.sphere(2), examples.torus_nd(2, 5), examples.klein_bottle(),
                               examples.projective_plane()], ids=["torus7", "S2", "torus5x5", "klein", "rp2"])
def test_dual_graph_of_a_closed_surface_is_3_regular_and_connected(X):
    D = dual_graph(X)
    assert D.number_of_nodes() == X.n_simplices(2)
    assert {d for _, d in D.degree()} == {3}
    assert nx.is_connected(D)
    assert D.number_of_edges() == X.n_simplices(1) == interior_face_count(X)[0]
    check_faces(X, D)


@given(closed_surfaces())
def test_dual_graph_of_random_closed_surfaces(surface):
    X = SimplicialComplex(surface[0])
    D = dual_graph(X)
    assert {d for _, d in D.degree()} == {3}
    assert nx.is_connected(D)
    assert D.number_of_edges() == interior_face_count(X)[0]


@pytest.mark.parametrize(("X", "interior"), [(examples.ball(2), 0), (examples.ball(3), 0),
                                             (examples.cube_nd(2, 3), None), (examples.cube_nd(3, 2), None),
                                             (examples.moebius_strip(), None)])
def test_dual_graph_edges_are_the_interior_faces(X, interior):
    D = dual_graph(X)
    n_interior, _ = interior_face_count(X)
    assert interior is None or n_interior == interior
    assert D.number_of_edges() == n_interior
    check_faces(X, D)


@given(complexes())
def test_dual_graph_of_any_complex(X):
    """Nodes are the X.dim-simplices; a face with c top cofaces gives c(c-1)/2 edges, each labelled by it."""
    D = dual_graph(X)
    assert sorted(D.nodes) == list(range(X.n_simplices(X.dim)))
    if X.dim == 0:
        assert D.number_of_edges() == 0
        return
    _, counts = interior_face_count(X)
    assert D.number_of_edges() == int(sum(comb(int(c), 2) for c in counts))
    check_faces(X, D)
    tops = X.simplices(X.dim).tolist()
    expected = {frozenset((a, b)) for a, b in combinations(range(len(tops)), 2)
                if len(set(tops[a]) & set(tops[b])) == X.dim}
    assert {frozenset(e) for e in D.edges} == expected


@given(complexes())
def test_skeleton_graph_of_any_complex(X):
    S = skeleton_graph(X)
    assert sorted(S.nodes) == list(range(X.n_vertices))
    assert sorted(tuple(sorted(e)) for e in S.edges) == [tuple(r) for r in X.simplices(1).tolist()]
    F, nodes = flag_complex(S)           # X lies in the flag complex of its 1-skeleton
    assert nodes == list(range(X.n_vertices))
    assert all(F.contains(k, X.simplices(k)).all() for k in range(X.dim + 1))
