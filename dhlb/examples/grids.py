"""Freudenthal–Kuhn triangulations of the cube grid and of the periodic grid (flat torus) in any dimension."""

from __future__ import annotations

import numbers
from typing import TYPE_CHECKING

import numpy as np

from dhlb._coerce import check_int
from dhlb.errors import InvalidParameterError
from dhlb.examples._util import kuhn_paths
from dhlb.topology.complex import SimplicialComplex

if TYPE_CHECKING:
    from collections.abc import Sequence

__all__ = ["cube_nd", "torus_nd"]


def _cells_per_axis(n: int, m, minimum: int, why: str = "") -> tuple[int, ...]:
    if isinstance(m, numbers.Integral) and not isinstance(m, (bool, np.bool_)):
        return (check_int(m, "m", minimum, why=why),) * n
    try:
        seq = list(m)
    except TypeError:
        raise InvalidParameterError(f"m must be an integer or a sequence of {n} integers, got {m!r}") from None
    if len(seq) != n:
        raise InvalidParameterError(f"m must give one cell count per axis ({n} of them), got {len(seq)}: {seq!r}")
    return tuple(check_int(v, f"m[{a}]", minimum, why=why) for a, v in enumerate(seq))


_PERIODIC_WHY = (
    "with m <= 2 cells on an axis the periodic grid is no simplicial complex (grid points i and i + 2 "
    "coincide, so two different edges would join the same two vertices); use m >= 3 or cube_nd"
)


def _strides(shape: tuple[int, ...]) -> np.ndarray:
    """C-order strides (in elements) of an array of ``shape``."""
    return np.array([int(np.prod(shape[a + 1:], dtype=np.int64)) for a in range(len(shape))], np.int64)


def _grid_points(shape: tuple[int, ...], cells: tuple[int, ...]) -> np.ndarray:
    idx = np.indices(shape, dtype=np.int64).reshape(len(shape), -1).T
    return idx / np.asarray(cells, dtype=np.float64)


def cube_nd(
    n: int, m: int | Sequence[int] = 1, return_points: bool = False
) -> SimplicialComplex | tuple[SimplicialComplex, np.ndarray]:
    """Freudenthal–Kuhn triangulation of the cube ``[0, 1]^n`` with ``m`` cells per axis.

    Each grid cell ``c + [0, 1]^n`` (in units of the cell size) is split into ``n!`` simplices,
    one per monotone lattice path from ``c`` to ``c + (1, ..., 1)``: for a permutation ``π`` the
    simplex ``c, c + e_{π(0)}, c + e_{π(0)} + e_{π(1)}, ..., c + (1, ..., 1)`` (Freudenthal 1942,
    Kuhn 1960). All cells use the same diagonal, so the triangulation is the shuffle product of
    ``n`` subdivided intervals: ``cube_nd(n + k, m) == product(cube_nd(n, m), cube_nd(k, m))``.

    Parameters
    ----------
    n : int, >= 1
        Dimension.
    m : int >= 1, or sequence of n ints
        Number of cells along each axis.
    return_points : bool
        Also return the vertex coordinates.

    Returns
    -------
    X : SimplicialComplex
        ``prod(m + 1)`` vertices and ``n! * prod(m)`` top simplices. The grid point
        ``(i_0, ..., i_{n-1})`` (``0 <= i_a <= m_a``) is vertex ``Σ_a i_a * Π_{b > a} (m_b + 1)``
        (C order, ``np.ravel_multi_index``).
    points : (N, n) float64, only if ``return_points``
        ``points[v] = (i_0 / m_0, ..., i_{n-1} / m_{n-1})``.

    Raises
    ------
    InvalidParameterError
        ``n < 1``, ``m < 1`` or ``m`` of the wrong length.

    Examples
    --------
    >>> from dhlb.examples import cube_nd
    >>> X, P = cube_nd(2, 1, return_points=True)
    >>> X.simplices(2).tolist()          # the diagonal runs from (0, 0) to (1, 1)
    [[0, 1, 3], [0, 2, 3]]
    >>> P.tolist()
    [[0.0, 0.0], [0.0, 1.0], [1.0, 0.0], [1.0, 1.0]]
    >>> cube_nd(3, 2).counts
    (27, 98, 120, 48)
    """
    n = check_int(n, "n", 1)
    cells = _cells_per_axis(n, m, 1)
    shape = tuple(c + 1 for c in cells)
    strides = _strides(shape)
    base = np.zeros(1, np.int64)  # vertex index of each cell's lowest corner, C order of cells
    for a in range(n):
        base = np.add.outer(base, np.arange(cells[a], dtype=np.int64) * strides[a]).ravel()
    offsets = kuhn_paths(n) @ strides  # (n!, n+1), increasing along each path
    rows = (base[:, None, None] + offsets[None, :, :]).reshape(-1, n + 1)
    X = SimplicialComplex(rows)
    if return_points:
        return X, _grid_points(shape, cells)
    return X


