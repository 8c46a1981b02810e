"""Gauss linking numbers of polylines (exact segment-pair formula) and polyline distances."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb.errors import CurveIntersectionError, InvalidParameterError, NonFiniteError, ShapeError
from dhlb.vortex import (
    gauss_linking_integral,
    hausdorff_distance,
    hopf_link,
    linking_matrix,
    linking_number,
    polyline_distance,
    torus_knot,
    trefoil,
    vortex_ring,
)


def brute_gauss(a, b, k=30):
    """Midpoint-rule Gauss double integral (an independent, approximate reference)."""
    def sample(C):
        t = (np.arange(k) + 0.5) / k
        D = np.roll(C, -1, axis=0) - C
        return (C[:, None] + t[None, :, None] * D[:, None]).reshape(-1, 3), np.repeat(D / k, k, axis=0)
    p, dp = sample(a)
    q, dq = sample(b)
    D = p[:, None] - q[None]
    return float(np.einsum("ijk,ijk->", D, np.cross(dp[:, None], dq[None]) / np.linalg.norm(D, axis=2)[..., None] ** 3)
                 / (4 * np.pi))


def rotation(seed):
    Q, _ = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    return Q * np.sign(np.linalg.det(Q))  # proper rotation


def test_hopf_link_sign_matches_the_gauss_integral():
    a, b = hopf_link(n=40)
    assert linking_number(a, b) == 1
    assert abs(brute_gauss(a, b) - 1) < 1e-3  # the sign convention is Gauss's
    assert linking_number(a, b[::-1]) == -1 and linking_number(a[::-1], b[::-1]) == 1
    assert linking_number(b, a) == 1


def test_unlinked_rings():
    a = vortex_ring(1.0, n=30)
    assert linking_number(a, vortex_ring(1.0, center=(3.0, 0, 0), n=30)) == 0
    assert linking_number(a, vortex_ring(0.5, center=(0, 0, 0.5), n=30)) == 0  # stacked coaxial
    assert linking_number(a, vortex_ring(2.0, n=30)) == 0  # coplanar, concentric: every pair contributes 0
    assert abs(gauss_linking_integral(a, vortex_ring(2.0, n=30))) < 1e-14
    # the (2, 1) torus curve (an unknot) winds twice around the z-axis and misses a small central ring
    assert linking_number(torus_knot(2, 1, 1.0, 0.4, 200), vortex_ring(0.3, n=50)) == 0
    axis = np.array([[0, 0, -5.0], [0, 0, 5.0], [50, 0, 5.0], [50, 0, -5.0]])  # up the z-axis, back far out
    assert linking_number(torus_knot(2, 1, 1.0, 0.4, 200), axis) == 2


def test_trefoil_self_consistency():
    K = trefoil(1.0, 0.4, n=300)
    core = vortex_ring(1.0, n=300)
    axis = np.array([[0, 0, -5.0], [0, 0, 5.0], [50, 0, 5.0], [50, 0, -5.0]])
    assert linking_number(K, core) == -3  # three meridional turns, left-handed about the core
    assert linking_number(K, axis) == 2  # two turns around the z-axis
    assert abs(brute_gauss(K, core, 4) + 3) < 1e-2
    # a small ring around one strand, right-handed about its direction, links it once
    t = K[1] - K[-1]
    assert linking_number(K, vortex_ring(0.05, center=K[0], normal=t, n=40)) == 1
    assert linking_number(K, vortex_ring(0.05, center=K[0] + [0, 0, 2.0], normal=t, n=40)) == 0
    # for the (3, 2) torus knot (also a trefoil) the two numbers swap roles
    K32 = torus_knot(3, 2, 1.0, 0.4, 300)
    assert (linking_number(K32, core), linking_number(K32, axis)) == (-2, 3)


@settings(max_examples=12, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 4), st.integers(0, 3))
def test_linking_number_is_invariant(seed, refine, shift):
    """Rigid motions, refinement (inserting midpoints), cyclic shifts and scaling change nothing."""
    K = trefoil(1.0, 0.4, n=90)
    core = vortex_ring(1.0, n=60)
    Q = rotation(seed)
    move = lambda C: 1.7 * C @ Q.T + [0.3, -2.0, 1.0]  # noqa: E731
    fine = np.repeat(core, refine, axis=0) + (np.arange(refine * 60) % refine / refine)[:, None] * np.repeat(
        np.roll(core, -1, axis=0) - core, refine, axis=0)
    assert linking_number(move(np.roll(K, shift, axis=0)), move(fine)) == -3


def test_linking_matrix():
    a, b = hopf_link(n=30)
    c = vortex_ring(0.2, center=(-1.0, 0, 0), normal=(0, -1.0, 0), n=30)  # around ring a's strand at (-1, 0, 0)
    M = linking_matrix([a, b, c, vortex_ring(center=(9.0, 0, 0), n=20)])
    assert np.array_equal(M, M.T) and np.all(np.diag(M) == 0)
    assert M[0, 1] == 1 and M[0, 2] == 1 and M[1, 2] == 0 and not M[3].any()


def test_intersecting_curves_raise():
    a = vortex_ring(1.0, n=8)
    b = vortex_ring(1.0, center=(1.0, 0, 0), normal=(0, 1.0, 0), n=8)  # passes through the vertex (1, 0, 0) of a
    b = b - b[0] + a[0]
    with pytest.raises(CurveIntersectionError, match="intersect"):
        linking_number(a, b)
    with pytest.raises(CurveIntersectionError):
        linking_matrix([a, b])


def test_linking_bad_input():
    with pytest.raises(ShapeError):
        linking_number(np.zeros((2, 3)), vortex_ring())
    with pytest.raises(ShapeError):
        linking_number(np.zeros((5, 2)), vortex_ring())
    with pytest.raises(NonFiniteError):
        linking_number(np.where(np.arange(30).reshape(10, 3) == 4, np.nan, vortex_ring(n=10)), vortex_ring())


def test_polyline_and_hausdorff_distance():
    assert polyline_distance([[0.0, 0, 0]], vortex_ring(2.0, n=4)).tolist() == [pytest.approx(np.sqrt(2))]
    # ring vs a slightly bigger ring: exactly the radius difference (sampled finely)
    h = hausdorff_distance(vortex_ring(1.0, n=100), vortex_ring(1.1, n=100), spacing=1e-3)
    assert h == pytest.approx(0.1, abs=1e-9)
    # a polygon vs its circle: the sagitta R (1 − cos(π/n)), within spacing / 2
    n = 12
    h = hausdorff_distance(vortex_ring(1.0, n=n), vortex_ring(1.0, n=4000), spacing=1e-3)
    assert abs(h - (1 - np.cos(np.pi / n))) < 1e-3
    # open chains: a segment vs a longer one on the same line
    seg, longer = np.array([[0, 0, 0], [1.0, 0, 0]]), np.array([[0, 0, 0], [3.0, 0, 0]])
    assert hausdorff_distance(seg, longer, closed=(False, False)) == pytest.approx(2.0)
    with pytest.raises(InvalidParameterError):
        hausdorff_distance(seg, longer, closed=(False, False), spacing=0.0)
    with pytest.raises(ShapeError):
        polyline_distance(np.zeros(3), seg, closed=False)
