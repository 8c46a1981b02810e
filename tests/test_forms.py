"""Discrete forms: coefficient groups, d, Stokes, pairing with chains, conversions, bad input.

Solving dα = β and integrating 1-forms are tested in ``test_forms_solve.py``."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb import SimplicialComplex
from dhlb.errors import InvalidCochainError, NonFiniteError, SimplexNotFoundError
from dhlb.forms import Chain, Cochain, wrap_angle
from dhlb.forms.groups import get_group
from tests.strategies import complexes, cycle

GROUPS = ["Z", "R", "C", "S1", "C*"]
seeds = st.integers(0, 2**32 - 1)
some_complexes = complexes(max_vertices=6, max_dim=5, max_size=8)


def random_values(rng, group, n):
    if group == "Z":
        return rng.integers(-5, 6, n)
    if group == "R":
        return rng.normal(size=n)
    if group == "C":
        return rng.normal(size=n) + 1j * rng.normal(size=n)
    if group == "S1":
        v = rng.uniform(-np.pi, np.pi, n)
        v[rng.random(n) < 0.2] = np.pi * rng.choice([-1, 1])  # exercise the ±π boundary
        return v
    return np.exp(0.5 * rng.normal(size=n) + 1j * rng.uniform(-np.pi, np.pi, n))


def random_form(rng, X, k, group):
    return Cochain(X, k, random_values(rng, group, X.n_simplices(k)), group)


def assert_same(a, b, tol=1e-9):
    """a and b agree in their group (S¹ modulo 2π)."""
    assert a.group == b.group and a.k == b.k
    g = get_group(a.group)
    assert np.all(g.distance(g.op(a.values, g.inv(b.values))) <= tol), (a.values, b.values)


def group_distance(group, x, y):
    g = get_group(group)
    return float(np.max(g.distance(g.op(np.asarray(x), g.inv(np.asarray(y)))), initial=0.0))


# ----------------------------------------------------------------------------- d, Stokes, pairing
@settings(max_examples=30, deadline=None)
@given(some_complexes, seeds)
def test_dd_is_identity_in_every_group(X, seed):
    rng = np.random.default_rng(seed)
    for group in GROUPS:
        for k in range(X.dim + 1):
            w = random_form(rng, X, k, group)
            assert_same(w.d().d(), Cochain.identity(X, k + 2, group))


@settings(max_examples=30, deadline=None)
@given(some_complexes, seeds)
def test_d_is_the_coboundary_written_in_the_group(X, seed):
    rng = np.random.default_rng(seed)
    for k in range(X.dim):
        D = X.coboundary(k)
        w = random_form(rng, X, k, "R")
        assert np.allclose(w.d().values, D @ w.values)
        z = random_form(rng, X, k, "Z")
        assert z.d().values.dtype == np.int64 and np.array_equal(z.d().values, D @ z.values)
        s = random_form(rng, X, k, "S1")
        assert_same(s.d(), Cochain(X, k + 1, D @ s.values, "S1"))
        m = random_form(rng, X, k, "C*")
        assert_same(m.d(), Cochain(X, k + 1, np.exp(D @ np.log(m.values)), "C*"))
        # d is a homomorphism
        for group in GROUPS:
            a, b = random_form(rng, X, k, group), random_form(rng, X, k, group)
            assert_same(a.op(b).d(), a.d().op(b.d()))


@settings(max_examples=30, deadline=None)
@given(some_complexes, seeds)
def test_stokes(X, seed):
    """⟨dω, c⟩ = ⟨ω, ∂c⟩ for random integer chains, in every group."""
    rng = np.random.default_rng(seed)
    for k in range(X.dim):
        c = Chain(X, k + 1, rng.integers(-3, 4, X.n_simplices(k + 1)))
        for group in GROUPS:
            w = random_form(rng, X, k, group)
            assert group_distance(group, w.d().pair(c), w.pair(c.boundary())) <= 1e-9
            assert group_distance(group, w.d()(c), w(c.boundary())) <= 1e-9
        assert c.boundary().is_cycle()
        if k >= 1:
            assert not np.any(c.boundary().boundary().coefficients)


def test_pairing_values_and_batches():
    X = SimplicialComplex([(0, 1, 2)])
    w = Cochain(X, 1, [1.0, 2.0, 4.0])
    assert w.pair(Chain.path(X, [0, 1, 2, 0])) == 1.0 + 4.0 - 2.0
    assert w.pair([1, 0, 1]) == 5.0 and w.pair(np.array([0.5, 0.0, 0.0])) == 0.5  # real chains for R
    assert w.pair(np.array([[1, 0, 0], [0, 1, 1]])).tolist() == [1.0, 6.0]
    s = Cochain(X, 1, [3.0, -3.0, 3.0], "S1")
    assert s.pair([1, 1, 0]) == pytest.approx(0.0) and s.pair([2, 0, 0]) == pytest.approx(6.0 - 2 * np.pi)
    m = Cochain(X, 1, [2.0, 1j, -1.0], "C*")
    assert m.pair([1, -1, 2]) == pytest.approx(2.0 / 1j)
    z = Cochain(X, 1, [1, 2, 3], "Z")
    assert z.pair(np.array([1.0, 1.0, 1.0])) == 6 and isinstance(z.pair([1, 1, 1]), int)



def test_circle_storage_wraps_to_half_open_interval():
    X = SimplicialComplex(cycle(5))
    vals = [np.pi, -np.pi, np.pi + 1e-12, -np.pi - 1e-12, 7 * np.pi]
    w = Cochain(X, 1, vals, "S1")
    assert np.all(w.values > -np.pi) and np.all(w.values <= np.pi)
    assert w.values[0] == np.pi and w.values[1] == np.pi and w.values[4] == pytest.approx(np.pi)
    assert w.values[2] == pytest.approx(-np.pi + 1e-12, abs=1e-15)
    assert (w + w).values[0] == pytest.approx(0.0) and (w - w).is_closed()
    three = Cochain(X, 1, [3.0] * 5, "S1")
    assert (three + three).values[0] == pytest.approx(6.0 - 2 * np.pi)
    assert (2 * three).allclose(three + three) and (-three).values[0] == -3.0
    assert wrap_angle(np.array([-np.pi, np.pi]).tolist()).tolist() == [np.pi, np.pi]



# ----------------------------------------------------------------------------- group operations, conversions
def test_group_operations_and_conversions():
    X = SimplicialComplex([(0, 1, 2)])
    a, b = Cochain(X, 1, [1, 2, 3], "Z"), Cochain(X, 1, [1, 1, 1], "Z")
    assert (a + b).values.tolist() == [2, 3, 4] and (a - b).values.tolist() == [0, 1, 2]
    assert (-a).values.tolist() == [-1, -2, -3] and (3 * a).values.tolist() == [3, 6, 9]
    r = a.to_group("R")
    assert r.group == "R" and (0.5 * r).values.tolist() == [0.5, 1.0, 1.5]
    assert (r.to_group("C") * 1j).values.tolist() == [1j, 2j, 3j]
    m, n = Cochain(X, 1, [2, 1j, -1], "C*"), Cochain(X, 1, [2, 2, 2], "C*")
    assert (m * n).values.tolist() == [4, 2j, -2] and (m / n).values.tolist() == [1, 0.5j, -0.5]
    assert (m**2).values.tolist() == [4, -1, 1] and m.inverse().values.tolist() == [0.5, -1j, -1]
    s = Cochain(X, 1, [3 * np.pi / 2, 0.5, -0.5])
    assert s.to_group("S1").values.tolist() == pytest.approx([-np.pi / 2, 0.5, -0.5])
    assert s.to_group("S1").to_group("C*").values == pytest.approx(np.exp(1j * s.values))
    assert s.to_group("S1").to_group("C*").to_group("S1") .allclose(s.to_group("S1"))
    assert m.to_group("S1").values.tolist() == pytest.approx([0, np.pi / 2, np.pi])
    assert s.to_group("S1").lift().group == "R" and s.to_group("R") == s
    assert Cochain.from_simplices(X, [(1, 0)], [0.5]).values.tolist() == [-0.5, 0.0, 0.0]
    assert Cochain.from_simplices(X, [(2, 1)], [2j], "C*").values.tolist() == [1, 1, -0.5j]
    assert Cochain.from_simplices(X, [(2, 1)], [1.0], "S1").values.tolist() == [0, 0, -1.0]
    bad_ops = [
        lambda: m + n, lambda: a * a, lambda: a / b, lambda: a ** 2, lambda: a + r,
        lambda: a + Cochain(X, 0, [1, 2, 3], "Z"), lambda: 1.5 * a, lambda: r * 1j,
        lambda: a + Cochain(SimplicialComplex([(0, 1, 3)]), 1, [1, 2, 3], "Z"), lambda: m ** 0.5,
        lambda: a + 1, lambda: 2 * m, lambda: a.to_group("C*"), lambda: r.to_group("Z"),
        lambda: a.lift(), lambda: a.allclose(r),
    ]
    for op in bad_ops:
        with pytest.raises(InvalidCochainError):
            op()


# ----------------------------------------------------------------------------- bad input
def test_bad_values_name_the_simplex():
    X = SimplicialComplex([(3, 5, 8)])
    with pytest.raises(InvalidCochainError, match=r"shape \(3,\)"):
        Cochain(X, 1, [1.0, 2.0])
    with pytest.raises(InvalidCochainError, match=r"shape \(3,\)"):
        Cochain(X, 1, 1.0)
    with pytest.raises(NonFiniteError, match=r"edge \(3, 8\)"):
        Cochain(X, 1, [1.0, np.nan, 0.0])
    with pytest.raises(NonFiniteError, match=r"triangle \(3, 5, 8\)"):
        Cochain(X, 2, [np.inf], "C")
    with pytest.raises(InvalidCochainError, match=r"edge \(5, 8\).*integer"):
        Cochain(X, 1, [1, 2, 2.5], "Z")
    with pytest.raises(InvalidCochainError, match=r"vertex 5.*nonzero"):
        Cochain(X, 0, [1, 0, 1j], "C*")
    with pytest.raises(InvalidCochainError, match=r"edge \(3, 5\).*complex"):
        Cochain(X, 1, [1j, 0, 0], "R")
    with pytest.raises(InvalidCochainError, match="angles"):
        Cochain(X, 1, [1j, 0, 0], "S1")
    with pytest.raises(InvalidCochainError, match="unknown coefficient group"):
        Cochain(X, 1, [1, 2, 3], "Q")
    with pytest.raises(InvalidCochainError, match="non-negative integer"):
        Cochain(X, -1, [])
    with pytest.raises(InvalidCochainError, match="numbers"):
        Cochain(X, 1, ["a", "b", "c"])
    with pytest.raises(InvalidCochainError, match="listed twice"):
        Cochain.from_simplices(X, [(3, 5), (5, 3)], [1.0, 2.0])
    with pytest.raises(SimplexNotFoundError):
        Cochain.from_simplices(X, [(3, 4)], [1.0])
    with pytest.raises(InvalidCochainError, match="equal length"):
        Cochain.from_simplices(X, [(3, 5), (3, 5, 8)], [1.0, 2.0])
    with pytest.raises(InvalidCochainError, match="equal length"):
        Chain.from_simplices(X, [(3.5, 5)])
    with pytest.raises(InvalidCochainError, match="SimplicialComplex"):
        Cochain([(0, 1)], 1, [1.0])
    with pytest.raises(InvalidCochainError, match="SimplicialComplex"):
        Chain(None, 0, [1])
    with pytest.raises(InvalidCochainError, match="non-negative integer"):
        Cochain(X, 1.0, [1.0, 2.0, 3.0])
    w = Cochain(X, 1, [1.0, 2.0, 3.0])
    assert Cochain(X, 1, np.array([True, False, True]), "Z").values.tolist() == [1, 0, 1]
    assert Cochain(X, 1, [1.0 + 0j, 2, 3], "Z").values.dtype == np.int64
    with pytest.raises(ValueError):
        w.values[0] = 5.0  # read-only
    assert Cochain(X, 3, []).d().values.size == 0 and Cochain(X, 2, [1.0]).d().k == 3
