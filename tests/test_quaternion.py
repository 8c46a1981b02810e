"""Property tests of dhlb.conformal.quaternion: algebra, H ≅ C² (SU(2)), H ≅ R⁴ (SO(4)), exp/log."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from dhlb.conformal.quaternion import (
    as_quaternions,
    from_c2,
    imag,
    left_matrix,
    qconj,
    qexp,
    qlog,
    qmul,
    qnorm,
    qnormalize,
    right_matrix,
    sandwich_matrix,
    so4_matrix,
    su2_matrix,
    to_c2,
)
from dhlb.errors import NonFiniteError, ShapeError

finite = st.floats(-10, 10, allow_nan=False, allow_infinity=False)
quats = st.lists(finite, min_size=4, max_size=4).map(np.array)
vecs = st.lists(st.floats(-3, 3, allow_nan=False), min_size=3, max_size=3).map(np.array)
units = quats.filter(lambda q: np.linalg.norm(q) > 1e-3).map(lambda q: q / np.linalg.norm(q))


def close(a, b, scale=1.0):
    return np.allclose(a, b, rtol=1e-12, atol=1e-12 * scale)


def test_basis_relations():
    one, i, j, k = np.eye(4)
    for a in (i, j, k):
        assert close(qmul(a, a), -one)
    assert close(qmul(i, j), k) and close(qmul(j, k), i) and close(qmul(k, i), j)
    assert close(qmul(qmul(i, j), k), -one)                          # i j k = −1


@given(quats, quats, quats)
def test_associative(p, q, r):
    s = max(1.0, qnorm(p) * qnorm(q) * qnorm(r))
    assert close(qmul(qmul(p, q), r), qmul(p, qmul(q, r)), s)


@given(quats, quats)
def test_norm_multiplicative_and_conjugation_reverses(p, q):
    s = max(1.0, qnorm(p) * qnorm(q))
    assert np.isclose(qnorm(qmul(p, q)), qnorm(p) * qnorm(q), rtol=1e-12, atol=1e-12 * s)
    assert close(qconj(qmul(p, q)), qmul(qconj(q), qconj(p)), s)
    assert close(qmul(p, qconj(p)), [qnorm(p) ** 2, 0, 0, 0], s * s)


@given(vecs, vecs)
def test_imaginary_product_is_minus_dot_plus_cross(a, b):
    ab = qmul(imag(a), imag(b))
    assert np.isclose(ab[0], -a @ b, atol=1e-12) and close(ab[1:], np.cross(a, b), 10)


@given(quats, quats)
def test_c2_coordinates_su2_homomorphism(p, q):
    assert close(from_c2(to_c2(q)), q)
    assert np.isclose(np.linalg.norm(to_c2(q)), qnorm(q))
    s = max(1.0, qnorm(p) * qnorm(q))
    assert close(su2_matrix(p) @ to_c2(q), to_c2(qmul(p, q)), s)           # left mult is C-linear
    assert close(su2_matrix(qmul(p, q)), su2_matrix(p) @ su2_matrix(q), s)
    # the complex structure is right multiplication by i
    assert close(to_c2(qmul(q, [0, 1, 0, 0])), 1j * to_c2(q), max(1.0, qnorm(q)))


@given(units)
def test_unit_quaternions_are_su2_and_so4(p):
    U = su2_matrix(p)
    assert close(U.conj().T @ U, np.eye(2)) and np.isclose(np.linalg.det(U), 1.0)
    for Mx in (left_matrix(p), right_matrix(p)):
        assert close(Mx.T @ Mx, np.eye(4))


@given(units, units, quats)
def test_so4(p, r, q):
    R = so4_matrix(p, r)
    assert close(R @ R.T, np.eye(4)) and np.isclose(np.linalg.det(R), 1.0)
    assert close(R @ q, qmul(p, qmul(q, qconj(r))), max(1.0, qnorm(q)))


@given(units, vecs)
def test_sandwich_is_a_rotation(q, x):
    S = sandwich_matrix(q)
    assert close(S @ S.T, np.eye(3)) and np.isclose(np.linalg.det(S), 1.0)
    assert close(imag(S @ x), qmul(qconj(q), qmul(imag(x), q)), 10)


@given(vecs, st.floats(-2, 2))
def test_exp_unit_one_parameter_group_and_log(v, t):
    e = qexp(imag(v))
    assert np.isclose(qnorm(e), 1.0)
    assert close(qmul(qexp(imag(t * v)), qexp(imag((1 - t) * v))), e, 10)   # commuting exponents add
    if np.linalg.norm(v) < np.pi - 1e-3:
        assert close(qlog(e), imag(v), 10)
    h = 1e-6                                                            # d/dt exp(t v) = v exp(t v)
    d = (qexp(imag((t + h) * v)) - qexp(imag((t - h) * v))) / (2 * h)
    assert np.allclose(d, qmul(imag(v), qexp(imag(t * v))), atol=1e-7 * (1 + np.linalg.norm(v)) ** 3)


def test_small_angle_exp_is_accurate():
    v = np.array([1e-9, -2e-9, 3e-9])
    assert close(qexp(imag(v)), [1 - (v @ v) / 2, *v])


def test_bad_input():
    with pytest.raises(ShapeError, match=r"\(\.\.\., 4\)"):
        as_quaternions([1.0, 2.0])
    with pytest.raises(NonFiniteError):
        as_quaternions([np.nan, 0, 0, 0])
    with pytest.raises(NonFiniteError, match="zero quaternion"):
        qnormalize([0.0, 0, 0, 0])
    with pytest.raises(ShapeError):
        imag([1.0, 2.0])
    with pytest.raises(ShapeError):
        from_c2([1j])


@given(st.floats(1e-3, 1e3), st.integers(0, 3))
def test_log_of_a_real_quaternion_inverts_exp_also_for_negative_reals(r, k):
    # issue 27's audit: qlog(−r) dropped the π (qexp(qlog(−1)) was +1); it is log r + iπ, as for complex numbers
    q = np.zeros(4)
    q[0] = -r if k % 2 else r
    assert close(qexp(qlog(q)), q, 10)
    if k % 2:
        assert np.isclose(qlog(q)[1], np.pi)
