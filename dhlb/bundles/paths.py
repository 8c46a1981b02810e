"""Loop-group generators and the π₁ presentation of a complex (edge paths and forests re-exported).

The graph primitives (:class:`SpanningForest`, :func:`spanning_forest`, :func:`bfs_forest`,
:func:`tree_accumulate`, :func:`edge_lookup`, :func:`path_edges`, :func:`tree_path_chains`,
:func:`fundamental_cycles`) live in :mod:`dhlb.topology.graph` and are re-exported here.

A *path* is a sequence of (compact) vertex indices in which consecutive vertices span an edge.
A spanning forest of the 1-skeleton has one root per connected component; every non-tree
edge ``e = (u, v)``, ``u < v``, gives one generator of the discrete path group at the root
(seed part 3, §4): the loop ``root → u`` (tree) ``→ v`` (along ``e``) ``→ root`` (tree).
Its abelianization is the 1-cycle ``chain(u) + e − chain(v)``; these *fundamental cycles*
form a Z-basis of ker ∂₁.  Relators of π₁ come from the 2-simplices.

Values along tree paths (transport matrices, angles, depths) are accumulated by pointer
jumping: ``O(n log depth)`` vectorized work, no Python loop over vertices.

Examples
--------
>>> from dhlb import SimplicialComplex
>>> X = SimplicialComplex([(0, 1), (1, 2), (0, 2), (2, 3)])
>>> T = spanning_forest(X)
>>> T.roots.tolist(), T.nontree.tolist()
([0], [2])
>>> fundamental_cycles(X, T).toarray().tolist()     # the triangle loop 0 -> 1 -> 2 -> 0
[[1, -1, 1, 0]]
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from dhlb.topology.graph import (
    SpanningForest,
    bfs_forest,
    edge_lookup,
    fundamental_cycles,
    path_edges,
    spanning_forest,
    tree_accumulate,
    tree_path_chains,
)

if TYPE_CHECKING:
    from dhlb.topology.complex import SimplicialComplex

__all__ = [
    "SpanningForest",
    "spanning_forest",
    "bfs_forest",
    "tree_accumulate",
    "edge_lookup",
    "path_edges",
    "tree_path_chains",
    "fundamental_cycles",
    "LoopGroupPresentation",
    "loop_group_presentation",
]  # all but the last two live in dhlb.topology.graph (re-exported here)


@dataclass(frozen=True)
class LoopGroupPresentation:
    """Presentation of π₁ of each component: free generators and relator words.

    Every parameter is kept as the attribute of the same name.

    Parameters
    ----------
    base : (c,) int64 array
        Base vertex per component.
    generators : (m,) int64 array
        Edge row of generator ``g`` (the non-tree edge ``(u, v)``, ``u < v``; loop
        ``base → u → v → base``).
    generator_component : (m,) int64 array
        Component of each generator.
    relators : list of lists of ``(g, ±1)``
        The word of the loop ``a → b → c → a`` around each triangle ``a < b < c`` (order of
        ``X.simplices(2)``), tree edges omitted.

    Examples
    --------
    >>> from dhlb.examples import torus
    >>> X = torus()
    >>> P = loop_group_presentation(X, spanning_forest(X))
    >>> P.n_generators, len(P.relators), P.base.tolist()
    (15, 14, [0])
    """

    base: np.ndarray
    generators: np.ndarray
    generator_component: np.ndarray
    relators: list

    @property
    def n_generators(self) -> int:
        """Number of generators (non-tree edges)."""
        return int(self.generators.size)


def loop_group_presentation(X: SimplicialComplex, forest: SpanningForest) -> LoopGroupPresentation:
    """Generators (non-tree edges) and relators (triangles) of π₁(X) at the forest roots.

    Parameters
    ----------
    X : SimplicialComplex
        Any complex.
    forest : SpanningForest
        A spanning forest of the whole 1-skeleton of ``X`` (:func:`spanning_forest` without
        ``edges``); its roots are the base points.

    Returns
    -------
    LoopGroupPresentation
        One generator per non-tree edge, one relator per triangle (none when ``X.dim < 2``).

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1, 2)])
    >>> P = loop_group_presentation(X, spanning_forest(X))
    >>> P.generators.tolist(), P.relators
    ([2], [[(0, 1)]])
    """
    gen_of = np.full(X.n_simplices(1), -1, np.int64)
    gen_of[forest.nontree] = np.arange(forest.nontree.size)
    relators = []
    if X.dim >= 2:
        f = X.faces(2)  # columns: (b,c), (a,c), (a,b)
        seq = np.stack([gen_of[f[:, 2]], gen_of[f[:, 0]], gen_of[f[:, 1]]], axis=1)
        signs = (1, 1, -1)
        for row in seq.tolist():
            relators.append([(g, s) for g, s in zip(row, signs) if g >= 0])
    E = X.simplices(1)
    return LoopGroupPresentation(
        base=forest.roots,
        generators=forest.nontree,
        generator_component=forest.component[E[forest.nontree, 0]] if forest.nontree.size else np.zeros(0, np.int64),
        relators=relators,
    )
