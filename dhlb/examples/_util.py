"""Shared helpers of :mod:`dhlb.examples`: parameter checks and lattice-path tables."""

from __future__ import annotations

from itertools import combinations, permutations

import numpy as np

from dhlb.topology.complex import SimplicialComplex


def as_complex(X, name: str = "X") -> SimplicialComplex:
    """``X`` itself if it is a :class:`SimplicialComplex`, else ``SimplicialComplex(X)``."""
    if isinstance(X, SimplicialComplex):
        return X
    return SimplicialComplex(X)


def shuffle_paths(p: int, q: int) -> tuple[np.ndarray, np.ndarray]:
    """All monotone lattice paths from ``(0, 0)`` to ``(p, q)``.

    Returns ``(I, J)``, each of shape ``(binom(p+q, p), p+q+1)``: the first and second coordinate
    of the ``r``-th point of each path. Paths are listed in lexicographic order of the set of
    steps (0-based) that move the first coordinate.

    Examples
    --------
    >>> I, J = shuffle_paths(1, 1)
    >>> I.tolist(), J.tolist()
    ([[0, 1, 1], [0, 0, 1]], [[0, 0, 1], [0, 1, 1]])
    """
    steps = p + q
    choices = list(combinations(range(steps), p))
    x_steps = np.array(choices, dtype=np.int64).reshape(len(choices), p)
    is_x = np.zeros((x_steps.shape[0], steps), dtype=np.int64)
    np.put_along_axis(is_x, x_steps, 1, axis=1)
    zero = np.zeros((is_x.shape[0], 1), np.int64)
    I = np.concatenate([zero, np.cumsum(is_x, axis=1)], axis=1)
    J = np.concatenate([zero, np.cumsum(1 - is_x, axis=1)], axis=1)
    return I, J


def kuhn_paths(n: int) -> np.ndarray:
    """Corners of the unit n-cube along monotone paths, shape ``(n!, n+1, n)`` (0/1 entries).

    Path ``s`` visits ``0, e_{π(0)}, e_{π(0)} + e_{π(1)}, ..., (1, ..., 1)`` for the ``s``-th
    permutation ``π`` of ``range(n)`` in lexicographic order.

    Examples
    --------
    >>> kuhn_paths(2).tolist()
    [[[0, 0], [1, 0], [1, 1]], [[0, 0], [0, 1], [1, 1]]]
    """
    perm_list = list(permutations(range(n)))
    perms = np.array(perm_list, dtype=np.int64).reshape(len(perm_list), n)
    steps = np.zeros((perms.shape[0], n, n), dtype=np.int64)
    np.put_along_axis(steps, perms[:, :, None], 1, axis=2)  # steps[s, r] = e_{π(r)}
    zero = np.zeros((perms.shape[0], 1, n), np.int64)
    return np.concatenate([zero, np.cumsum(steps, axis=1)], axis=1)


def from_blocks(blocks: list[np.ndarray]) -> SimplicialComplex:
    """A complex from row blocks of possibly different widths (one array when they all agree)."""
    return SimplicialComplex([np.asarray(b, np.int64) for b in blocks])
