"""The closed forms of dhlb.geometry._small agree with the LAPACK route they replace (n <= 3)."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb.geometry._small import (
    cholesky_3,
    eigvalsh_small,
    factor_from_edges,
    gradient_gram_2,
    gradients_from_factor,
    gram_of_columns,
    surely_definite_3,
)
from dhlb.geometry.simplex import SimplexStack


def _edges(seed, m, d, n, squash=1.0):
    rng = np.random.default_rng(seed)
    E = rng.standard_normal((m, d, n))
    if n == 2:
        E[:, :, 1] = E[:, :, 0] + squash * E[:, :, 1]  # squash -> 0: nearly degenerate triangles
    return E


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**31), d=st.integers(2, 5), n=st.integers(1, 2),
       squash=st.sampled_from([1.0, 1e-3, 1e-6]))
def test_factor_matches_qr_up_to_row_signs(seed, d, n, squash):
    E = _edges(seed, 50, d, n, squash)
    R, g = factor_from_edges(E)
    Rq = np.linalg.qr(E, mode="r")
    sign = np.sign(np.diagonal(Rq, axis1=1, axis2=2))
    np.testing.assert_allclose(R, sign[:, :, None] * Rq, rtol=1e-9, atol=1e-12 * np.abs(Rq).max())
    np.testing.assert_allclose(g, np.swapaxes(E, 1, 2) @ E, rtol=1e-13, atol=1e-13)
    assert np.all(np.diagonal(R, axis1=1, axis2=2) >= 0)


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**31), n=st.integers(1, 2), squash=st.sampled_from([1.0, 1e-4]))
def test_eigenvalues_match_eigvalsh(seed, n, squash):
    R, g = factor_from_edges(_edges(seed, 50, 3, n, squash))
    ev = eigvalsh_small(g)
    ref = np.linalg.eigvalsh(g)
    np.testing.assert_allclose(ev, ref, rtol=1e-7, atol=1e-14 * ref[:, -1:].max())
    det = np.prod(np.diagonal(R, axis1=1, axis2=2), axis=1) ** 2
    np.testing.assert_allclose(eigvalsh_small(g, det), ref, rtol=1e-7, atol=1e-14 * ref.max())


def test_small_eigenvalue_of_a_thin_triangle_to_relative_accuracy():
    # e1 = (1, 0, 0), e2 = (1, t, 0): det g = t², λ_max = 1 + 1 + ...; λ_min = t² / λ_max exactly
    t = 1e-9
    R, g = factor_from_edges(np.array([[[1.0, 1.0], [0.0, t], [0.0, 0.0]]]))
    det = np.prod(np.diagonal(R, axis1=1, axis2=2), axis=1) ** 2
    lo, hi = eigvalsh_small(g, det)[0]
    assert abs(lo * hi - t * t) <= 1e-15 * t * t


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**31), n=st.integers(1, 2))
def test_gradients_are_dual_to_the_edges(seed, n):
    R, _ = factor_from_edges(_edges(seed, 30, 3, n))
    Y = gradients_from_factor(R)
    # in the frame of R the edges are R's columns: dλ_a(e_b) = δ_ab, and the gradients sum to 0
    np.testing.assert_allclose(np.swapaxes(Y[:, :, 1:], 1, 2) @ R, np.broadcast_to(np.eye(n), (30, n, n)),
                               atol=1e-10)
    np.testing.assert_allclose(Y.sum(axis=2), 0, atol=1e-12)


def test_simplex_stack_triangle_quantities_match_the_lapack_route():
    rng = np.random.default_rng(5)
    P = rng.standard_normal((200, 3, 3))
    S = SimplexStack.from_points(P)
    L = SimplexStack.from_squared_lengths(S.squared_lengths)  # Cholesky route, independent of the closed forms
    np.testing.assert_allclose(S.volumes, 0.5 * np.linalg.norm(np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]),
                                                               axis=1), rtol=1e-12)
    np.testing.assert_allclose(S.barycentric_gradient_gram, L.barycentric_gradient_gram, rtol=1e-8, atol=1e-10)
    np.testing.assert_allclose(S.cotan_weights, L.cotan_weights, rtol=1e-8, atol=1e-10)


def _metrics_3(seed, m, squash):
    """Random tetrahedron metrics, some nearly flat (squash), some indefinite (lengths not realizable)."""
    rng = np.random.default_rng(seed)
    E = rng.standard_normal((m, 3, 3))
    E[:, :, 2] = E[:, :, 0] + E[:, :, 1] + squash * E[:, :, 2]
    g = np.swapaxes(E, 1, 2) @ E
    g[: m // 4, 2, 2] *= 0.01                               # indefinite or degenerate
    return 0.5 * (g + np.swapaxes(g, 1, 2))


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**31), squash=st.sampled_from([1.0, 1e-3, 1e-6, 1e-9]))
def test_cholesky_3_and_the_certificate_match_lapack(seed, squash):
    g = _metrics_3(seed, 40, squash)
    R = cholesky_3(g)
    ev = np.linalg.eigvalsh(g)
    ok = ev[:, 0] > 1e-10 * ev[:, -1]                     # the factor is defined to ~eps·cond
    if ok.any():
        Rl = np.swapaxes(np.linalg.cholesky(g[ok]), 1, 2)
        np.testing.assert_allclose(R[ok], Rl, rtol=1e-5, atol=1e-12 * np.abs(Rl).max())
    assert np.isnan(R[ev[:, 0] < -1e-8 * ev[:, -1]]).any(axis=(1, 2)).all()  # indefinite: a pivot fails
    # the certificate never accepts a simplex the exact test rejects
    sure = surely_definite_3(g, R, 100 * 3 * np.finfo(float).eps)
    assert not np.any(sure & (ev[:, 0] <= 100 * 3 * np.finfo(float).eps * ev[:, -1]))
    assert sure[ev[:, 0] > 1e-3 * ev[:, -1]].all()        # and accepts well-shaped ones


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**31))
def test_tetrahedra_closed_forms_match_the_lapack_route(seed):
    rng = np.random.default_rng(seed)
    P = rng.standard_normal((60, 4, 3))
    P[:5, 3] = P[:5, 0] + 0.5 * (P[:5, 1] - P[:5, 0]) + 0.5 * (P[:5, 2] - P[:5, 0])    # coplanar: degenerate
    S = SimplexStack.from_points(P)
    ev = np.linalg.eigvalsh(S.metric)
    ref = np.where(ev[:, 0] / ev[:, -1] > S.rtol, 0, np.where(ev[:, 0] / ev[:, -1] >= -S.rtol, 1, 2))
    assert np.array_equal(S.status, ref)
    ok = S.positive_definite
    det = np.linalg.det(P[:, 1:] - P[:, :1])
    np.testing.assert_allclose(S.volumes[ok], np.abs(det[ok]) / 6, rtol=1e-10)
    D = np.hstack([-np.ones((3, 1)), np.eye(3)])
    G = np.swapaxes(D, 0, 1) @ np.linalg.inv(S.metric[ok]) @ D
    np.testing.assert_allclose(S.barycentric_gradient_gram[ok], G, rtol=1e-8, atol=1e-10 * np.abs(G).max())
    Y = S.barycentric_gradients[ok]
    eye = np.broadcast_to(np.eye(3), (int(ok.sum()), 3, 3))
    E = np.swapaxes(P[:, 1:] - P[:, :1], 1, 2)[ok]           # in R³ the gradients are in the ambient frame
    np.testing.assert_allclose(np.swapaxes(Y[:, :, 1:], 1, 2) @ E, eye, atol=1e-9)
    L = SimplexStack.from_squared_lengths(S.squared_lengths)   # lengths: the Cholesky frame
    np.testing.assert_allclose(np.swapaxes(L.barycentric_gradients[ok][:, :, 1:], 1, 2) @ L.factor[ok], eye, atol=1e-8)
    np.testing.assert_allclose(L.barycentric_gradient_gram[ok], G, rtol=1e-6, atol=1e-9 * np.abs(G).max())


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**31), d=st.integers(2, 4), squash=st.sampled_from([1.0, 1e-6]),
       scale=st.sampled_from([1.0, 1e-60, 1e60]))   # beyond 1e±75 the edge factor itself overflows
def test_gradient_gram_2_is_the_gram_of_the_gradients_to_the_bit(seed, d, squash, scale):
    R, _ = factor_from_edges(scale * _edges(seed, 50, d, 2, squash))
    G = gradient_gram_2(R)
    assert np.array_equal(G, gram_of_columns(gradients_from_factor(R)))
    S = SimplexStack.from_points(np.random.default_rng(seed).standard_normal((30, 3, d)))
    assert np.array_equal(S.barycentric_gradient_gram, gram_of_columns(S.barycentric_gradients))
