"""The bridge to `networkx <https://networkx.org>`_ (extra ``dhlb[graph]``): complexes from graphs, graphs of complexes.

* :func:`flag_complex`: the clique (flag) complex of a graph, its k-simplices the (k+1)-cliques.
* :func:`skeleton_graph`: the 1-skeleton of a complex as a graph.
* :func:`dual_graph`: the top simplices of a complex, adjacent when they share a codimension-1 face.

These are the methods :meth:`SimplicialComplex.from_graph
<dhlb.topology.complex.SimplicialComplex.from_graph>` (which also gives the node list) and
:meth:`SimplicialComplex.to_networkx <dhlb.topology.complex.SimplicialComplex.to_networkx>`
as functions; the cliques are enumerated by :mod:`dhlb.topology.cliques`, the graphs read and
built in ``dhlb.topology._graphs``. networkx is imported inside the functions only
(``import dhlb.topology`` does not load it); without it every function raises an
``ImportError`` that names the extra to install.

Examples
--------
>>> import networkx as nx
>>> from dhlb.topology.networkx_bridge import dual_graph, flag_complex, skeleton_graph
>>> X, nodes = flag_complex(nx.octahedral_graph())      # the octahedron: a 2-sphere
>>> X.counts, X.euler_characteristic
((6, 12, 8), 2)
>>> D = dual_graph(X)                                   # the cube graph
>>> sorted({d for _, d in D.degree()}), nx.is_connected(D)
([3], True)
>>> nx.is_isomorphic(skeleton_graph(X), nx.octahedral_graph())
True
"""

from __future__ import annotations

from dhlb.errors import InvalidTypeError
from dhlb.topology._graphs import NETWORKX_EXTRA, require_networkx
from dhlb.topology.complex import SimplicialComplex

__all__ = ["NETWORKX_EXTRA", "require_networkx", "flag_complex", "skeleton_graph", "dual_graph"]


# ---------------------------------------------------------------------------- graph -> complex
def flag_complex(G, max_dim: int | None = None) -> tuple[SimplicialComplex, list]:
    """The clique (flag) complex of a graph: its k-simplices are the (k+1)-cliques of ``G``, k <= ``max_dim``.

    Vertex ``i`` of the complex is the node ``list(G.nodes)[i]`` (the graph's node order, i.e.
    insertion order); that list is returned as ``nodes``, so ``nodes[v]`` maps any vertex index
    back to its node and ``X.vertex_labels`` is ``0 .. n-1``. Every node is a vertex, isolated
    nodes included.

    Parameters
    ----------
    G : networkx.Graph, DiGraph, MultiGraph or MultiDiGraph
        Any hashable nodes. A directed graph is taken undirected (``u ~ v`` when ``u → v`` or
        ``v → u``), parallel edges of a multigraph count once: the flag complex depends on the
        adjacency only. Edge and node attributes are ignored. Any object with ``.nodes`` and
        ``.edges`` is read the same way.
    max_dim : int >= 0, optional
        The largest simplex dimension kept (the complex is the ``max_dim``-skeleton of the full
        flag complex). Default: the clique number of ``G`` minus one, i.e. every clique.

    Returns
    -------
    X : SimplicialComplex
        The flag complex, ``X.dim <= max_dim``.
    nodes : list, length n
        ``list(G.nodes)``: the node of each vertex index.

    Raises
    ------
    ImportError
        networkx is not installed (the message names ``pip install "dhlb[graph]"``).
    InvalidTypeError
        ``G`` has no ``.nodes`` or no ``.edges`` (it is not a networkx graph), or ``max_dim`` is
        not an integer.
    InvalidParameterError
        ``max_dim`` is negative.
    InvalidSimplexError
        ``G`` has a self-loop (a simplex cannot repeat a vertex); the message names the node.
    EmptyComplexError
        ``G`` has no nodes.

    Notes
    -----
    The cliques are enumerated by :func:`~dhlb.topology.cliques.maximal_cliques`, level by level,
    vectorised: vertices are ranked by degree, every
    edge points from the lower to the higher rank, and two k-cliques that agree but for their last
    (highest-rank) vertex make a (k+1)-clique when their last vertices are adjacent. Ranking by
    degree bounds the out-degrees by ``sqrt(2 |E|)`` (a star with a million leaves has no
    candidate triangle). Only the maximal cliques (and the ``max_dim``-cliques) are handed to
    :class:`~dhlb.topology.complex.SimplicialComplex`, which adds their faces. On a random
    geometric graph with 10,000 nodes and 61,736 edges (radius 0.02, clique number 15) this takes
    0.13–0.17 s for ``max_dim=2`` (224k simplices; ``networkx.find_cliques``, truncated and built
    the same way: 0.5 s) and 1.1–1.2 s for the whole complex (1.1 million simplices;
    ``find_cliques``, whose cliques are maximal already: 0.9 s; ``enumerate_all_cliques``: 9 s).

    Examples
    --------
    >>> import networkx as nx
    >>> X, nodes = flag_complex(nx.cycle_graph(5))          # a 5-cycle has no triangle: a circle
    >>> X.counts, X.euler_characteristic
    ((5, 5), 0)
    >>> X, nodes = flag_complex(nx.complete_graph(5), max_dim=2)
    >>> X.counts
    (5, 10, 10)
    >>> G = nx.Graph([("a", "b"), ("b", "c"), ("c", "a"), ("c", "d")])
    >>> X, nodes = flag_complex(G)
    >>> nodes, [[nodes[v] for v in s] for s in X.simplices(2)]
    (['a', 'b', 'c', 'd'], [['a', 'b', 'c']])
    """
    require_networkx()
    return SimplicialComplex.from_graph(G, max_dim=max_dim), list(G.nodes)


