"""Input checks of :func:`dhlb.stripes.stripe_form`: per-vertex directions and positive frequencies.

Private helpers of :mod:`dhlb.stripes.oneform`. :func:`checked_directions` turns the user's
directions into unit tangent vectors and rescaled angles (frames of
:class:`~dhlb.mesh.TangentBundle`), :func:`per_vertex_positive` validates a frequency or a
spacing; errors name the offending vertex or edge in input labels.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from dhlb.errors import InvalidParameterError, NonFiniteError, SectionZeroError, ShapeError

if TYPE_CHECKING:
    from dhlb.mesh.surface import SurfaceMesh
    from dhlb.mesh.tangent import TangentBundle

__all__ = ["vertex_name", "edge_name", "per_vertex_positive", "checked_directions"]


def vertex_name(mesh: SurfaceMesh, v: int) -> str:
    """``"vertex <label>"``: compact vertex ``v`` in the input labels, for error messages."""
    return f"vertex {int(mesh.vertex_rows[v])}"


def edge_name(mesh: SurfaceMesh, e: int) -> str:
    """``"edge (a, b)"``: canonical edge row ``e`` in the input labels, for error messages."""
    return "edge ({}, {})".format(*(int(x) for x in mesh.vertex_rows[mesh.complex.simplices(1)[e]]))


def per_vertex_positive(mesh: SurfaceMesh, value, what: str) -> np.ndarray:
    """``(N,)`` float: a positive number or one positive finite value per vertex (``what`` names it in errors)."""
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise InvalidParameterError(f"{what} must be a positive number or one per vertex, got {value!r}") from None
    if arr.ndim == 0:
        if not np.isfinite(arr):
            raise NonFiniteError(f"{what} is not finite ({float(arr)}); give a positive number")
        if arr <= 0:
            raise InvalidParameterError(f"{what} must be positive, got {float(arr)}")
        return np.full(mesh.n_vertices, float(arr))
    if arr.ndim != 1:
        raise ShapeError(f"{what} must be a number or a 1-d array with one value per vertex, got shape {arr.shape}")
    arr = mesh.per_vertex(arr, what)
    bad = ~np.isfinite(arr)
    if np.any(bad):
        raise NonFiniteError(f"{what} is not finite at {vertex_name(mesh, int(np.argmax(bad)))}")
    bad = arr <= 0
    if np.any(bad):
        v = int(np.argmax(bad))
        raise InvalidParameterError(f"{what} must be positive; it is {arr[v]} at {vertex_name(mesh, v)}")
    return arr.astype(np.float64)


def _field_section(tb: TangentBundle, directions):
    """``(u, n)`` of a direction-field result computed on ``tb.mesh`` itself, else None."""
    u, fn = getattr(directions, "u", None), getattr(directions, "n", None)
    if u is None or fn is None or getattr(directions, "mesh", None) is not tb.mesh:
        return None
    return np.asarray(u), int(fn)


def checked_directions(tb: TangentBundle, directions, method: str) -> tuple[np.ndarray, np.ndarray]:
    """Unit tangent directions ``(N, 3)`` and their rescaled angles ``(N,)`` (``method``: see ``stripe_form``).

    ``directions`` is one 3D vector per vertex, or a direction-field result (``.u``, ``.n``,
    ``.directions``): its first direction, whose rescaled angle ``arg u / n`` is read from the section
    when the field lives on ``tb.mesh`` (no round trip through 3D vectors).
    """
    mesh = tb.mesh
    field = _field_section(tb, directions)
    if field is not None:
        u, fn = field
        zero = u == 0
        if np.any(zero):
            raise SectionZeroError(f"the direction at {vertex_name(mesh, int(np.argmax(zero)))} is zero "
                                   f"({int(zero.sum())} such vertices); stripes need a nonzero tangent direction at "
                                   "every vertex")
        theta = np.mod(np.angle(u) / fn, 2 * np.pi)
        W = np.asarray(directions.directions)[:, 0, :]   # = tb.angles_to_vectors(v, theta): the field's own
        if method == "extrinsic":
            return _tangent_unit(tb, W), theta
        return np.array(W, dtype=np.float64), theta
    if hasattr(directions, "directions") and hasattr(directions, "mesh"):   # a field without u, or on another mesh
        other = directions.mesh is not mesh and hasattr(directions, "input_directions")
        directions = directions.input_directions() if other else directions.directions   # input order / compact
    try:
        W = np.asarray(directions, dtype=np.float64)
    except (TypeError, ValueError):
        raise ShapeError("directions must be a real array of shape (n_vertices, 3) (or (n_vertices, k, 3) from "
                         "dhlb.fields.direction_vectors)") from None
    if W.ndim == 3 and W.shape[2] == 3 and W.shape[1] >= 1:
        W = W[:, 0, :]
    if W.ndim != 2 or W.shape[1] != 3:
        raise ShapeError(f"directions must have shape (n_vertices, 3), got {np.shape(directions)}")
    W = mesh.per_vertex(W, "directions")
    bad = ~np.isfinite(W).all(axis=1)
    if np.any(bad):
        raise NonFiniteError(f"the direction at {vertex_name(mesh, int(np.argmax(bad)))} is not finite "
                             f"({W[np.argmax(bad)].tolist()}); give a finite tangent vector")
    theta, tangential = tb.vectors_to_angles(W)
    norm = np.linalg.norm(W, axis=1)
    zero = ~(tangential > 1e-8 * norm)
    if np.any(zero):
        v = int(np.argmax(zero))
        what = "is zero" if norm[v] == 0 else "is normal to the surface (no tangential part)"
        raise SectionZeroError(f"the direction at {vertex_name(mesh, v)} {what} ({int(zero.sum())} such vertices); "
                               "stripes need a nonzero tangent direction at every vertex")
    if method == "extrinsic":
        return _tangent_unit(tb, W), theta
    return tb.angles_to_vectors(np.arange(mesh.n_vertices), theta), theta


def _tangent_unit(tb: TangentBundle, W: np.ndarray) -> np.ndarray:
    """The tangential parts of ``W`` (one row per vertex), normalized."""
    Nv = tb.normals
    T = W - np.sum(W * Nv, axis=1, keepdims=True) * Nv
    return T / np.linalg.norm(T, axis=1, keepdims=True)
