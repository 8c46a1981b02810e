"""The closed forms of dhlb.geometry._small agree with the LAPACK route they replace (n <= 2)."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb.geometry._small import eigvalsh_small, factor_from_edges, gradients_from_factor
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
