"""Line bundles: connection forms and Hom(ker ∂₁, F*) (Theorems 3–6)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb import SimplicialComplex
from dhlb.bundles import (
    LineBundleClass,
    VectorBundle,
    connection_form,
    find_isomorphism,
    form_class,
    integrate_exact_form,
    line_bundle_class,
    tensor,
)
from dhlb.bundles.paths import fundamental_cycles
from dhlb.errors import InvalidConnectionError, NotClosedError, NotExactError
from tests.strategies import rich_complexes, rp2


def random_units(rng, n, field):
    if field == "C":
        return np.exp(rng.standard_normal(n) + 1j * rng.uniform(-np.pi, np.pi, n))
    if field == "R":
        return rng.choice([-1, 1], n) * np.exp(rng.standard_normal(n))
    return rng.integers(1, field[1], n)


def random_line(X, rng, field):
    return VectorBundle(X, random_units(rng, X.n_simplices(1), field), field)


FIELDS = st.sampled_from(["R", "C", ("GF", 7)])


@settings(max_examples=20, deadline=None)
@given(rich_complexes(3), st.integers(0, 2**32 - 1), FIELDS)
def test_class_is_a_group_homomorphism(X, seed, field):
    """Theorem 4: [L ⊗ L'] = [L][L'], [L*] = [L]⁻¹."""
    rng = np.random.default_rng(seed)
    A, B = random_line(X, rng, field), random_line(X, rng, field)
    cA, cB = line_bundle_class(A), line_bundle_class(B)
    assert line_bundle_class(tensor(A, B)) == cA * cB
    assert line_bundle_class(A.dual()) == cA.inverse()
    assert (cA * cA.inverse()).is_trivial()


@settings(max_examples=20, deadline=None)
@given(rich_complexes(3), st.integers(0, 2**32 - 1), FIELDS)
def test_class_values_are_the_form_on_fundamental_cycles(X, seed, field):
    """Theorem 5/6: the class is the connection form restricted to ker ∂₁ (basis: fundamental cycles)."""
    rng = np.random.default_rng(seed)
    L = random_line(X, rng, field)
    c = line_bundle_class(L)
    w = connection_form(L)
    Z = fundamental_cycles(X, L.forest).toarray()
    for i, z in enumerate(Z[:5]):
        if L.ops.exact:
            p = field[1]
            val = 1
            for e in np.nonzero(z)[0]:
                val = val * pow(int(w[e]), int(z[e]) % (p - 1), p) % p
            assert val == c.values[i] == c.evaluate(z)
        else:
            assert np.isclose(np.prod(w.astype(complex) ** z), c.values[i])
            assert np.isclose(c.evaluate(z), c.values[i])


@settings(max_examples=20, deadline=None)
@given(rich_complexes(3), st.integers(0, 2**32 - 1), FIELDS)
def test_isomorphic_iff_same_class(X, seed, field):
    """Theorem 3: two line bundles are isomorphic iff their classes in Hom(ker ∂₁, F*) agree."""
    rng = np.random.default_rng(seed)
    L = random_line(X, rng, field)
    M = L.gauge(random_units(rng, X.n_vertices, field))
    assert line_bundle_class(M) == line_bundle_class(L)
    assert find_isomorphism(L, M) is not None
    # the normalized representative is in the same class
    assert find_isomorphism(L, line_bundle_class(L).bundle()) is not None
    if L.forest.nontree.size:
        w = np.array(connection_form(L))
        e = L.forest.nontree[-1]
        w[e] = (w[e] * 2) % field[1] if L.ops.exact else w[e] * 2
        N = VectorBundle(X, w, field)
        assert line_bundle_class(N) != line_bundle_class(L)
        assert find_isomorphism(L, N) is None


def test_exact_forms_integrate():
    X = SimplicialComplex(rp2())
    rng = np.random.default_rng(1)
    g = np.exp(1j * rng.uniform(-np.pi, np.pi, X.n_vertices)) * 2.0 ** rng.integers(-2, 3, X.n_vertices)
    E = X.simplices(1)
    w = g[E[:, 1]] / g[E[:, 0]]
    h = integrate_exact_form(X, w)
    assert np.allclose(h, g / g[0])
    assert form_class(X, w).is_trivial()
    w[3] *= -1
    with pytest.raises(NotExactError, match="fundamental cycle of edge"):
        integrate_exact_form(X, w)


def test_evaluate_rejects_non_cycles_and_class_checks():
    X = SimplicialComplex([(0, 1), (1, 2), (0, 2)])
    c = line_bundle_class(VectorBundle(X, [2.0, 1.0, 1.0]))
    assert c.evaluate([1, -1, 1]) == pytest.approx(2.0)
    with pytest.raises(NotClosedError, match="not a cycle"):
        c.evaluate([1, 0, 0])
    with pytest.raises(InvalidConnectionError, match="nonzero"):
        LineBundleClass(X, [0.0], "R")
    with pytest.raises(InvalidConnectionError, match="rank 1"):
        line_bundle_class(VectorBundle.trivial(X, 2))