def torus_nd(
    n: int, m: int | Sequence[int] = 3, return_points: bool = False
) -> SimplicialComplex | tuple[SimplicialComplex, np.ndarray]:
    """Freudenthal–Kuhn triangulation of the flat torus ``R^n / Z^n`` with ``m`` cells per axis.

    The periodic version of :func:`cube_nd`: the grid points ``(i_0, ..., i_{n-1})`` are taken
    modulo ``m`` on each axis and each cell is split into ``n!`` simplices along monotone lattice
    paths. Since all simplices share the diagonal direction ``(1, ..., 1)`` the triangulation is
    invariant under all grid translations; ``torus_nd(1, m)`` is the ``m``-gon and
    ``torus_nd(2, 3)`` the 9-vertex torus.

    Parameters
    ----------
    n : int, >= 1
        Dimension.
    m : int >= 3, or sequence of n ints >= 3
        Number of cells (= vertices) along each axis. With ``m <= 2`` the periodic grid would
        glue two different edges onto the same pair of vertices, which is not a simplicial complex.
    return_points : bool
        Also return the grid coordinates.

    Returns
    -------
    X : SimplicialComplex
        ``prod(m)`` vertices and ``n! * prod(m)`` top simplices. The grid point
        ``(i_0, ..., i_{n-1})`` (``0 <= i_a < m_a``) is vertex ``Σ_a i_a * Π_{b > a} m_b``.
    points : (N, n) float64, only if ``return_points``
        ``points[v] = (i_0 / m_0, ..., i_{n-1} / m_{n-1}) ∈ [0, 1)^n``, coordinates on ``R^n / Z^n``.

    Raises
    ------
    InvalidParameterError
        ``n < 1``, some ``m_a < 3``, or ``m`` of the wrong length.

    Examples
    --------
    >>> from dhlb.examples import torus_nd
    >>> T = torus_nd(2, 3)
    >>> T.counts, T.euler_characteristic
    ((9, 27, 18), 0)
    >>> torus_nd(3, 4).counts
    (64, 448, 768, 384)
    """
    n = check_int(n, "n", 1)
    cells = _cells_per_axis(n, m, 3, _PERIODIC_WHY)
    strides = _strides(cells)
    paths = kuhn_paths(n)  # (n!, n+1, n)
    rows = np.zeros(1, np.int64)[:, None, None]
    for a in range(n):
        coord = np.arange(cells[a], dtype=np.int64)
        # broadcast: (cells so far, 1, 1) x this axis -> (cells so far * m_a, n!, n+1)
        wrapped = (coord[:, None, None] + paths[None, :, :, a]) % cells[a] * strides[a]
        rows = (rows[:, None] + wrapped[None]).reshape(-1, *paths.shape[:2])
    X = SimplicialComplex(rows.reshape(-1, n + 1))
    if return_points:
        return X, _grid_points(cells, cells)
    return X
