"""Θ, Λ, Ξ, the divided differences and moments of dhlb.fem.integrals (seed part 3, §11-§12), and its errors.

References: 60-digit mpmath (divided differences as exp of the Opitz matrix, ``tests/integral_references.py``);
the local FEM matrices are tested in ``test_integrals_local.py``.
"""

from math import factorial

import numpy as np
import pytest

from dhlb import errors
from dhlb.fem.integrals import (
    curvature_tensor,
    expi_divided_difference,
    expi_moment,
    lambda_,
    local_dirichlet_matrices,
    local_edges,
    local_mass_matrices,
    theta,
    xi,
)
from tests.integral_references import closed_data, mp_divided_difference, mp_pair_moment

RTOL = 1e-12


# ------------------------------------------------------------------------------------------------
# divided differences and moments against mpmath
# ------------------------------------------------------------------------------------------------

def test_divided_difference_against_mpmath_all_regimes():
    rng = np.random.default_rng(0)
    worst = 0.0
    for _ in range(150):
        c = int(rng.integers(1, 4))
        mult = rng.integers(1, 5, c)
        th = rng.choice([-1, 1], c) * 10.0 ** rng.uniform(-9, 3.5, c)
        if rng.random() < 0.3:
            th[0] = 0.0
        for q in range(1, c):
            if rng.random() < 0.4:   # nearly coinciding or far-but-clustered nodes
                th[q] = th[rng.integers(q)] + rng.choice([-1, 1]) * 10.0 ** rng.uniform(-9, 1.2)
        ref = mp_divided_difference(list(1j * np.repeat(th, mult)))
        worst = max(worst, abs(expi_divided_difference(th, mult) - ref) / abs(ref))
    assert worst < RTOL


def test_divided_difference_exact_values():
    assert expi_divided_difference(np.zeros(3), [2, 3, 1]) == 1 / factorial(5)
    t = 3.7
    assert np.isclose(expi_divided_difference([0.0, t], [1, 1]), (np.exp(1j * t) - 1) / (1j * t), rtol=1e-15, atol=0)
    # confluent: exp[z^(m)] = e^z / (m-1)!
    assert np.isclose(expi_divided_difference([5.0], [4]), np.exp(5j) / 6, rtol=1e-15, atol=0)
    # batched shape
    assert expi_divided_difference(np.zeros((2, 5, 2)), [1, 1]).shape == (2, 5)


def test_divided_difference_modulus_bound():
    """|exp[iθ...]| <= 1/N! (Hermite-Genocchi with |e^{iθ·x}| = 1)."""
    rng = np.random.default_rng(1)
    th = rng.normal(size=(500, 3)) * 20
    v = expi_divided_difference(th, [3, 2, 2])
    assert np.all(np.abs(v) <= 1 / factorial(6) * (1 + 1e-12))


@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_expi_moment_against_mpmath(n):
    rng = np.random.default_rng(n)
    for _ in range(10):
        th = rng.choice([-1, 1], n + 1) * 10.0 ** rng.uniform(-8, 3, n + 1)
        p = rng.integers(0, 3, n + 1)
        nodes = [1j * th[m] for m in range(n + 1) for _ in range(p[m] + 1)]
        ref = factorial(n) * np.prod([factorial(int(k)) for k in p]) * mp_divided_difference(nodes)
        assert abs(expi_moment(th, p) - ref) <= RTOL * abs(ref)


@pytest.mark.parametrize("n", [2, 3])
def test_theta_lambda_xi_against_mpmath_tiny_and_huge_curvature(n):
    rng = np.random.default_rng(10 + n)
    for scale in (1e-9, 1e-3, 0.5, 3.0, 40.0, 1e3):
        om, _ = closed_data(rng, n, scale)
        t = curvature_tensor(om)
        for i, j in [(0, 1), (1, 0), (0, n), (n - 1, n), (1, 1)]:
            ref = mp_pair_moment(t, i, j, [0] * (n + 1))
            assert abs(lambda_(om, i, j) - ref) <= RTOL * abs(ref)
            for k, l in [(i, j), (i, i), (j, n), (0, n - 1)]:
                p = [0] * (n + 1)
                p[k] += 1
                p[l] += 1
                ref = mp_pair_moment(t, i, j, p)
                assert abs(theta(om, i, j, k, l) - ref) <= RTOL * abs(ref)
                for v in (i, j):
                    p[v] += 1
                ref = mp_pair_moment(t, i, j, p)
                assert abs(xi(om, i, j, k, l) - ref) <= RTOL * abs(ref)


def test_theta_vectorized_matches_single():
    rng = np.random.default_rng(3)
    om = np.stack([closed_data(rng, 3, s)[0] for s in (0.01, 1.0, 7.0, 300.0)])
    batch = theta(om, 0, 2, 1, 3)
    assert batch.shape == (4,)
    for s in range(4):
        assert theta(om[s], 0, 2, 1, 3) == pytest.approx(batch[s], rel=1e-15)


