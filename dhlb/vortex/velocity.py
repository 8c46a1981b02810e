"""Velocity fields as edge 1-forms, and the hermitian line bundle of a velocity field.

A velocity field ``v`` on a tetrahedral mesh becomes the 1-form ``ω_ij = ∫_{x_i}^{x_j} v · dl``
on every edge.  ``v`` is given either

* as a callable ``v(x)`` taking ``(m, 3)`` points and returning ``(m, 3)`` vectors: the line
  integral is computed by Gauss–Legendre quadrature with ``order`` nodes on the edge
  (``∫_0^1 v(x_i + s e)·e ds ≈ Σ_q w_q v(x_i + s_q e)·e`` with ``e = x_j − x_i``), exact when
  ``v`` restricted to the edge is a polynomial of degree ``<= 2·order − 1``; for a smooth field
  the error on an edge of length ``h`` is ``O(h^{2·order + 1})``;
* or as one vector per vertex, meaning its piecewise-linear interpolant, whose line integral is
  exactly ``ω_ij = ½ (v_i + v_j) · (x_j − x_i)``.

:func:`velocity_bundle` turns ``ω`` into the bundle of Weißmann–Pinkall–Schröder ("Smoke rings
from smoke", 2014; seed part 3 §2.3): connection ``r_ij = exp(i ω_ij / ħ)`` and curvature
``Ω = dω / ħ`` (the real 2-form, not wrapped to (−π, π]).  Demo fields live in
:mod:`dhlb.vortex.flows`.

Examples
--------
>>> import numpy as np
>>> from dhlb.vortex.velocity import edge_circulation
>>> x = np.array([[0.0, 0, 0], [1, 0, 0], [1, 2, 0]])
>>> edges = np.array([[0, 1], [1, 2]])
>>> edge_circulation(x, edges, lambda p: np.stack([p[:, 0] ** 2, p[:, 0], 0 * p[:, 0]], axis=1)).round(12).tolist()
[0.333333333333, 2.0]
>>> edge_circulation(x, edges, np.array([[1.0, 0, 0], [3, 0, 0], [0, 1, 0]])).tolist()   # per-vertex
[2.0, 1.0]
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from dhlb._coerce import as_points, check_int
from dhlb.errors import InvalidParameterError, NonFiniteError, ShapeError
from dhlb.mesh.arrays import check_cells

if TYPE_CHECKING:
    from collections.abc import Callable

    from numpy.typing import ArrayLike

    from dhlb.bundles.hermitian import HermitianLineBundle
    from dhlb.topology.complex import SimplicialComplex

__all__ = ["DEFAULT_ORDER", "MAX_ORDER", "gauss_legendre", "edge_circulation", "velocity_bundle"]

DEFAULT_ORDER = 4
"""Default number of Gauss–Legendre nodes per edge (exact for degree <= 7 along the edge)."""
MAX_ORDER = 64
"""Largest accepted number of Gauss–Legendre nodes per edge (exact for degree 127)."""


def gauss_legendre(order: int) -> tuple[np.ndarray, np.ndarray]:
    """Nodes ``s_q ∈ (0, 1)`` and weights ``w_q`` (summing to 1) of Gauss–Legendre quadrature on [0, 1].

    Parameters
    ----------
    order : int
        The number of nodes, ``1 <= order <= MAX_ORDER``; exact for polynomials of degree ``2·order − 1``.

    Returns
    -------
    s : (order,) float array
        The nodes, increasing.
    w : (order,) float array
        The weights.

    Raises
    ------
    InvalidParameterError
        ``order`` is not an integer in ``1 .. MAX_ORDER`` (booleans are refused).

    Examples
    --------
    >>> s, w = gauss_legendre(2)
    >>> s.round(6).tolist(), w.tolist()
    ([0.211325, 0.788675], [0.5, 0.5])
    """
    order = check_int(order, "the quadrature order", 1)
    if order > MAX_ORDER:  # leggauss builds an order x order matrix: 60000 nodes would need 29 GB
        raise InvalidParameterError(f"the quadrature order must be at most {MAX_ORDER} (exact for polynomials of "
                                    f"degree {2 * MAX_ORDER - 1} along an edge), got {order}")
    x, w = np.polynomial.legendre.leggauss(int(order))
    return (x + 1) / 2, w / 2


def _as_edges(edges, N: int) -> np.ndarray:
    E = np.asarray(edges)
    if E.ndim != 2 or E.shape[1] != 2 or not np.issubdtype(E.dtype, np.integer):
        raise ShapeError(f"edges must be an integer array of shape (n_edges, 2), got {E.dtype} array of "
                         f"shape {E.shape}")
    return check_cells(E, N, 2, "edge", points="points", error=ShapeError)


def _eval_field(velocity, x: np.ndarray) -> np.ndarray:
    """``velocity(x)`` checked to be a finite (m, 3) array."""
    u = velocity(x)
    u = np.asarray(u, dtype=np.float64)
    if u.shape != x.shape:
        raise ShapeError(f"the velocity callable must map (m, 3) points to (m, 3) vectors; for {x.shape} points "
                         f"it returned shape {u.shape}")
    return u


def edge_circulation(
    points: ArrayLike,
    edges: ArrayLike,
    velocity: Callable[[np.ndarray], np.ndarray] | ArrayLike,
    *,
    order: int = DEFAULT_ORDER,
) -> np.ndarray:
    """Line integrals ``ω_e = ∫_e v · dl`` along the edges ``e = (i, j)``, oriented from ``i`` to ``j``.

    Parameters
    ----------
    points : (N, 3) float array
        Vertex positions.
    edges : (n_e, 2) int array
        Edges as vertex pairs (for the canonical edges of a complex: ``X.simplices(1)``).
    velocity : callable or (N, 3) array
        ``v(x)`` for ``x`` of shape ``(m, 3)`` returning ``(m, 3)``; or one vector per vertex
        (the piecewise-linear field, integrated exactly as ``½ (v_i + v_j) · (x_j − x_i)``).
    order : int >= 1
        Gauss–Legendre nodes per edge for a callable (exact for polynomials of degree
        ``2·order − 1`` along the edge).

    Returns
    -------
    (n_e,) float array
        The circulation of each edge, from its first to its second vertex.

    Raises
    ------
    InvalidParameterError
        ``order`` is not an integer in ``1 .. MAX_ORDER`` (callable ``velocity`` only).
    ShapeError
        Wrong shapes of ``points``, ``edges``, the per-vertex array or the callable's output, or an
        edge index outside ``points``.
    NonFiniteError
        NaN/inf in positions or per-vertex vectors (the vertex is named), or returned by the
        callable (the edge and the sample point are named).

    Examples
    --------
    >>> from dhlb.vortex import edge_circulation, uniform_flow
    >>> edge_circulation([[0, 0, 0], [1, 2, 0]], [[0, 1]], uniform_flow([1.0, 1.0, 0.0])).round(12).tolist()
    [3.0]
    """
    P = as_points(points, "points", item="vertex")
    E = _as_edges(edges, P.shape[0])
    e = P[E[:, 1]] - P[E[:, 0]]
    if callable(velocity):
        s, w = gauss_legendre(order)
        x = P[E[:, 0], None, :] + s[None, :, None] * e[:, None, :]  # (n_e, q, 3)
        u = _eval_field(velocity, x.reshape(-1, 3)).reshape(x.shape)
        bad = ~np.isfinite(u).all(axis=2)
        if np.any(bad):
            r, q = np.unravel_index(int(np.argmax(bad)), bad.shape)
            raise NonFiniteError(
                f"the velocity is not finite at {x[r, q].tolist()} (quadrature node {q} of edge #{r} "
                f"{tuple(int(v) for v in E[r])}); {int(bad.sum())} of {bad.size} samples are not finite"
            )
        return np.einsum("eqk,q,ek->e", u, w, e)
    V = np.asarray(velocity)
    if V.dtype == object or not (np.issubdtype(V.dtype, np.floating) or np.issubdtype(V.dtype, np.integer)):
        raise ShapeError(f"velocity must be a callable or a real (N, 3) array, got {type(velocity).__name__} "
                         f"of dtype {V.dtype}")
    V = V.astype(np.float64)
    if V.shape != P.shape:
        raise ShapeError(f"per-vertex velocities must have one 3-vector per vertex, shape {P.shape}; got {V.shape}")
    bad = ~np.isfinite(V).all(axis=1)
    if np.any(bad):
        i = int(np.argmax(bad))
        raise NonFiniteError(f"the velocity at vertex {i} is not finite: {V[i].tolist()} "
                             f"({int(bad.sum())} vertices affected)")
    return 0.5 * np.einsum("ek,ek->e", V[E[:, 0]] + V[E[:, 1]], e)


def _check_hbar(hbar) -> float:
    import numbers

    if isinstance(hbar, (bool, np.bool_)) or not isinstance(hbar, numbers.Real):
        what = "complex" if isinstance(hbar, numbers.Complex) else type(hbar).__name__
        raise InvalidParameterError(f"hbar must be a real number > 0, got {what} {hbar!r}")
    h = float(hbar)
    if not (np.isfinite(h) and h > 0):
        raise InvalidParameterError(f"hbar must be a finite number > 0 (it sets the filament spacing), got {hbar!r}")
    return h


def velocity_bundle(
    X: SimplicialComplex,
    points: ArrayLike,
    velocity: Callable[[np.ndarray], np.ndarray] | ArrayLike,
    hbar: float,
    *,
    order: int = DEFAULT_ORDER,
) -> HermitianLineBundle:
    """The hermitian line bundle ``r = exp(iω/ħ)``, ``Ω = dω/ħ`` of a velocity field on a complex.

    Parameters
    ----------
    X : SimplicialComplex
        The mesh complex (typically ``TetMesh.complex``); ``ω`` lives on ``X.simplices(1)``.
    points : (N, 3) float array
        Positions of the compact vertices of ``X``.
    velocity : callable or (N, 3) array
        As for :func:`edge_circulation`.
    hbar : float > 0
        The scale ``ħ``: the curvature is the flux of ``curl v / ħ``.
    order : int, optional
        Quadrature order for a callable velocity.

    Returns
    -------
    HermitianLineBundle
        Its ``curvature`` is ``dω/ħ`` exactly as computed (real, not reduced mod 2π), so the
        index form of a section counts the zeros of ψ inside each triangle.

    Raises
    ------
    InvalidParameterError
        ``hbar`` not a finite positive number, or a bad ``order`` (as for :func:`edge_circulation`).
    ShapeError, NonFiniteError
        As for :func:`edge_circulation` (also: ``points`` not one row per vertex of ``X``).

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import box_tet_mesh
    >>> mesh = box_tet_mesh(1)
    >>> L = velocity_bundle(mesh.complex, mesh.points, lambda x: np.cross([0, 0, 1.0], x), hbar=0.5)
    >>> tri = mesh.complex.simplices(2)
    >>> flat = np.ptp(mesh.points[tri][:, :, 2], axis=1) == 0   # triangles in a plane z = const
    >>> bool(np.allclose(np.abs(L.curvature[flat]), 2 * 0.5 / 0.5))   # curl v = (0, 0, 2), area 1/2
    True
    """
    from dhlb.bundles import HermitianLineBundle

    h = _check_hbar(hbar)
    P = as_points(points, "points", item="vertex")
    if P.shape[0] != X.n_vertices:
        raise ShapeError(f"points must have one row per vertex of the complex ({X.n_vertices}), got {P.shape[0]}")
    w = edge_circulation(P, X.simplices(1), velocity, order=order) / h
    f = X.faces(2)
    curvature = w[f[:, 2]] - w[f[:, 1]] + w[f[:, 0]]  # (dω)_ijk = ω_jk − ω_ik + ω_ij
    return HermitianLineBundle(X, np.exp(1j * w), curvature)


def _per_vertex_velocity(velocity, n_rows: int, rows: np.ndarray) -> np.ndarray:
    """Check a per-vertex velocity array against the input rows and restrict it to the mesh's vertices ``rows``."""
    try:
        arr = np.asarray(velocity)
    except ValueError:
        raise ShapeError("velocity must be a callable v(x) or an (N, 3) array of numbers, got a ragged "
                         f"{type(velocity).__name__}") from None
    if arr.dtype == object or not (np.issubdtype(arr.dtype, np.floating) or np.issubdtype(arr.dtype, np.integer)):
        raise ShapeError(f"velocity must be a callable v(x) or a real (N, 3) array, got {type(velocity).__name__} "
                         f"of dtype {arr.dtype}")
    if arr.shape != (n_rows, 3):
        raise ShapeError(f"a per-vertex velocity needs one 3-vector per row of V, shape ({n_rows}, 3); got "
                         f"{arr.shape}")
    arr = arr.astype(np.float64)[rows]  # rows of V used by the mesh (unreferenced ones are ignored)
    bad = ~np.isfinite(arr).all(axis=1)
    if np.any(bad):
        i = int(np.argmax(bad))
        more = f"; {int(bad.sum())} vertices are affected" if bad.sum() > 1 else ""
        raise NonFiniteError(f"the velocity at vertex {int(rows[i])} (row {int(rows[i])} of V) is not finite: "
                             f"{arr[i].tolist()}{more}")
    return arr
