"""Gauss linking numbers of closed polylines, and the Hausdorff distance between polylines.

Linking number (exact for polylines)
    ``Lk(γ₁, γ₂) = 1/4π ∮∮ (γ₁ − γ₂) · (γ₁' × γ₂') / |γ₁ − γ₂|³`` is the degree of the Gauss
    map
    ``(s, t) ↦ (γ₂(t) − γ₁(s)) / |γ₂(t) − γ₁(s)|``. For a segment ``p₁ → p₂`` of ``γ₁`` and a
    segment ``p₃ → p₄`` of ``γ₂`` the differences ``q − p`` fill a planar parallelogram with
    corners ``r₁₃, r₂₃, r₂₄, r₁₄`` (``r_ij = p_j − p_i``), so the pair contributes the signed
    solid angle of the convex spherical quadrilateral ``r₁₃ → r₂₃ → r₂₄ → r₁₄`` (Klenin &
    Langowski 2000; Arai 2013).  We split it into the triangles ``(r₁₃, r₂₃, r₂₄)`` and
    ``(r₁₃, r₂₄, r₁₄)`` and evaluate each with the Van Oosterom–Strackee formula
    ``tan(Ω/2) = a·(b × c) / (|a||b||c| + (a·b)|c| + (a·c)|b| + (b·c)|a|)`` through ``atan2``,
    which is accurate for tiny and for nearly flat triangles (no ``arcsin`` of a rounded
    argument). Coplanar non-intersecting segments contribute exactly 0. The sum over all pairs
    is ``4π Lk`` up to rounding; a result farther than ``atol`` from an integer means that the
    curves (nearly) intersect, and is reported.

Examples
--------
>>> from dhlb.vortex.curves import hopf_link, vortex_ring
>>> a, b = hopf_link(n=48)
>>> linking_number(a, b), linking_number(b, a), linking_number(a, b[::-1])
(1, 1, -1)
>>> linking_matrix([a, b, vortex_ring(center=(5.0, 0, 0))]).tolist()
[[0, 1, 0], [1, 0, 0], [0, 0, 0]]
"""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING

import numpy as np

from dhlb._coerce import as_points, as_polyline
from dhlb.errors import CurveIntersectionError, DhlbWarning, InvalidParameterError

if TYPE_CHECKING:
    from collections.abc import Sequence

    from numpy.typing import ArrayLike

    from dhlb.vortex.filaments import Filament

__all__ = ["filament_linking_numbers", "gauss_linking_integral", "linking_number", "linking_matrix",
           "hausdorff_distance", "polyline_distance"]

_CHUNK = 1 << 19


def _curve(c, name: str, closed: bool = True) -> np.ndarray:
    """A closed polyline needs 3 points, an open one 2."""
    return as_polyline(c, name, closed=closed, min_points=3 if closed else 2)


def _segments(C: np.ndarray, closed: bool) -> tuple[np.ndarray, np.ndarray]:
    return (C, np.roll(C, -1, axis=0)) if closed else (C[:-1], C[1:])


def _triangle_solid_angle(a, b, c) -> np.ndarray:
    """Signed solid angle of the spherical triangle a, b, c (Van Oosterom & Strackee 1983)."""
    na, nb, nc = (np.sqrt(np.einsum("...k,...k->...", v, v)) for v in (a, b, c))
    num = np.einsum("...k,...k->...", a, np.cross(b, c))
    den = (na * nb * nc + np.einsum("...k,...k->...", a, b) * nc + np.einsum("...k,...k->...", a, c) * nb
           + np.einsum("...k,...k->...", b, c) * na)
    return 2.0 * np.arctan2(num, den)


