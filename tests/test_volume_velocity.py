"""Velocity 1-forms (Gauss–Legendre edge integrals), the velocity bundle, and Biot–Savart fields."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb.errors import InvalidParameterError, NonFiniteError, ShapeError
from dhlb.mesh import box_tet_mesh
from dhlb.vortex import (
    FilamentField,
    edge_circulation,
    gauss_legendre,
    hopf_link,
    segment_velocity,
    superpose,
    trefoil,
    uniform_flow,
    velocity_bundle,
    vortex_ring,
)

RNG = np.random.default_rng(7)
P0 = RNG.normal(size=(12, 3))
E0 = np.array([(i, j) for i in range(12) for j in range(12) if i != j])


def poly_field(coef, degree):
    """v_k(x) = Σ_{a+b+c <= degree} coef[k, a, b, c] x^a y^b z^c."""
    def v(x):
        out = np.zeros_like(x)
        for a in range(degree + 1):
            for b in range(degree + 1 - a):
                for c in range(degree + 1 - a - b):
                    out += coef[:, a, b, c] * (x[:, :1] ** a * x[:, 1:2] ** b * x[:, 2:] ** c)
        return out
    return v


# ---------------------------------------------------------------------------- quadrature
@pytest.mark.parametrize("order", [1, 2, 3, 4, 5])
def test_gauss_legendre_is_exact_up_to_degree_2q_minus_1(order):
    s, w = gauss_legendre(order)
    assert w.sum() == pytest.approx(1.0, abs=1e-15) and np.all((0 < s) & (s < 1))
    for d in range(2 * order):
        assert w @ s**d == pytest.approx(1 / (d + 1), rel=1e-13)
    assert abs(w @ s ** (2 * order) - 1 / (2 * order + 1)) > 1e-6


@settings(max_examples=10, deadline=None)
@given(st.integers(1, 4), st.integers(0, 2**32 - 1))
def test_edge_integral_exact_for_polynomial_fields(order, seed):
    rng = np.random.default_rng(seed)
    degree = 2 * order - 1
    v = poly_field(rng.normal(size=(3, degree + 1, degree + 1, degree + 1)), degree)
    ref = edge_circulation(P0, E0, v, order=12)  # exact for degree <= 23
    got = edge_circulation(P0, E0, v, order=order)
    assert np.allclose(got, ref, rtol=1e-11, atol=1e-11 * np.abs(ref).max())
    # and the orientation: reversing an edge flips the sign
    assert np.allclose(edge_circulation(P0, E0[:, ::-1], v, order=order), -got, rtol=1e-12, atol=1e-12)


@settings(max_examples=10, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_per_vertex_velocity_is_the_exact_integral_of_the_linear_interpolant(seed):
    rng = np.random.default_rng(seed)
    A, b = rng.normal(size=(3, 3)), rng.normal(size=3)
    lin = lambda x: x @ A.T + b  # noqa: E731  (linear: the interpolant is the field itself)
    per_vertex = edge_circulation(P0, E0, lin(P0))
    assert np.allclose(per_vertex, edge_circulation(P0, E0, lin, order=1), rtol=1e-12, atol=1e-12)
    assert np.allclose(per_vertex, 0.5 * np.einsum("ek,ek->e", lin(P0)[E0[:, 0]] + lin(P0)[E0[:, 1]],
                                                   P0[E0[:, 1]] - P0[E0[:, 0]]), rtol=0, atol=0)


@pytest.mark.parametrize("order", [1, 2, 3])
def test_edge_integral_converges_at_order_2q_plus_1(order):
    def v(x):
        return np.stack([np.sin(x[:, 1]) * np.exp(x[:, 0]), np.cos(x[:, 2] + x[:, 0]), np.exp(-x[:, 1] ** 2)], axis=1)

    x0, d = np.array([[0.1, -0.3, 0.2]]), np.array([0.6, 0.48, 0.64])
    errs = []
    for h in (0.4, 0.2, 0.1):
        P = np.vstack([x0, x0 + h * d])
        ref = edge_circulation(P, [[0, 1]], v, order=20)[0]
        errs.append(abs(edge_circulation(P, [[0, 1]], v, order=order)[0] - ref))
    rates = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(np.abs(rates - (2 * order + 1)) < 0.2), rates


def test_edge_circulation_bad_input():
    v = lambda x: x  # noqa: E731
    with pytest.raises(ShapeError, match="one 3-vector per vertex"):
        edge_circulation(P0, E0, np.zeros((11, 3)))
    with pytest.raises(ShapeError):
        edge_circulation(P0, E0, np.zeros((12, 2)))
    with pytest.raises(ShapeError, match="returned shape"):
        edge_circulation(P0, E0, lambda x: x[:, :2])
    with pytest.raises(ShapeError):
        edge_circulation(P0[:, :2], E0, v)
    with pytest.raises(ShapeError, match="outside"):
        edge_circulation(P0, [[0, 12]], v)
    with pytest.raises(ShapeError):
        edge_circulation(P0, E0.astype(float), v)
    bad = np.zeros((12, 3))
    bad[5, 1] = np.nan
    with pytest.raises(NonFiniteError, match="vertex 5"):
        edge_circulation(P0, E0, bad)
    with pytest.raises(NonFiniteError, match=r"edge #0 \(0, 1\)"):
        edge_circulation(P0, E0, lambda x: np.where(x > 1e9, 0.0, np.inf))
    with pytest.raises(NonFiniteError, match="vertex 3"):
        edge_circulation(np.where(np.arange(36).reshape(12, 3) == 10, np.inf, P0), E0, v)
    with pytest.raises(InvalidParameterError):
        edge_circulation(P0, E0, v, order=0)
    with pytest.raises(ShapeError):
        edge_circulation(P0, E0, "fast")


# ---------------------------------------------------------------------------- the bundle
def test_velocity_bundle_curvature_is_the_flux_of_curl_over_hbar():
    mesh = box_tet_mesh(2, lower=-1.0, upper=1.0)
    X, P = mesh.complex, mesh.points
    B = np.array([0.3, -1.2, 2.0])
    hbar = 0.37
    L = velocity_bundle(X, P, lambda x: 0.5 * np.cross(B, x), hbar, order=1)  # curl = B
    tri = P[X.simplices(2)]
    flux = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]) @ B / 2
    assert np.allclose(L.curvature, flux / hbar, rtol=1e-12, atol=1e-13)
    w = edge_circulation(P, X.simplices(1), lambda x: 0.5 * np.cross(B, x))
    assert np.allclose(L.connection, np.exp(1j * w / hbar))
    # the curvature is not wrapped: with a small hbar it exceeds π
    L2 = velocity_bundle(X, P, 0.5 * np.cross(B, P), 1e-3)
    assert np.abs(L2.curvature).max() > 100 and np.allclose(L2.curvature, flux / 1e-3, rtol=1e-12)


@pytest.mark.parametrize("hbar", [0.0, -1.0, np.nan, np.inf, "x", None])
def test_velocity_bundle_rejects_bad_hbar(hbar):
    mesh = box_tet_mesh(1)
    with pytest.raises(InvalidParameterError, match="hbar"):
        velocity_bundle(mesh.complex, mesh.points, np.zeros((8, 3)), hbar)


def test_velocity_bundle_points_must_match_the_complex():
    mesh = box_tet_mesh(1)
    with pytest.raises(ShapeError, match="one row per vertex"):
        velocity_bundle(mesh.complex, mesh.points[:7], np.zeros((7, 3)), 1.0)


# ---------------------------------------------------------------------------- Biot–Savart
def test_polygon_on_axis_field_is_exact():
    R, n, G = 1.3, 7, 2.5
    z = np.linspace(-2, 2, 9)
    u = FilamentField([vortex_ring(R, n=n)], circulation=G)(np.stack([0 * z, 0 * z, z], axis=1))
    rho, half = R * np.cos(np.pi / n), R * np.sin(np.pi / n)
    d2 = z**2 + rho**2
    exact = n * G / (4 * np.pi) * 2 * half * rho / (d2 * np.sqrt(d2 + half**2))
    assert np.allclose(u[:, 2], exact, rtol=1e-13) and np.allclose(u[:, :2], 0, atol=1e-14)


def test_ring_field_matches_the_analytic_on_axis_field():
    R, G = 0.8, 1.7
    z = np.linspace(-1.5, 1.5, 7)
    x = np.stack([0 * z, 0 * z, z], axis=1)
    exact = G * R**2 / (2 * (R**2 + z**2) ** 1.5)
    for n, a, tol in [(2000, 1e-4, 1e-5), (200, 0.0, 2e-4)]:
        u = FilamentField([vortex_ring(R, n=n)], circulation=G, core_radius=a)(x)
        assert np.allclose(u[:, 2], exact, rtol=tol, atol=0)
    # the core radius changes the field by O(a²)
    u = FilamentField([vortex_ring(R, n=2000)], circulation=G, core_radius=0.05)(x)
    assert 1e-4 < np.abs(u[:, 2] / exact - 1).max() < 0.05**2 * 10


@pytest.mark.parametrize("core", [0.0, 0.01])
def test_circulation_around_a_small_loop_counts_linking(core):
    G, rho = 1.9, 0.2
    v = FilamentField([vortex_ring(1.0, n=300)], circulation=G, core_radius=core)
    # a small loop around the ring's strand at (1, 0, 0), right-handed about the strand's direction +y
    loop = vortex_ring(rho, center=(1.0, 0.0, 0.0), normal=(0.0, 1.0, 0.0), n=120)
    edges = np.stack([np.arange(120), np.roll(np.arange(120), -1)], axis=1)
    circ = edge_circulation(loop, edges, v).sum()
    far = edge_circulation(loop + [2.5, 0, 0], edges, v).sum()
    # exact for the singular field (Ampère); the regularization costs O(a²/ρ²) (measured 1.0 (a/ρ)²)
    tol, tol_far = (1e-9, 1e-9) if core == 0 else (2 * (core / rho) ** 2, 1e-6)
    assert abs(circ - G) < tol * G and abs(far) < tol_far
    assert abs(edge_circulation(loop[::-1], edges, v).sum() + circ) < 1e-12


def test_linked_and_knotted_fields_have_the_right_circulations():
    a, b = hopf_link(1.0, n=200)
    v = FilamentField([a, b], circulation=[1.0, -2.0])
    loop_a = vortex_ring(0.15, center=(1.0, 0, 0), normal=(0, 1.0, 0), n=80)  # around ring a at (1, 0, 0)
    edges = np.stack([np.arange(80), np.roll(np.arange(80), -1)], axis=1)
    assert edge_circulation(loop_a, edges, v).sum() == pytest.approx(1.0, abs=1e-9)
    # ring b passes (R, 0, R) heading in +x: a loop right-handed about +x there encloses −2
    loop_b = vortex_ring(0.15, center=(1.0, 0, 1.0), normal=(1.0, 0, 0), n=80)
    assert edge_circulation(loop_b, edges, v).sum() == pytest.approx(-2.0, abs=1e-9)
    K = trefoil(n=400)
    vk = FilamentField([K], circulation=0.5)
    t = np.gradient(K, axis=0)[0]
    loop_k = vortex_ring(0.05, center=K[0], normal=t, n=80)
    assert edge_circulation(loop_k, edges, vk).sum() == pytest.approx(0.5, abs=1e-7)


def test_field_helpers():
    x = RNG.normal(size=(5, 3))
    u = uniform_flow([1.0, -2.0, 0.5])
    ring = FilamentField([vortex_ring(1.0, n=50)], core_radius=0.1)
    s = superpose(u, ring, weights=[2.0, 3.0])
    assert np.allclose(s(x), 2 * u(x) + 3 * ring(x))
    # chunking does not change the result; segment_velocity sums segments
    C = vortex_ring(1.0, n=50)
    full = segment_velocity(x, C, np.roll(C, -1, axis=0), 1.0, 0.1)
    assert np.allclose(segment_velocity(x, C, np.roll(C, -1, axis=0), 1.0, 0.1, chunk=7), full, rtol=1e-14, atol=0)
    assert np.allclose(full, ring(x), rtol=1e-14)
    # a closed curve given with its first point repeated is the same curve
    assert np.allclose(FilamentField([np.vstack([C, C[:1]])], core_radius=0.1)(x), full, rtol=1e-14)
    # the singular field is 0 (not NaN) on a segment's own line
    assert np.all(np.isfinite(FilamentField([C])(C)))


def test_field_bad_input():
    with pytest.raises(ShapeError):
        FilamentField([])
    with pytest.raises(ShapeError):
        FilamentField([np.zeros((1, 3))])
    with pytest.raises(NonFiniteError):
        FilamentField([[[0, 0, 0], [1, np.nan, 0]]], closed=False)
    with pytest.raises(InvalidParameterError):
        FilamentField([vortex_ring()], core_radius=-0.1)
    with pytest.raises(ShapeError):
        FilamentField([vortex_ring()])(np.zeros((3, 2)))
    with pytest.raises(ShapeError):
        uniform_flow([1.0, 2.0])
    with pytest.raises(ShapeError):
        superpose()
    with pytest.raises(ShapeError):
        superpose(uniform_flow([0, 0, 1.0]), weights=[1.0, 2.0])
