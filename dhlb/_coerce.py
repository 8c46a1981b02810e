"""Checked conversion of the plain inputs every layer takes: point arrays, polylines, integers, reals.

Each function returns the value in one canonical form (float64 arrays, Python ``int``/``float``) or
raises a typed error of :mod:`dhlb.errors` whose message names the parameter and, for arrays, the
first bad row.  Layer 0.5: imports only :mod:`dhlb.errors` and numpy.

Examples
--------
>>> as_points([[0, 0, 0], [1, 2, 3]], "V").dtype
dtype('float64')
>>> check_int(3, "n", 1)
3
"""

from __future__ import annotations

import numbers
from collections.abc import Iterable

import numpy as np

from dhlb.errors import InvalidParameterError, NonFiniteError, ShapeError

__all__ = ["as_points", "as_vec3", "as_polyline", "curve_list", "check_int", "check_real"]


def _first_bad_row(X: np.ndarray) -> int | None:
    bad = ~np.isfinite(X).reshape(X.shape[0], -1).all(axis=1)
    return int(np.argmax(bad)) if bad.any() else None


def as_points(x, name: str, *, n: int | None = None, dim: int = 3, finite: bool = True,
              item: str = "point") -> np.ndarray:
    """``x`` as a float64 ``(k, dim)`` array of points, checked.

    Parameters
    ----------
    x : (k, dim) array_like
        The points.
    name : str
        The parameter name used in messages (e.g. ``"V"``, ``"points"``, ``"out.vtu: the points"``).
    n : int, optional
        The required number of points ``k``; any number if None.
    dim : int, optional
        The number of coordinates of each point.
    finite : bool, optional
        Whether NaN and infinite coordinates are refused.
    item : str, optional
        What a row is called in the message of a non-finite row (``"point"``, ``"vertex"``, ...).

    Returns
    -------
    (k, dim) float array
        The points (a new array unless ``x`` already was a float64 array).

    Raises
    ------
    ShapeError
        ``x`` is not numeric or not of shape ``(k, dim)`` (``(n, dim)`` when ``n`` is given).
    NonFiniteError
        ``finite`` and a row has a NaN or infinite coordinate; the message names the first such row.

    Examples
    --------
    >>> as_points([[0, 1, 2]], "V").tolist()
    [[0.0, 1.0, 2.0]]
    >>> as_points([[0, 1], [2, 3]], "uv", n=2, dim=2).shape
    (2, 2)
    >>> as_points([[0, 0, 0], [0, float("nan"), 0]], "V", item="vertex")
    Traceback (most recent call last):
    ...
    dhlb.errors.NonFiniteError: V: vertex 1 is not finite ([0.0, nan, 0.0])
    """
    rows = "k" if n is None else str(n)
    try:
        X = np.asarray(x, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ShapeError(f"{name} must be an ({rows}, {dim}) array of numbers ({exc})") from None
    if X.ndim != 2 or X.shape[1] != dim or (n is not None and X.shape[0] != n):
        raise ShapeError(f"{name} must have shape ({rows}, {dim}), got {X.shape}")
    if finite:
        r = _first_bad_row(X)
        if r is not None:
            raise NonFiniteError(f"{name}: {item} {r} is not finite ({X[r].tolist()})")
    return X


def as_vec3(x, name: str) -> np.ndarray:
    """``x`` as a finite float64 3-vector.

    Parameters
    ----------
    x : (3,) array_like
        The vector.
    name : str
        The parameter name used in messages.

    Returns
    -------
    (3,) float array
        The vector.

    Raises
    ------
    ShapeError
        ``x`` is not numeric or not of shape ``(3,)``.
    NonFiniteError
        A coordinate is NaN or infinite.

    Examples
    --------
    >>> as_vec3((1, 0, 0), "axis").tolist()
    [1.0, 0.0, 0.0]
    """
    try:
        v = np.asarray(x, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ShapeError(f"{name} must be a 3-vector of numbers ({exc})") from None
    if v.shape != (3,):
        raise ShapeError(f"{name} must be a 3-vector, got shape {v.shape}")
    if not np.isfinite(v).all():
        raise NonFiniteError(f"{name} must be finite, got {v.tolist()}")
    return v


def as_polyline(c, name: str, *, closed: bool | None = None, min_points: int = 2) -> np.ndarray:
    """A polyline ``c`` as a finite float64 ``(m, 3)`` array; a closed one without a repeated closing point.

    Parameters
    ----------
    c : (m, 3) array_like
        The points along the curve.
    name : str
        What the curve is called in messages (``"curve"``, ``"curve #2"``, ...).
    closed : bool or None, optional
        True for a closed curve: a last point equal to the first is dropped (after the checks).
        False or None (closedness unknown): the points are kept as given.
    min_points : int, optional
        The fewest points accepted, counted before a repeated closing point is dropped.

    Returns
    -------
    (m, 3) float array
        The points.

    Raises
    ------
    ShapeError
        ``c`` is not of shape ``(m, 3)`` with ``m >= min_points``.
    NonFiniteError
        A point is NaN or infinite; the message names its row.

    Examples
    --------
    >>> as_polyline([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 0]], "curve", closed=True).shape
    (3, 3)
    >>> as_polyline([[0, 0, 0]], "curve")
    Traceback (most recent call last):
    ...
    dhlb.errors.ShapeError: curve must be an (n, 3) array of n >= 2 points, got shape (1, 3)
    """
    C = np.asarray(c, dtype=np.float64)
    if C.ndim != 2 or C.shape[1] != 3 or C.shape[0] < min_points:
        raise ShapeError(f"{name} must be an (n, 3) array of n >= {min_points} points, got shape {C.shape}")
    r = _first_bad_row(C)
    if r is not None:
        raise NonFiniteError(f"{name} has a non-finite point (row {r})")
    if closed and np.array_equal(C[0], C[-1]):
        C = C[:-1]
    return C


def curve_list(curves, name: str) -> list[tuple[np.ndarray, bool]]:
    """``[(points (m, 3), closed)]`` from Filament-like objects, ``(points, closed)`` pairs or open arrays.

    Parameters
    ----------
    curves : iterable
        Each item an object with ``.points`` and ``.closed`` (a Filament, isoline, ...), a pair
        ``(points, closed)`` or an ``(m, 3)`` array (an open curve).
    name : str
        What the list is called in messages.

    Returns
    -------
    list of tuple of ((m, 3) float array, bool)
        The points (unchanged: a closed curve is not repeated) and whether each curve is closed.

    Raises
    ------
    ShapeError
        ``curves`` is not iterable (a single array is refused), or a curve is not ``(m, 3)``.
    NonFiniteError
        A point is NaN or infinite; the message names the curve and the point.

    Examples
    --------
    >>> [(P.shape, c) for P, c in curve_list([([[0, 0, 0], [1, 0, 0], [0, 1, 0]], True), [[0, 0, 0]]], "curves")]
    [((3, 3), True), ((1, 3), False)]
    """
    if isinstance(curves, (np.ndarray, str, bytes)) or not isinstance(curves, Iterable):
        raise ShapeError(f"{name} must be a list of (m, 3) arrays, (points, closed) pairs or Filaments")
    out = []
    for k, c in enumerate(list(curves)):
        if hasattr(c, "points") and hasattr(c, "closed"):
            pts, closed = c.points, bool(c.closed)
        elif isinstance(c, tuple) and len(c) == 2 and np.ndim(c[1]) == 0:
            pts, closed = c[0], bool(c[1])
        else:
            pts, closed = c, False
        try:
            X = np.asarray(pts, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise ShapeError(f"{name}: curve {k} must be an (m, 3) array of numbers ({exc})") from None
        if X.size == 0:
            X = X.reshape(0, 3)
        if X.ndim != 2 or X.shape[1] != 3:
            raise ShapeError(f"{name}: curve {k} must have shape (m, 3), got {X.shape}")
        r = _first_bad_row(X) if X.size else None
        if r is not None:
            raise NonFiniteError(f"{name}: point {r} of curve {k} is not finite")
        out.append((X, closed))
    return out


def check_int(value, name: str, minimum: int | None = None, maximum: int | None = None, *, why: str = "") -> int:
    """``value`` as a Python int, checked to be an integer (not a bool) in ``[minimum, maximum]``.

    Parameters
    ----------
    value : int
        The value (a Python or numpy integer).
    name : str
        The parameter name used in messages.
    minimum, maximum : int, optional
        Inclusive bounds; unbounded if None.
    why : str, optional
        Appended to the message of an out-of-range value.

    Returns
    -------
    int
        The value.

    Raises
    ------
    InvalidParameterError
        ``value`` is not an integer (``bool`` included) or is out of range.

    Examples
    --------
    >>> check_int(np.int64(4), "n", 1)
    4
    >>> check_int(0, "n", 1, why="a grid needs a cell")
    Traceback (most recent call last):
    ...
    dhlb.errors.InvalidParameterError: n must be an integer >= 1, got 0; a grid needs a cell
    """
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise InvalidParameterError(f"{name} must be an integer, got {value!r} ({type(value).__name__})")
    value = int(value)
    low_bad = minimum is not None and value < minimum
    high_bad = maximum is not None and value > maximum
    if low_bad or high_bad:
        if minimum is not None and maximum is not None:
            bound = f"between {minimum} and {maximum}"
        else:
            bound = f">= {minimum}" if minimum is not None else f"<= {maximum}"
        reason = f"; {why}" if why else ""
        raise InvalidParameterError(f"{name} must be an integer {bound}, got {value}{reason}")
    return value


def check_real(value, name: str, *, low: float | None = None, high: float | None = None,
               finite: bool = True) -> float:
    """``value`` as a Python float, checked to be a real number (not a bool) in ``[low, high]``.

    Parameters
    ----------
    value : float
        The value (a Python or numpy real number).
    name : str
        The parameter name used in messages.
    low, high : float, optional
        Inclusive bounds; unbounded if None.
    finite : bool, optional
        Whether NaN and infinity are refused.

    Returns
    -------
    float
        The value.

    Raises
    ------
    InvalidParameterError
        ``value`` is not a real number (``bool`` included), is out of range or is NaN.
    NonFiniteError
        ``finite`` and ``value`` is NaN or infinite.

    Examples
    --------
    >>> check_real(2, "hbar", low=0.0)
    2.0
    >>> check_real(-1.0, "hbar", low=0.0)
    Traceback (most recent call last):
    ...
    dhlb.errors.InvalidParameterError: hbar must be a real number >= 0.0, got -1.0
    """
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise InvalidParameterError(f"{name} must be a real number, got {value!r} ({type(value).__name__})")
    x = float(value)
    if finite and not np.isfinite(x):
        raise NonFiniteError(f"{name} must be finite, got {x!r}")
    if np.isnan(x) or (low is not None and x < low) or (high is not None and x > high):
        if low is not None and high is not None:
            bound = f" in [{low}, {high}]"
        elif low is not None or high is not None:
            bound = f" >= {low}" if low is not None else f" <= {high}"
        else:
            bound = ""
        raise InvalidParameterError(f"{name} must be a real number{bound}, got {x!r}")
    return x