def gauss_linking_integral(a: ArrayLike, b: ArrayLike) -> float:
    """The Gauss integral ``1/4π ∮∮ (γ₁ − γ₂)·(γ₁' × γ₂') / |γ₁ − γ₂|³`` of closed polylines.

    Exact (up to rounding) for disjoint polylines, where it is an integer; see the module docstring.

    Parameters
    ----------
    a : (n, 3) float array
        The first closed polyline (first point not repeated; a repeated last point is dropped).
    b : (k, 3) float array
        The second closed polyline.

    Returns
    -------
    float
        The integral, not rounded (:func:`linking_number` rounds it and checks that it is an integer).

    Raises
    ------
    ShapeError, NonFiniteError
        Not ``(n, 3)`` arrays with ``n >= 3`` finite points.

    Examples
    --------
    >>> from dhlb.vortex.curves import hopf_link
    >>> round(gauss_linking_integral(*hopf_link(n=16)), 12)
    1.0
    """
    A, B = _curve(a, "a"), _curve(b, "b")
    p1, p2 = _segments(A, True)
    p3, p4 = _segments(B, True)
    total = 0.0
    step = max(1, _CHUNK // p3.shape[0])
    for lo in range(0, p1.shape[0], step):
        P1, P2 = p1[lo:lo + step, None, :], p2[lo:lo + step, None, :]
        r13, r14, r23, r24 = p3[None] - P1, p4[None] - P1, p3[None] - P2, p4[None] - P2
        total += float(np.sum(_triangle_solid_angle(r13, r23, r24)) + np.sum(_triangle_solid_angle(r13, r24, r14)))
    return total / (4 * np.pi)


def polyline_distance(x: ArrayLike, curve: ArrayLike, *, closed: bool = True) -> np.ndarray:
    """Euclidean distance from each point of ``x`` (m, 3) to the polyline ``curve`` (exact).

    Parameters
    ----------
    x : (m, 3) float array
        The points.
    curve : (n, 3) float array
        The polyline, ``n >= 3`` finite points if closed, ``n >= 2`` if open.
    closed : bool, optional
        Whether the last point of ``curve`` is joined to the first.

    Returns
    -------
    (m,) float array
        The distance of each point to the nearest point of the polyline.

    Raises
    ------
    ShapeError
        ``x`` is not ``(m, 3)``, or ``curve`` is not ``(n, 3)`` with enough points.
    NonFiniteError
        ``curve`` has a NaN or infinite point.

    Examples
    --------
    >>> polyline_distance([[0.5, 1.0, 0.0], [2.0, 0.0, 0.0]], [[0, 0, 0], [1.0, 0, 0]], closed=False).tolist()
    [1.0, 1.0]
    """
    P = as_points(x, "x", finite=False)
    C = _curve(curve, "curve", closed)
    A, B = _segments(C, closed)
    E = B - A
    E2 = np.einsum("ij,ij->i", E, E)
    E2safe = np.where(E2 > 0, E2, 1.0)
    out = np.empty(P.shape[0])
    step = max(1, _CHUNK // A.shape[0])
    for lo in range(0, P.shape[0], step):
        d = P[lo:lo + step, None, :] - A[None]
        t = np.clip(np.einsum("csk,sk->cs", d, E) / E2safe, 0.0, 1.0)
        res = d - t[..., None] * E[None]
        out[lo:lo + step] = np.sqrt(np.einsum("csk,csk->cs", res, res).min(axis=1))
    return out


def _check_int_result(value: float, A: np.ndarray, B: np.ndarray, atol: float) -> int:
    n = int(np.round(value))
    if abs(value - n) > atol:
        d = polyline_distance(A, B).min()
        raise CurveIntersectionError(
            f"the Gauss linking integral is {value:.9g}, not an integer: the curves intersect or nearly "
            f"touch (closest vertex-to-curve distance {d:.3g}); move them apart"
        )
    return n


def linking_number(a: ArrayLike, b: ArrayLike, *, atol: float = 1e-6) -> int:
    """The linking number of two disjoint closed polylines (each ``(n, 3)``, first point not repeated).

    Reversing either curve changes the sign; ``Lk(a, b) = Lk(b, a)``.

    Parameters
    ----------
    a : (n, 3) float array
        The first closed polyline.
    b : (k, 3) float array
        The second closed polyline.
    atol : float, optional
        How far the Gauss integral may be from the nearest integer.

    Returns
    -------
    int
        The Gauss integral rounded to the nearest integer.

    Raises
    ------
    CurveIntersectionError
        The Gauss integral is farther than ``atol`` from an integer (the curves intersect).
    ShapeError, NonFiniteError
        Not ``(n, 3)`` arrays with ``n >= 3`` finite points.

    Examples
    --------
    >>> from dhlb.vortex.curves import vortex_ring
    >>> linking_number(vortex_ring(1.0), vortex_ring(1.0, center=(0, 0, 1.0)))
    0
    """
    A, B = _curve(a, "a"), _curve(b, "b")
    return _check_int_result(gauss_linking_integral(A, B), A, B, atol)


def linking_matrix(curves: Sequence[ArrayLike], *, atol: float = 1e-6) -> np.ndarray:
    """Symmetric integer matrix of pairwise linking numbers (zero diagonal).

    Parameters
    ----------
    curves : sequence of (n_i, 3) float arrays
        Closed polylines (first point not repeated).
    atol : float, optional
        As for :func:`linking_number`.

    Returns
    -------
    (k, k) int array
        ``L[i, j]`` is the linking number of curves ``i`` and ``j``.

    Raises
    ------
    CurveIntersectionError
        Two curves intersect or nearly touch (as for :func:`linking_number`).
    ShapeError, NonFiniteError
        A curve is not an ``(n, 3)`` array with ``n >= 3`` finite points.

    Examples
    --------
    >>> from dhlb.vortex import hopf_link, linking_matrix
    >>> linking_matrix(hopf_link(n=32)).tolist()
    [[0, 1], [1, 0]]
    """
    Cs = [_curve(c, f"curve #{i}") for i, c in enumerate(curves)]
    k = len(Cs)
    L = np.zeros((k, k), np.int64)
    for i in range(k):
        for j in range(i + 1, k):
            L[i, j] = L[j, i] = _check_int_result(gauss_linking_integral(Cs[i], Cs[j]), Cs[i], Cs[j], atol)
    return L


def _samples(C: np.ndarray, closed: bool, spacing: float) -> np.ndarray:
    A, B = _segments(C, closed)
    n = np.maximum(1, np.ceil(np.linalg.norm(B - A, axis=1) / spacing)).astype(np.int64)
    seg = np.repeat(np.arange(A.shape[0]), n)
    t = (np.arange(seg.size) - np.repeat(np.cumsum(n) - n, n)) / np.repeat(n, n)
    pts = A[seg] + t[:, None] * (B - A)[seg]
    return pts if closed else np.concatenate([pts, C[-1:]])


def hausdorff_distance(
    a: ArrayLike, b: ArrayLike, *, closed: tuple[bool, bool] = (True, True), spacing: float | None = None
) -> float:
    """Hausdorff distance between two polylines, to within ``spacing / 2``.

    Both curves are sampled with points at most ``spacing`` apart along each segment (vertices
    included), and for every sample the exact distance to the other polyline is taken. Since
    the distance to a set is 1-Lipschitz, the result ``h`` satisfies
    ``h <= d_H(a, b) <= h + spacing / 2``.

    Parameters
    ----------
    a : (n, 3) float array
        The first polyline.
    b : (k, 3) float array
        The second polyline.
    closed : pair of bools, optional
        Whether ``a`` resp. ``b`` is closed (last point joined to the first).
    spacing : float > 0, optional
        Default: a quarter of the median segment length of both curves.

    Returns
    -------
    float
        The lower bound ``h`` of the Hausdorff distance, ``h <= d_H(a, b) <= h + spacing / 2``.

    Raises
    ------
    InvalidParameterError
        ``spacing`` is not a finite number > 0.
    ShapeError, NonFiniteError
        A curve is not an ``(n, 3)`` array of finite points (``n >= 3`` if closed, ``n >= 2`` if open).

    Examples
    --------
    >>> from dhlb.vortex.curves import vortex_ring
    >>> round(hausdorff_distance(vortex_ring(1.0, n=64), vortex_ring(1.2, n=64), spacing=1e-3), 6)
    0.2
    """
    ca, cb = (bool(c) for c in closed)
    A, B = _curve(a, "a", ca), _curve(b, "b", cb)
    if spacing is None:
        lens = np.concatenate([np.linalg.norm(np.diff(C, axis=0), axis=1) for C in (A, B)])
        spacing = 0.25 * float(np.median(lens[lens > 0])) if np.any(lens > 0) else 1.0
    if not (np.isfinite(spacing) and spacing > 0):
        raise InvalidParameterError(f"spacing must be a finite number > 0, got {spacing!r}")
    dab = polyline_distance(_samples(A, ca, spacing), B, closed=cb).max()
    dba = polyline_distance(_samples(B, cb, spacing), A, closed=ca).max()
    return float(max(dab, dba))


_LINK_ATOL = 1e-6  # a Gauss integral farther than this from an integer means touching curves


def filament_linking_numbers(
    filaments: Sequence[Filament], *, atol: float = _LINK_ATOL
) -> tuple[np.ndarray, np.ndarray, float]:
    """Gauss linking numbers among the closed filaments.

    A defect above ``atol`` (two filaments touching inside an ambiguous tetrahedron) is reported
    as a :class:`~dhlb.errors.DhlbWarning` naming the pair; the integral is rounded anyway.

    Parameters
    ----------
    filaments : sequence of Filament
        The filaments (open ones and those of fewer than 3 points are skipped).
    atol : float, optional
        The largest distance of a Gauss integral from an integer that passes without a warning.

    Returns
    -------
    L : (k, k) int64 array
        The symmetric matrix of linking numbers of the ``k`` closed filaments (zero diagonal).
    index : (k,) int64 array
        Their positions in ``filaments``.
    defect : float
        The largest distance of a Gauss integral from its integer.

    Examples
    --------
    >>> from dhlb.vortex import Filament, hopf_link
    >>> a, b = hopf_link(n=32)
    >>> L, idx, defect = filament_linking_numbers([Filament(a, True, None), Filament(b, True, None)])
    >>> L.tolist(), idx.tolist(), defect < 1e-9
    ([[0, 1], [1, 0]], [0, 1], True)
    """
    idx = np.array([i for i, f in enumerate(filaments) if f.closed and len(f) >= 3], dtype=np.int64)
    k = idx.size
    L = np.zeros((k, k), np.int64)
    defect = 0.0
    for a in range(k):
        for b in range(a + 1, k):
            g = gauss_linking_integral(filaments[idx[a]].points, filaments[idx[b]].points)
            n = int(np.round(g))
            d = abs(g - n)
            if d > atol:
                warnings.warn(f"filaments #{idx[a]} and #{idx[b]} touch or cross (Gauss integral {g:.6g} is not an "
                              f"integer); their linking number {n} is a guess: refine the mesh", DhlbWarning,
                              stacklevel=3)
            defect = max(defect, d)
            L[a, b] = L[b, a] = n
    return L, idx, float(defect)
