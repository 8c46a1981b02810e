"""dhlb._coerce: each conversion on good input and each typed error."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from dhlb._coerce import as_points, as_polyline, as_vec3, check_int, check_real, curve_list
from dhlb.errors import InvalidParameterError, NonFiniteError, ShapeError


def test_as_points():
    P = as_points([[0, 1, 2], [3, 4, 5]], "V")
    assert P.dtype == np.float64 and P.shape == (2, 3)
    assert as_points([[0, 1]], "uv", dim=2, n=1).shape == (1, 2)
    assert np.isnan(as_points([[np.nan, 0, 0]], "x", finite=False)[0, 0])
    with pytest.raises(ShapeError, match=r"V must have shape \(k, 3\), got \(3,\)"):
        as_points([0, 1, 2], "V")
    with pytest.raises(ShapeError, match=r"V must have shape \(4, 3\), got \(2, 3\)"):
        as_points(np.zeros((2, 3)), "V", n=4)
    with pytest.raises(ShapeError, match=r"V must be an .* array of numbers"):
        as_points([[0, 1, 2], [3, 4]], "V")
    with pytest.raises(NonFiniteError, match=r"V: vertex 1 is not finite \(\[0.0, inf, 0.0\]\)"):
        as_points([[0, 0, 0], [0, np.inf, 0], [np.nan, 0, 0]], "V", item="vertex")
    with pytest.raises(NonFiniteError, match="points: point 0"):
        as_points([[np.nan, 0, 0]], "points")


def test_as_vec3():
    assert as_vec3((1, 2, 3), "c").tolist() == [1.0, 2.0, 3.0]
    with pytest.raises(ShapeError, match=r"c must be a 3-vector, got shape \(2,\)"):
        as_vec3((1, 2), "c")
    with pytest.raises(ShapeError, match="c must be a 3-vector of numbers"):
        as_vec3(("a", "b", "c"), "c")
    with pytest.raises(NonFiniteError, match="normal must be finite"):
        as_vec3((0, np.nan, 1), "normal")


def test_as_polyline():
    square = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 0, 0]]
    assert as_polyline(square, "c", closed=True).shape == (3, 3)           # repeated closing point dropped
    assert as_polyline(square, "c", closed=False).shape == (4, 3)
    assert as_polyline(square, "c").shape == (4, 3)
    # the minimum is counted before the closing point is dropped (as vortex.linking always did)
    assert as_polyline([[0, 0, 0], [1, 0, 0], [0, 0, 0]], "c", closed=True, min_points=3).shape == (2, 3)
    with pytest.raises(ShapeError, match=r"curve #2 must be an \(n, 3\) array of n >= 3 points, got shape \(2, 3\)"):
        as_polyline(np.zeros((2, 3)), "curve #2", min_points=3)
    with pytest.raises(ShapeError, match=r"got shape \(4, 2\)"):
        as_polyline(np.zeros((4, 2)), "c")
    with pytest.raises(NonFiniteError, match=r"a has a non-finite point \(row 2\)"):
        as_polyline([[0, 0, 0], [1, 0, 0], [np.nan, 0, 0]], "a")


def test_curve_list():
    fil = SimpleNamespace(points=np.eye(3), closed=True)
    out = curve_list([fil, (np.zeros((2, 3)), False), [[0, 0, 0]], np.zeros((0, 3))], "curves")
    assert [(P.shape, c) for P, c in out] == [((3, 3), True), ((2, 3), False), ((1, 3), False), ((0, 3), False)]
    assert len(curve_list(iter([np.eye(3)]), "curves")) == 1                  # any iterable
    with pytest.raises(ShapeError, match="curves must be a list"):
        curve_list(np.zeros((2, 3)), "curves")
    with pytest.raises(ShapeError, match=r"curves: curve 1 must have shape \(m, 3\), got \(3,\)"):
        curve_list([np.eye(3), [0, 0, 1]], "curves")
    with pytest.raises(ShapeError, match=r"curve 0 must be an .* array of numbers"):
        curve_list([[[0, 0, 0], [1, 0]]], "curves")
    with pytest.raises(NonFiniteError, match="curves: point 1 of curve 0 is not finite"):
        curve_list([[[0, 0, 0], [0, np.inf, 0]]], "curves")


def test_check_int():
    assert check_int(np.int32(5), "n", 1) == 5 and type(check_int(np.int32(5), "n")) is int
    assert check_int(-7, "q") == -7
    assert check_int(64, "refine", 1, 64) == 64
    for bad in (True, np.bool_(False), 2.0, "3", None):
        with pytest.raises(InvalidParameterError, match="n must be an integer, got"):
            check_int(bad, "n", 1)
    with pytest.raises(InvalidParameterError, match="n must be an integer >= 1, got 0; the grid needs a cell"):
        check_int(0, "n", 1, why="the grid needs a cell")
    with pytest.raises(InvalidParameterError, match="refine must be an integer between 1 and 64, got 65"):
        check_int(65, "refine", 1, 64)
    with pytest.raises(InvalidParameterError, match="k must be an integer <= 3, got 4"):
        check_int(4, "k", maximum=3)


def test_check_real():
    assert check_real(np.float32(0.5), "a") == 0.5 and type(check_real(1, "a")) is float
    assert check_real(np.inf, "a", finite=False) == np.inf
    for bad in (True, "1.0", 1j, None):
        with pytest.raises(InvalidParameterError, match="a must be a real number, got"):
            check_real(bad, "a")
    with pytest.raises(NonFiniteError, match="a must be finite, got nan"):
        check_real(np.nan, "a")
    with pytest.raises(InvalidParameterError, match="a must be a real number, got nan"):
        check_real(np.nan, "a", finite=False)
    with pytest.raises(InvalidParameterError, match=r"a must be a real number >= 0.0, got -1.0"):
        check_real(-1.0, "a", low=0.0)
    with pytest.raises(InvalidParameterError, match=r"a must be a real number <= 1.0, got 2.0"):
        check_real(2.0, "a", high=1.0)
    with pytest.raises(InvalidParameterError, match=r"a must be a real number in \[0.0, 1.0\], got 2.0"):
        check_real(2.0, "a", low=0.0, high=1.0)
