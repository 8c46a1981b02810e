"""Closed polylines for vortex demos: rings, the Hopf link, torus knots (the trefoil).

Every function returns closed polylines as ``(n, 3)`` arrays whose last point connects back to
the first (the first point is not repeated), sampled at equal parameter steps.

Examples
--------
>>> from dhlb.vortex.curves import hopf_link, trefoil
>>> [c.shape for c in hopf_link(n=64)], trefoil(n=100).shape
([(64, 3), (64, 3)], (100, 3))
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from dhlb._coerce import as_vec3, check_int
from dhlb.errors import InvalidParameterError

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["vortex_ring", "hopf_link", "torus_knot", "trefoil"]


def _positive(value, name: str) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InvalidParameterError(f"{name} must be a positive number, got {value!r}") from None
    if not (np.isfinite(v) and v > 0):
        raise InvalidParameterError(f"{name} must be a finite number > 0, got {value!r}")
    return v


def vortex_ring(
    radius: float = 1.0, center: ArrayLike = (0.0, 0.0, 0.0), normal: ArrayLike = (0.0, 0.0, 1.0), n: int = 128
) -> np.ndarray:
    """A regular ``n``-gon inscribed in the circle of the given radius, center and normal.

    It runs counter-clockwise seen from the tip of ``normal`` (right-handed about ``normal``),
    starting in the direction ``normal × e`` where ``e`` is the coordinate axis least parallel to
    ``normal`` (for ``normal = z``: at ``(R, 0, 0)``, through ``(0, R, 0)``).

    Parameters
    ----------
    radius : float > 0, optional
        Radius ``R`` of the circle.
    center : 3 floats, optional
        Center of the circle.
    normal : 3 floats, optional
        Normal of its plane (any non-zero length); the ring is right-handed about it.
    n : int >= 3, optional
        Number of points.

    Returns
    -------
    (n, 3) float array
        The closed polyline (the first point is not repeated).

    Raises
    ------
    InvalidParameterError
        ``radius`` is not a finite number > 0, ``normal`` is zero, or ``n`` is not an integer >= 3.
    ShapeError, NonFiniteError
        ``center`` or ``normal`` is not 3 finite numbers.

    Examples
    --------
    >>> vortex_ring(2.0, n=4).round(12).tolist()
    [[2.0, 0.0, 0.0], [0.0, 2.0, 0.0], [-2.0, 0.0, 0.0], [0.0, -2.0, 0.0]]
    """
    R = _positive(radius, "radius")
    c, nrm = as_vec3(center, "center"), as_vec3(normal, "normal")
    n = check_int(n, "n", 3)
    length = np.linalg.norm(nrm)
    if length == 0:
        raise InvalidParameterError("normal must be a non-zero vector")
    nrm = nrm / length
    if np.allclose(nrm, [0, 0, 1]):
        u, v = np.array([1.0, 0, 0]), np.array([0, 1.0, 0])
    else:
        e = np.eye(3)[np.argmin(np.abs(nrm))]
        u = np.cross(nrm, e)
        u /= np.linalg.norm(u)
        v = np.cross(nrm, u)
    t = 2 * np.pi * np.arange(n) / n
    return c + R * (np.cos(t)[:, None] * u + np.sin(t)[:, None] * v)


def hopf_link(radius: float = 1.0, n: int = 128) -> list[np.ndarray]:
    """Two rings of the given radius forming a Hopf link with linking number +1.

    The first lies in the plane ``z = 0`` around the origin (right-handed about +z); the second
    lies in the plane ``y = 0`` around ``(radius, 0, 0)`` (right-handed about +y) and passes
    through the first one's center in direction +z; each passes through the other's center.

    Parameters
    ----------
    radius : float > 0, optional
        Radius of both rings.
    n : int >= 3, optional
        Number of points per ring.

    Returns
    -------
    list of two (n, 3) float arrays
        The two closed polylines.

    Raises
    ------
    InvalidParameterError
        ``radius`` is not a finite number > 0, or ``n`` is not an integer >= 3.

    Examples
    --------
    >>> from dhlb.vortex.linking import linking_number
    >>> linking_number(*hopf_link(n=32))
    1
    """
    R = _positive(radius, "radius")
    a = vortex_ring(R, (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), n)
    b = vortex_ring(R, (R, 0.0, 0.0), (0.0, 1.0, 0.0), n)
    return [a, b]


def torus_knot(p: int = 2, q: int = 3, major: float = 1.0, minor: float = 0.4, n: int = 256) -> np.ndarray:
    """The ``(p, q)`` torus knot on the torus with radii ``major > minor``.

    ``x(t) = ((R + r cos qt) cos pt, (R + r cos qt) sin pt, r sin qt)``, ``t ∈ [0, 2π)``: it winds
    ``p`` times around the z-axis (right-handed about +z) and ``q`` times around the core circle
    ``|x| = R, z = 0`` (on the outer side it moves up, so each of these turns is left-handed about
    the core's direction of :func:`vortex_ring`). Hence, for ``gcd(p, q) = 1``, its linking number
    with the core circle ``vortex_ring(R)`` is ``−q`` and with a loop running up the z-axis and
    closing far outside the torus it is ``+p``.

    Parameters
    ----------
    p : int >= 1, optional
        Turns around the z-axis.
    q : int >= 1, optional
        Turns around the core circle.
    major : float > 0, optional
        Radius ``R`` of the core circle.
    minor : float > 0, optional
        Radius ``r < R`` of the tube.
    n : int >= 3, optional
        Number of points.

    Returns
    -------
    (n, 3) float array
        The closed polyline (the first point is not repeated).

    Raises
    ------
    InvalidParameterError
        ``p``, ``q`` or ``n`` is not an integer of the range above, ``major`` or ``minor`` is not a
        finite number > 0, or ``minor >= major``.

    Examples
    --------
    >>> from dhlb.vortex.curves import vortex_ring
    >>> from dhlb.vortex.linking import linking_number
    >>> linking_number(torus_knot(2, 3, n=200), vortex_ring(1.0, n=200))
    -3
    """
    p, q = check_int(p, "p", 1), check_int(q, "q", 1)
    R, r = _positive(major, "major"), _positive(minor, "minor")
    if r >= R:
        raise InvalidParameterError(f"the torus needs minor < major, got minor={r}, major={R}")
    n = check_int(n, "n", 3)
    t = 2 * np.pi * np.arange(n) / n
    rho = R + r * np.cos(q * t)
    return np.stack([rho * np.cos(p * t), rho * np.sin(p * t), r * np.sin(q * t)], axis=1)


def trefoil(major: float = 1.0, minor: float = 0.4, n: int = 256) -> np.ndarray:
    """The trefoil knot as the ``(2, 3)`` torus knot (see :func:`torus_knot`).

    Parameters
    ----------
    major : float > 0, optional
        Radius ``R`` of the core circle.
    minor : float > 0, optional
        Radius ``r < R`` of the tube.
    n : int >= 3, optional
        Number of points.

    Returns
    -------
    (n, 3) float array
        ``torus_knot(2, 3, major, minor, n)``.

    Raises
    ------
    InvalidParameterError
        As :func:`torus_knot`.

    Examples
    --------
    >>> from dhlb.vortex import linking_number, trefoil, vortex_ring
    >>> knot = trefoil(n=64)
    >>> knot.shape, linking_number(knot, vortex_ring(0.2, center=(10, 0, 0)))   # a far-away ring: unlinked
    ((64, 3), 0)
    """
    return torus_knot(2, 3, major, minor, n)