# ---------------------------------------------------------------------------- complex -> graph
def skeleton_graph(X: SimplicialComplex):
    """The 1-skeleton of a complex as a ``networkx.Graph``.

    Parameters
    ----------
    X : SimplicialComplex
        Any complex (of dimension 0 too: then the graph has no edges).

    Returns
    -------
    networkx.Graph
        Nodes ``0 .. X.n_vertices - 1`` (vertex indices; ``X.vertex_labels[v]`` is the input
        label of node ``v``), every vertex included; one edge per edge of ``X``, with the edge
        attribute ``'index'``: its row in ``X.simplices(1)``.

    Raises
    ------
    ImportError
        networkx is not installed (the message names ``pip install "dhlb[graph]"``).
    InvalidTypeError
        ``X`` is not a :class:`~dhlb.topology.complex.SimplicialComplex`.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> S = skeleton_graph(SimplicialComplex([(0, 1, 2), (2, 3), (4,)]))
    >>> sorted(S.nodes), sorted(S.edges(data="index"))
    ([0, 1, 2, 3, 4], [(0, 1, 0), (0, 2, 1), (1, 2, 2), (2, 3, 3)])
    """
    _check_complex(X, "skeleton_graph")
    return X.to_networkx("skeleton")


def dual_graph(X: SimplicialComplex):
    """The dual graph: the top simplices of a complex, adjacent when they share a codimension-1 face.

    "Top" means of dimension ``X.dim``; in a non-pure complex the lower-dimensional maximal
    simplices are not nodes (take :meth:`~dhlb.topology.complex.SimplicialComplex.skeleton` or a
    pure subcomplex first if they matter). Two distinct n-simplices share at most one
    (n-1)-face, so the graph is simple: a face with ``c`` top cofaces gives ``c(c-1)/2`` edges
    (one for an interior face of a pseudomanifold, none for a boundary face, a triangle of edges
    for a face with three cofaces). For ``X.dim == 0`` the nodes are the vertices and there are
    no edges.

    Parameters
    ----------
    X : SimplicialComplex
        Any complex; pure or a pseudomanifold for the usual dual graph.

    Returns
    -------
    networkx.Graph
        Nodes ``0 .. X.n_simplices(X.dim) - 1`` (rows of ``X.simplices(X.dim)``); edge attribute
        ``'face'``: the row in ``X.simplices(X.dim - 1)`` of the shared face.

    Raises
    ------
    ImportError
        networkx is not installed (the message names ``pip install "dhlb[graph]"``).
    InvalidTypeError
        ``X`` is not a :class:`~dhlb.topology.complex.SimplicialComplex`.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1, 2), (1, 2, 3), (2, 3, 4), (5, 6)])   # a strip of 3 triangles, an edge
    >>> D = dual_graph(X)
    >>> sorted(D.nodes), sorted(D.edges(data="face"))
    ([0, 1, 2], [(0, 1, 2), (1, 2, 4)])
    >>> X.simplices(1)[[2, 4]].tolist()                      # the shared edges
    [[1, 2], [2, 3]]
    """
    _check_complex(X, "dual_graph")
    return X.to_networkx("dual")


def _check_complex(X, name: str) -> None:
    """Raise :class:`~dhlb.errors.InvalidTypeError` unless ``X`` is a SimplicialComplex."""
    if not isinstance(X, SimplicialComplex):
        raise InvalidTypeError(f"{name} needs a SimplicialComplex, got {type(X).__name__}")
