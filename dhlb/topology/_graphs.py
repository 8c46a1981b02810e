"""Graphs in and out of complexes: reading a graph object, building networkx graphs of a complex.

:func:`read_graph` reads any object shaped like a networkx graph (``.nodes`` and ``.edges``) into
a node list and an edge array, for
:meth:`SimplicialComplex.from_graph <dhlb.topology.complex.SimplicialComplex.from_graph>`;
:func:`skeleton_graph` and :func:`dual_graph` build the graphs of
:meth:`SimplicialComplex.to_networkx <dhlb.topology.complex.SimplicialComplex.to_networkx>`,
importing networkx at call time (:func:`require_networkx`). The public functions are in
:mod:`dhlb.topology.networkx_bridge`; this module does not import :mod:`dhlb.topology.complex`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from dhlb._install import install_hint
from dhlb.errors import EmptyComplexError, InvalidSimplexError, InvalidTypeError
from dhlb.topology.cliques import group_pairs

if TYPE_CHECKING:
    from dhlb.topology._protocol import ComplexLike

__all__ = ["NETWORKX_EXTRA", "require_networkx", "read_graph", "skeleton_graph", "dual_graph"]

NETWORKX_EXTRA = f"networkx is not installed: {install_hint('networkx', 'graph')}"
"""The message of the ``ImportError`` raised when networkx is missing."""


def require_networkx():
    """The ``networkx`` module, or an ``ImportError`` naming the extra ``dhlb[graph]``.

    Returns
    -------
    module
        ``networkx``.

    Raises
    ------
    ImportError
        networkx is not installed; the message is :data:`NETWORKX_EXTRA`.
    """
    try:
        import networkx
    except ImportError:
        raise ImportError(NETWORKX_EXTRA) from None
    return networkx


def read_graph(G) -> tuple[list, np.ndarray]:
    """The nodes of a graph and its edges as rows of node indices (no networkx needed).

    Parameters
    ----------
    G : networkx.Graph, DiGraph, MultiGraph, MultiDiGraph, or any object like them
        Read through ``G.nodes`` (iterable of hashable nodes) and ``G.edges()`` (or ``G.edges``:
        iterable of tuples whose first two entries are the end nodes; further entries, such as
        the keys of a multigraph, are ignored).

    Returns
    -------
    nodes : list, length n
        ``list(G.nodes)``: node ``i`` is vertex ``i``.
    edges : (m, 2) int64 array
        The edges as ``(index of u, index of v)``, in the graph's order, repeats kept.

    Raises
    ------
    InvalidTypeError
        ``G`` has no ``.nodes`` or no ``.edges``.
    EmptyComplexError
        ``G`` has no nodes.
    InvalidSimplexError
        An edge end is not a node of ``G``, or ``G`` has a self-loop (the message names the node).

    Examples
    --------
    >>> class Graph:   # anything with .nodes and .edges
    ...     nodes = ["a", "b", "c"]
    ...     edges = [("a", "b"), ("c", "b")]
    >>> nodes, E = read_graph(Graph())
    >>> nodes, E.tolist()
    (['a', 'b', 'c'], [[0, 1], [2, 1]])
    """
    if not (hasattr(G, "nodes") and hasattr(G, "edges")):
        raise InvalidTypeError(f"from_graph needs a networkx graph (an object with .nodes and .edges), "
                               f"got {type(G).__name__}")
    nodes = list(G.nodes)
    if not nodes:
        raise EmptyComplexError("the graph has no nodes; its flag complex would be empty")
    index = {v: i for i, v in enumerate(nodes)}
    pairs = G.edges() if callable(G.edges) else G.edges  # called: a multigraph's edges without their keys
    try:
        E = np.fromiter((index[w] for e in pairs for w in e[:2]), np.int64).reshape(-1, 2)
    except KeyError as exc:
        raise InvalidSimplexError(f"an edge ends at {exc.args[0]!r}, which is not a node of the graph") from None
    loops = E[:, 0] == E[:, 1]
    if np.any(loops):
        v = nodes[int(E[np.argmax(loops), 0])]
        raise InvalidSimplexError(f"the graph has a self-loop at node {v!r}; a flag complex has none "
                                  "(remove them: G.remove_edges_from(nx.selfloop_edges(G)))")
    return nodes, E


def skeleton_graph(X: ComplexLike):
    """The 1-skeleton of a complex as a ``networkx.Graph`` (documented in :mod:`dhlb.topology.networkx_bridge`).

    Parameters
    ----------
    X : SimplicialComplex
        Any complex.

    Returns
    -------
    networkx.Graph
        Nodes ``0 .. X.n_vertices - 1``; one edge per edge of ``X``, edge attribute ``'index'``.

    Raises
    ------
    ImportError
        networkx is not installed (the message is :data:`NETWORKX_EXTRA`).
    """
    nx = require_networkx()
    S = nx.Graph()
    S.add_nodes_from(range(X.n_vertices))
    S.add_edges_from((int(u), int(v), {"index": e}) for e, (u, v) in enumerate(X.simplices(1).tolist()))
    return S


def dual_graph(X: ComplexLike):
    """The top simplices, adjacent when they share a codimension-1 face (see :mod:`dhlb.topology.networkx_bridge`).

    Parameters
    ----------
    X : SimplicialComplex
        Any complex.

    Returns
    -------
    networkx.Graph
        Nodes ``0 .. X.n_simplices(X.dim) - 1``; edge attribute ``'face'``: the shared face's row.

    Raises
    ------
    ImportError
        networkx is not installed (the message is :data:`NETWORKX_EXTRA`).
    """
    nx = require_networkx()
    n = X.dim
    D = nx.Graph()
    D.add_nodes_from(range(X.n_simplices(n)))
    if n == 0:
        return D
    flat = np.asarray(X.faces(n)).ravel()  # flat position = top * (n+1) + local position
    order = np.argsort(flat, kind="stable")
    face = flat[order]
    starts = np.flatnonzero(np.r_[True, face[1:] != face[:-1]])
    a, b = group_pairs(starts, np.diff(np.r_[starts, face.size]))
    D.add_edges_from(zip((order[a] // (n + 1)).tolist(), (order[b] // (n + 1)).tolist(),
                         ({"face": f} for f in face[a].tolist())))
    return D
