"""Discrete forms: exactness (Lemmas 1–3), solving dα = β in every group, integrating closed 1-forms."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import dhlb.forms.solve as solve_mod
from dhlb import SimplicialComplex
from dhlb.errors import InvalidCochainError, NotAPathError, NotClosedError, NotExactError
from dhlb.forms import Chain, Cochain, integrate_closed_1form, is_exact, solve_d, wrap_angle
from dhlb.forms.groups import get_group
from dhlb.topology.intlinalg import integer_kernel_basis
from tests.strategies import closed_surfaces, complexes, cycle, rp2, sphere, suspension, torus_grid
from tests.test_forms import GROUPS, assert_same, group_distance, random_form, seeds

some_complexes = complexes(max_vertices=6, max_dim=5, max_size=8)


# ----------------------------------------------------------------------------- exactness and closedness
@settings(max_examples=30, deadline=None)
@given(some_complexes, seeds)
def test_exact_forms_are_closed_and_exact(X, seed):
    rng = np.random.default_rng(seed)
    for k in range(X.dim):
        for group in GROUPS:
            beta = random_form(rng, X, k, group).d()
            assert beta.is_closed()
            assert is_exact(beta)
            res = solve_d(beta)
            assert res.exact and res.residual <= 1e-8
            assert res.solution.group == group and res.solution.k == k
            assert_same(res.solution.d(), beta, tol=1e-8)


@settings(max_examples=30, deadline=None)
@given(some_complexes, seeds)
def test_lemma2_exact_iff_zero_periods_over_R(X, seed):
    """Over R, β is exact iff ⟨β, c⟩ = 0 for an integer basis of ker ∂_k (seed, Lemma 2)."""
    rng = np.random.default_rng(seed)
    for k in range(1, X.dim + 1):
        C = integer_kernel_basis(X.boundary(k))
        C = C.toarray() if hasattr(C, "toarray") else np.asarray(C)
        beta = random_form(rng, X, k, "R")
        r = solve_d(beta)
        periods_vanish = bool(np.all(np.abs(C.T @ beta.values) <= 1e-8))
        assert r.exact == periods_vanish == is_exact(beta)
        # the least-squares residual β − dα is a real cycle, orthogonal to im d
        resid = beta.values - r.solution.d().values
        assert np.allclose(X.boundary(k) @ resid, 0.0, atol=1e-8)
        exact_part = Cochain(X, k, r.solution.d().values)
        assert is_exact(exact_part) and np.allclose(C.T @ exact_part.values, 0.0, atol=1e-8)


def test_least_squares_residuals_analytic():
    S2 = SimplicialComplex(sphere(2))  # ∂Δ³: the only cycle is ±(the 4 triangles), |c|² = 4
    r = solve_d(Cochain(S2, 2, [1.0, 0.0, 0.0, 0.0]))
    assert not r.exact and r.residual == pytest.approx(0.25)
    C3 = SimplicialComplex(cycle(3))  # edges 01, 02, 12; cycle c = (1, -1, 1)
    r = solve_d(Cochain(C3, 1, [1.0, 1.0, 1.0]))
    assert not r.exact and r.residual == pytest.approx(1 / 3)
    r = solve_d(Cochain(C3, 1, [1j, 1j, 1j], "C"))
    assert not r.exact and r.residual == pytest.approx(1 / 3)


@pytest.mark.parametrize("k", [1, 2])
def test_sparse_least_squares_paths_agree_with_dense(monkeypatch, k):
    X = SimplicialComplex(torus_grid(3, 4))
    rng = np.random.default_rng(k)
    beta = random_form(rng, X, k, "C")
    dense = solve_d(beta)
    monkeypatch.setattr(solve_mod, "_DENSE_LIMIT", 0)
    sparse = solve_d(beta)
    assert not dense.exact and sparse.residual == pytest.approx(dense.residual, rel=1e-8)
    assert np.allclose(sparse.solution.d().values, dense.solution.d().values, atol=1e-8)


def test_solve_over_Z():
    S2 = SimplicialComplex(sphere(2))
    alpha = Cochain(S2, 1, [3, -1, 4, 1, -5, 9], "Z")
    r = solve_d(alpha.d())
    assert r.exact and r.solution.group == "Z" and r.solution.d() == alpha.d()
    with pytest.raises(NotExactError, match="not even exact over R"):
        solve_d(Cochain(S2, 2, [1, 0, 0, 0], "Z"))
    with pytest.raises(NotExactError) as info:  # k = 1: the message names a cycle
        solve_d(Cochain(SimplicialComplex(cycle(4)), 1, [1, 0, 0, 0], "Z"))
    assert info.value.defect != 0 and info.value.cycle[0] == info.value.cycle[-1]
    # RP²: H²(RP²; Z) = Z/2 — one triangle is exact over R and S¹ but not over Z; twice it is
    P = SimplicialComplex(rp2())
    e = np.zeros(P.n_simplices(2), np.int64)
    e[0] = 1
    assert solve_d(Cochain(P, 2, e)).exact
    with pytest.raises(NotExactError, match="torsion"):
        solve_d(Cochain(P, 2, e, "Z"))
    assert not is_exact(Cochain(P, 2, e, "Z"))
    assert solve_d(Cochain(P, 2, 2 * e, "Z")).exact
    # the group argument converts
    assert solve_d(Cochain(P, 2, e, "Z"), group="R").exact


# ----------------------------------------------------------------------------- S¹ and C*
def test_circle_one_forms_with_winding():
    X = SimplicialComplex(cycle(3))  # edges 01, 02, 12; the loop 0→1→2→0 is (1, -1, 1)
    step = 2 * np.pi / 3
    w = Cochain(X, 1, [step, -step, step], "S1")  # winds once: period 2π ≡ 0
    assert not is_exact(Cochain(X, 1, w.values))  # over R it is not exact
    f = integrate_closed_1form(w)
    assert f.d().allclose(w) and is_exact(w)
    near = Cochain(X, 1, [3.1, 6.2 - 2 * np.pi, 3.1], "S1")  # path sums pass ±π
    f = integrate_closed_1form(near)
    assert f.values[0] == 0.0 and f.values[2] == pytest.approx(wrap_angle(6.2))
    bad = Cochain(X, 1, [step, -step, step + 0.1], "S1")
    with pytest.raises(NotExactError) as info:
        solve_d(bad)
    assert abs(info.value.defect) == pytest.approx(0.1)
    # H¹(RP²; S¹) = Z/2 (Bockstein): with dξ = e (ξ real, e one triangle, [e] ≠ 0 in H²(RP²; Z)),
    # 2πξ is a closed S¹ 1-form that is not exact (period π on the essential loop); 2·e is fine
    P = SimplicialComplex(rp2())
    e = np.zeros(P.n_simplices(2))
    e[0] = 1
    for mult in (1, 2):
        w = Cochain(P, 1, 2 * np.pi * solve_d(Cochain(P, 2, mult * e)).solution.values, "S1")
        assert w.is_closed() and is_exact(w) == (mult == 2)
        if mult == 1:
            with pytest.raises(NotExactError) as info:
                solve_d(w)
            assert abs(info.value.defect) == pytest.approx(np.pi)


@settings(max_examples=20, deadline=None)
@given(closed_surfaces(max_moves=4), seeds, st.integers(-3, 3))
def test_top_forms_on_closed_surfaces(surface, seed, winding):
    """Over S¹ a 2-form on a closed surface is exact iff its total flux is in 2πZ (orientable),
    always (non-orientable: H²(X; S¹) = Hom(H_2, S¹) = 0)."""
    tris, _, orientable = surface
    X = SimplicialComplex(tris)
    rng = np.random.default_rng(seed)
    vals = rng.uniform(-1, 1, X.n_simplices(2))
    C = integer_kernel_basis(X.boundary(2))
    C = C.toarray() if hasattr(C, "toarray") else np.asarray(C)
    assert C.shape[1] == (1 if orientable else 0)
    if orientable:
        c = C[:, 0]
        vals += (2 * np.pi * winding - c @ vals) / c.size * c  # total flux 2π·winding
    beta = Cochain(X, 2, vals, "S1")
    r = solve_d(beta)
    assert r.exact and r.solution.d().allclose(beta, tol=1e-8)
    off = vals.copy()
    off[0] += 0.25
    beta = Cochain(X, 2, off, "S1")
    if orientable:
        assert not is_exact(beta) and not is_exact(Cochain(X, 2, off))
        with pytest.raises(NotExactError) as info:
            solve_d(beta)
        assert abs(info.value.defect) == pytest.approx(0.25, abs=1e-8)
        assert abs(beta.pair(info.value.cycle)) == pytest.approx(0.25, abs=1e-8)
    else:
        assert is_exact(beta) and solve_d(beta).solution.d().allclose(beta, tol=1e-8)


def test_circle_two_forms_on_a_three_complex_with_torsion():
    """ΣRP²: H³(ΣRP²; Z) = Z/2.  With dξ = m (ξ real), 2πξ is a closed S¹ 2-form; it is exact iff
    m is d of an integer form, which fails for one tetrahedron and holds for twice it."""
    Y = SimplicialComplex(suspension(rp2()))
    m = np.zeros(Y.n_simplices(3))
    m[0] = 1
    for mult, exact in ((1, False), (2, True)):
        xi = solve_d(Cochain(Y, 3, mult * m)).solution
        beta = Cochain(Y, 2, 2 * np.pi * xi.values, "S1")
        assert beta.is_closed()
        assert is_exact(beta) == exact
        if exact:
            assert solve_d(beta).solution.d().allclose(beta, tol=1e-8)
        else:
            with pytest.raises(NotExactError, match="torsion"):
                solve_d(beta)
    noisy = Cochain(Y, 2, np.r_[0.3, np.zeros(Y.n_simplices(2) - 1)], "S1")
    with pytest.raises(NotExactError, match="not closed"):
        solve_d(noisy)


def test_circle_lift_adjustments_on_a_3_sphere():
    X = SimplicialComplex(sphere(3))
    rng = np.random.default_rng(7)
    for k in (1, 2, 3):
        a = rng.uniform(-3 * np.pi, 3 * np.pi, X.n_simplices(k - 1))
        n = rng.integers(-4, 5, X.n_simplices(k))
        beta = Cochain(X, k, X.coboundary(k - 1) @ a + 2 * np.pi * n, "S1")  # exact; lifts far off
        r = solve_d(beta)
        assert r.exact and r.solution.d().allclose(beta, tol=1e-8)


def test_solve_periods_fallback_without_private_simplices():
    import scipy.sparse as sp

    C = sp.csc_matrix(np.array([[1, 1], [1, -1], [1, 0]]))
    n = solve_mod._solve_periods(C, np.array([3, -2]))
    assert (C.T @ n).tolist() == [3, -2]


def test_cstar_solve_and_obstructions():
    S2 = SimplicialComplex(sphere(2))
    rng = np.random.default_rng(3)
    alpha = random_form(rng, S2, 1, "C*")
    r = solve_d(alpha.d())
    assert r.exact and r.solution.d().allclose(alpha.d())
    with pytest.raises(NotExactError, match="log"):
        solve_d(Cochain(S2, 2, [2.0, 1.0, 1.0, 1.0], "C*"))
    with pytest.raises(NotExactError):
        solve_d(Cochain(S2, 2, [np.exp(0.5j), 1.0, 1.0, 1.0], "C*"))
    c = integer_kernel_basis(S2.boundary(2)).toarray()[:, 0]
    theta = rng.uniform(-1, 1, 4)
    theta += (2 * np.pi - c @ theta) / 4 * c  # total flux 2π: exact over C* (not over C)
    flux = Cochain(S2, 2, 2.0 * np.exp(1j * theta), "C*")
    assert is_exact(flux) and not is_exact(Cochain(S2, 2, theta))
    assert solve_d(flux).solution.d().allclose(flux)



# ----------------------------------------------------------------------------- integration of 1-forms
@settings(max_examples=30, deadline=None)
@given(some_complexes, seeds)
def test_integrate_recovers_potential_up_to_constants(X, seed):
    rng = np.random.default_rng(seed)
    root = int(rng.integers(X.n_vertices))
    for group in GROUPS:
        f = random_form(rng, X, 0, group)
        g = integrate_closed_1form(f.d(), root=root)
        assert g.values[root] == get_group(group).identity
        diff = g.op(f.inverse())
        assert diff.d().allclose(Cochain.identity(X, 1, group), tol=1e-9)  # constant per component


@settings(max_examples=30, deadline=None)
@given(some_complexes, seeds)
def test_integrate_names_a_failing_cycle(X, seed):
    rng = np.random.default_rng(seed)
    for group in GROUPS:
        w = random_form(rng, X, 1, group)
        try:
            f = integrate_closed_1form(w)
        except NotClosedError as err:
            assert err.cycle[0] == err.cycle[-1] and len(err.cycle) >= 4
            assert group_distance(group, w.pair(Chain.path(X, err.cycle)), err.defect) <= 1e-9
            assert get_group(group).distance(np.asarray(err.defect)) > 1e-9
            assert not is_exact(w)
        else:
            assert f.d().allclose(w) and is_exact(w)


def test_integrate_forest_and_large_mesh():
    X = SimplicialComplex(cycle(5) + [(10, 11), (11, 12)])
    w = Cochain(X, 1, [1.0, 0, 0, 0, 0, 2.0, 3.0])  # 1 on the edge (0, 1) of the pentagon
    with pytest.raises(NotClosedError, match="cycle") as info:
        integrate_closed_1form(w)
    assert sorted(info.value.cycle[:-1]) == [0, 1, 2, 3, 4] and abs(info.value.defect) == 1.0
    f = integrate_closed_1form(Cochain(X, 1, [0, 0, 0, 0, 0, 2.0, 3.0]), root=3)
    assert f.values.tolist() == [0, 0, 0, 0, 0, 0, 2.0, 5.0]
    T = SimplicialComplex(torus_grid(60, 60))
    f = Cochain(T, 0, np.random.default_rng(0).normal(size=T.n_vertices))
    g = integrate_closed_1form(f.d(), root=17)
    assert np.allclose(g.values, f.values - f.values[17], atol=1e-10)



def test_bad_arguments_of_chains_and_solvers():
    X = SimplicialComplex([(3, 5, 8), (8, 9)])
    w = Cochain(X, 1, np.zeros(4), "S1")
    with pytest.raises(NotAPathError, match="3 → 9"):
        Chain.path(X, [5, 3, 9])
    with pytest.raises(NotAPathError, match="stays at vertex 3"):
        Chain.path(X, [3, 3, 5])
    with pytest.raises(NotAPathError):
        Chain.path(X, [3])
    with pytest.raises(InvalidCochainError, match="integer chain coefficients"):
        w.pair(np.array([0.5, 0, 0, 0]))
    with pytest.raises(InvalidCochainError, match=r"shape \(4,\)"):
        w.pair([1, 2])
    with pytest.raises(InvalidCochainError, match=r"shape \(4,\)"):
        w.pair([[1, 2, 3, 4], [1]])
    with pytest.raises(InvalidCochainError):
        w.pair(Chain(X, 2, [1]))
    with pytest.raises(InvalidCochainError):
        Chain(X, 1, [1, 0, 0, 0]) + Chain(X, 2, [1])
    with pytest.raises(InvalidCochainError):
        0.5 * Chain(X, 1, [1, 0, 0, 0])
    with pytest.raises(InvalidCochainError):
        Chain(X, 0, [1, 0, 0, 0]).boundary()
    with pytest.raises(InvalidCochainError):
        Chain.from_simplices(X, [(3, 5)], [0.5])
    assert (2 * Chain(X, 1, [1, 0, 0, 0]) - Chain(X, 1, [1, 0, 0, 0])).coefficients.tolist() == [1, 0, 0, 0]
    with pytest.raises(InvalidCochainError, match="1-form"):
        integrate_closed_1form(Cochain(X, 0, np.zeros(4)))
    with pytest.raises(InvalidCochainError, match="root"):
        integrate_closed_1form(w, root=4)
    with pytest.raises(InvalidCochainError, match="0-form"):
        solve_d(Cochain(X, 0, np.zeros(4)))
    with pytest.raises(InvalidCochainError):
        solve_d(np.zeros(4))
    assert is_exact(Cochain(X, 0, np.zeros(4))) and not is_exact(Cochain(X, 0, [0, 1, 0, 0], "Z"))
    assert solve_d(Cochain(X, 3, [])).exact


def test_cochain_is_exact_method_is_deprecated_and_still_answers():
    X = SimplicialComplex([(0, 1), (1, 2), (0, 2)])  # a circle: the loop form is closed, not exact
    loop, grad = Cochain(X, 1, [1.0, -1.0, 1.0]), Cochain(X, 0, [0.0, 1.0, 3.0]).d()
    with pytest.warns(DeprecationWarning, match=r"dhlb\.forms\.is_exact"):
        assert loop.is_exact() is False
    with pytest.warns(DeprecationWarning, match=r"dhlb\.forms\.is_exact"):
        assert grad.is_exact() is True
    assert is_exact(loop) is False and is_exact(grad) is True