def test_theta_hermitian_in_pair_and_flat_values():
    om = np.array([0.3, -1.2, 0.4, 0.0])
    om[3] = om[2] - om[1] + om[0]
    assert theta(om, 2, 1, 0, 3) == pytest.approx(np.conj(theta(om, 1, 2, 0, 3)), rel=1e-14)
    assert xi(om, 3, 0, 1, 1) == pytest.approx(np.conj(xi(om, 0, 3, 1, 1)), rel=1e-14)
    zero = np.zeros(4)
    # Dirichlet moments n! p! / (n + |p|)!
    assert theta(zero, 0, 1, 0, 1) == pytest.approx(6 / 120, rel=1e-15)
    assert theta(zero, 0, 1, 2, 2) == pytest.approx(12 / 120, rel=1e-15)
    assert lambda_(zero, 0, 1) == 1
    assert xi(zero, 0, 1, 0, 1) == pytest.approx(6 * 4 / factorial(7), rel=1e-15)


def test_single_theta_scalar_and_dim_one():
    assert np.ndim(theta([0.2], 0, 1, 0, 1)) == 0
    assert lambda_(np.zeros(0), 0, 1, dim=1) == 1
    assert theta(np.zeros(0), 0, 1, 0, 1) == pytest.approx(1 / 6, rel=1e-15)   # n = 1: 1!/3!


# ------------------------------------------------------------------------------------------------
# errors
# ------------------------------------------------------------------------------------------------

G2 = np.array([[2.0, -1.0, -1.0], [-1.0, 1.0, 0.0], [-1.0, 0.0, 1.0]])


@pytest.mark.parametrize("call,exc,text", [
    (lambda: local_mass_matrices(1.0, [0.1, 0.2]), errors.ShapeError, "C(n+1, 3)"),
    (lambda: local_mass_matrices(1.0, [np.nan]), errors.NonFiniteError, "simplex 0"),
    (lambda: local_mass_matrices(1.0, [1j]), errors.CurvatureMismatchError, "real"),
    (lambda: local_mass_matrices(-1.0, [0.0]), errors.DegenerateSimplexError, "simplex 0"),
    (lambda: local_mass_matrices([1.0, 0.0], [[0.0], [0.0]]), errors.DegenerateSimplexError, "simplex 1"),
    (lambda: local_mass_matrices([1.0, 2.0, 3.0], [[0.0], [0.0]]), errors.ShapeError, "inconsistent"),
    (lambda: local_mass_matrices(1.0, [0.1, 0.2, 0.3, 0.0]), errors.NotClosedError, "tetrahedron (0, 1, 2, 3)"),
    (lambda: local_mass_matrices(1.0, [0.0, 0.0, 0.0, 2 * np.pi]), errors.NotClosedError, "vortex"),
    (lambda: local_mass_matrices(1.0, [0.3], [1, 1, 1]), errors.CurvatureMismatchError, "triangle (0, 1, 2)"),
    (lambda: local_mass_matrices(1.0, [0.0], [2, 2, 1]), errors.InvalidConnectionError, "unit"),
    (lambda: local_mass_matrices(1.0, [0.0], [1, 1]), errors.ShapeError, "connection"),
    (lambda: local_dirichlet_matrices(G2[:2], 1.0, [0.0]), errors.ShapeError, "gram"),
    (lambda: local_dirichlet_matrices(G2 + np.eye(3), 1.0, [0.0]), errors.InvalidMetricError, "sum"),
    (lambda: local_dirichlet_matrices(-G2, 1.0, [0.0]), errors.InvalidMetricError, "semidefinite"),
    (lambda: local_dirichlet_matrices(G2, 1.0, [0.0, 0, 0, 0]), errors.ShapeError, "curvature"),
    (lambda: theta([0.1], 0, 1, 0, 3), errors.InvalidParameterError, "out of range"),
    (lambda: theta([0.1], 0, 1.0, 0, 1), errors.InvalidParameterError, "out of range"),
    (lambda: expi_divided_difference([0.0, 1.0], [1, 0]), errors.InvalidParameterError, "multiplicities"),
    (lambda: expi_divided_difference([0.0, np.inf], [1, 1]), errors.NonFiniteError, "finite"),
    (lambda: expi_moment([0.0, 1.0], [1, -1]), errors.InvalidParameterError, "powers"),
    (lambda: local_mass_matrices(1.0, [0.0], dim=3), errors.ShapeError, "triangles"),
    (lambda: local_edges(0), errors.InvalidParameterError, "dimension"),
])
def test_typed_errors(call, exc, text):
    with pytest.raises(exc, match=None) as info:
        call()
    assert text in str(info.value)


def test_no_warnings_on_extreme_but_valid_input(recwarn):
    om = np.array([[1e-300], [1e6], [0.0]])
    out = local_dirichlet_matrices(np.stack([G2] * 3), np.ones(3), om)
    assert np.all(np.isfinite(out))
    assert len(recwarn) == 0
