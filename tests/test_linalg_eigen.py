"""Tests of dhlb.linalg.eigen and dhlb.linalg.linear: generalized Hermitian eigenpairs and shifted solves."""

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb import SimplicialComplex
from dhlb.errors import ConvergenceError, InvalidOperatorError, InvalidParameterError, NonFiniteError, ShapeError
from dhlb.geometry import EuclideanComplex
from dhlb.linalg import EigenResult, SolverOptions, backward_errors, default_shift, smallest_eigenpairs, solve


# ---------------------------------------------------------------------- fixtures
@pytest.fixture(autouse=True)
def _sparse_path(monkeypatch):
    """These tests exercise the sparse (ARPACK) path: no dense shortcut for small problems."""
    import dhlb.linalg.eigen as E

    monkeypatch.setattr(E, "DENSE_MAX", 0)


def pencil(n, spectrum, complex_, seed):
    """Dense Hermitian pencil (A, M) with M PD and generalized spectrum exactly ``spectrum``."""
    rng = np.random.default_rng(seed)
    Z = rng.normal(size=(n, n)) + (1j * rng.normal(size=(n, n)) if complex_ else 0)
    Q, _ = np.linalg.qr(Z)
    C = rng.normal(size=(n, n)) + (1j * rng.normal(size=(n, n)) if complex_ else 0)
    M = C @ C.conj().T / n + np.eye(n)
    M = 0.5 * (M + M.conj().T)
    L = np.linalg.cholesky(M)                              # M = L Lᴴ
    A = L @ (Q * np.asarray(spectrum)) @ Q.conj().T @ L.conj().T
    return 0.5 * (A + A.conj().T), M


def path_laplacian(n):
    main = np.r_[1.0, 2 * np.ones(n - 2), 1.0]
    return sp.diags([-np.ones(n - 1), main, -np.ones(n - 1)], [-1, 0, 1], format="csr")


def twisted_cycle(n, theta):
    """Connection Laplacian of the n-cycle with r_{i,i+1} = exp(iθ/n): holonomy exp(iθ)."""
    r = np.exp(1j * theta / n)
    i = np.arange(n)
    j = (i + 1) % n
    rows = np.r_[i, j, i, j]
    cols = np.r_[i, j, j, i]
    # edge energy |z_j - r z_i|²: A[j, i] = -r, A[i, j] = -conj(r)
    vals = np.r_[np.ones(n), np.ones(n), -np.conj(r) * np.ones(n), -r * np.ones(n)]
    return sp.csr_matrix((vals, (rows, cols)), shape=(n, n))


def check_eigenpairs(res, A, M, k, tol):
    A, M = np.asarray(sp.csr_matrix(A).toarray()), np.asarray(sp.csr_matrix(M).toarray())
    U, lam = res.eigenvectors, res.eigenvalues
    assert isinstance(res, EigenResult) and res.converged and res.backend == "cholmod"
    assert res.method == "lanczos" and res.factorizations == 1 and res.solves == res.iterations > 0
    assert U.shape == (A.shape[0], k) and lam.shape == (k,)
    assert np.all(np.diff(lam) >= 0)
    np.testing.assert_allclose(U.conj().T @ M @ U, np.eye(k), atol=1e-10)
    R = A @ U - M @ U * lam
    eta = np.linalg.norm(R, axis=0) / ((np.abs(A).sum(0).max() + np.abs(lam) * np.abs(M).sum(0).max())
                                       * np.linalg.norm(U, axis=0))
    # both are rounding noise below ~eps; above it they must agree
    np.testing.assert_allclose(res.residuals, eta, rtol=1e-6, atol=4 * np.finfo(float).eps)
    assert np.all(res.residuals <= tol)


# ---------------------------------------------------------------------- accuracy
@pytest.mark.parametrize("complex_", [False, True])
def test_against_dense_eigh_with_degenerate_eigenvalues(complex_):
    n = 60
    spectrum = np.r_[0.0, 0.0, 0.5, 0.5, 0.5, 2.0, np.linspace(3, 50, n - 6)]
    A, M = pencil(n, spectrum, complex_, seed=1)
    k = 5                                            # ends exactly after a complete cluster
    res = smallest_eigenpairs(sp.csr_matrix(A), sp.csr_matrix(M), k=k)
    check_eigenpairs(res, A, M, k, 1e-10)
    np.testing.assert_allclose(res.eigenvalues, spectrum[:k], atol=1e-12)
    _, V = sla.eigh(A, M)
    for cluster in (slice(0, 2), slice(2, 5)):       # compare eigenspaces via M-projectors
        P_ref = V[:, cluster] @ V[:, cluster].conj().T @ M
        U = res.eigenvectors[:, cluster]
        np.testing.assert_allclose(P_ref @ U, U, atol=1e-8)
    assert np.iscomplexobj(res.eigenvectors) == complex_


@settings(max_examples=40, deadline=None)
@given(st.integers(12, 120), st.integers(1, 6), st.booleans(), st.integers(0, 10**6),
       st.lists(st.integers(1, 3), min_size=1, max_size=4))
def test_random_pencils_match_eigh(n, k, complex_, seed, mult):
    """Lanczos (completed by deflated passes for k > 1, which see multiplicities); dense when n is too small for it."""
    rng = np.random.default_rng(seed)
    low = np.repeat(np.sort(rng.uniform(0, 1, len(mult))), mult)   # clusters of equal eigenvalues
    spectrum = np.sort(np.r_[low, rng.uniform(2, 20, n - len(low))])[:n]
    A, M = pencil(n, spectrum, complex_, seed)
    res = smallest_eigenpairs(A, M, k=k)
    np.testing.assert_allclose(res.eigenvalues, sla.eigh(A, M, eigvals_only=True)[:k], atol=1e-10)
    if k >= n - 2:
        assert res.method == "dense" and res.converged
    else:
        check_eigenpairs(res, A, M, k, 1e-10)


def test_path_graph_spectrum():
    n = 200
    res = smallest_eigenpairs(path_laplacian(n), sp.identity(n), k=6)
    exact = 2 - 2 * np.cos(np.pi * np.arange(6) / n)
    np.testing.assert_allclose(res.eigenvalues, exact, atol=1e-13)
    check_eigenpairs(res, path_laplacian(n), sp.identity(n), 6, 1e-10)
    # eigenvector of λ_1 is cos(π j (x + 1/2) / n) up to sign
    x = np.cos(np.pi * (np.arange(n) + 0.5) / n)
    x /= np.linalg.norm(x)
    assert abs(abs(res.eigenvectors[:, 1] @ x) - 1) < 1e-10


def test_a_warm_start_still_factorizes_when_the_floor_factor_is_asked_for():
    n = 300
    A, M = path_laplacian(n), sp.identity(n, format="csr")
    first = smallest_eigenpairs(A, M, k=1)
    warm = smallest_eigenpairs(A, M, k=1, v0=first.eigenvectors[:, 0])
    assert warm.factor is None and warm.factorizations == 0          # the warm start passed: nothing factorized
    floor = smallest_eigenpairs(A, M, k=1, v0=first.eigenvectors[:, 0],
                                solver=SolverOptions(backend="superlu", factor_shift="floor"))
    assert floor.factor is not None and floor.factorizations == 1
    b = np.arange(n, dtype=float)
    x = floor.factor.solve(b)
    assert np.allclose((A - floor.shift * M) @ x, b)


def test_flat_torus_grid_spectrum_with_multiplicities():
    m = 24
    cyc = sp.diags([-np.ones(m - 1), 2 * np.ones(m), -np.ones(m - 1)], [-1, 0, 1], format="lil")
    cyc[0, m - 1] = cyc[m - 1, 0] = -1
    cyc = cyc.tocsr()
    I = sp.identity(m)
    A = sp.kron(cyc, I) + sp.kron(I, cyc)
    lam1 = 2 - 2 * np.cos(2 * np.pi * np.arange(m) / m)
    exact = np.sort(np.add.outer(lam1, lam1).ravel())
    k = 13                                           # 1 + 4 + 4 + 4: complete clusters
    res = smallest_eigenpairs(A, sp.identity(m * m), k=k)
    np.testing.assert_allclose(res.eigenvalues, exact[:k], atol=1e-12)
    assert res.residuals.max() <= 1e-10


@pytest.mark.parametrize("theta", [0.3, np.pi, 2.5])
def test_twisted_cycle_complex_spectrum(theta):
    """Hermitian connection Laplacian with holonomy e^{iθ}: λ = 2 − 2cos((2πj − θ)/n)."""
    n = 40
    A = twisted_cycle(n, theta)
    res = smallest_eigenpairs(A, sp.identity(n), k=4)
    exact = np.sort(2 - 2 * np.cos((2 * np.pi * np.arange(n) - theta) / n))
    np.testing.assert_allclose(res.eigenvalues, exact[:4], atol=1e-12)
    assert res.eigenvalues[0] > 0.99 * (theta / n) ** 2   # nontrivial holonomy: no kernel
    check_eigenpairs(res, A, sp.identity(n), 4, 1e-10)


def test_p1_interval_spectrum():
    """P1 FEM on a uniform interval: λ_j = (6/h²)(1 − cos(πj/N)) / (2 + cos(πj/N))."""
    N = 50
    X = SimplicialComplex(np.column_stack([np.arange(N), np.arange(1, N + 1)]))
    E = EuclideanComplex(X, points=np.linspace(0, 1, N + 1)[:, None])
    res = smallest_eigenpairs(E.stiffness_matrix(), E.mass_matrix(), k=5)
    c = np.cos(np.pi * np.arange(5) / N)
    np.testing.assert_allclose(res.eigenvalues, 6 * N**2 * (1 - c) / (2 + c), rtol=1e-11, atol=1e-12)


def test_sigma_selects_nearest_and_v0_speeds_up():
    n = 100
    A = path_laplacian(n)
    exact = 2 - 2 * np.cos(np.pi * np.arange(n) / n)
    res = smallest_eigenpairs(A, sp.identity(n), k=3, sigma=1.0)
    np.testing.assert_allclose(res.eigenvalues, np.sort(exact[np.argsort(np.abs(exact - 1.0))[:3]]), atol=1e-12)
    assert res.shift == 1.0
    # σ exactly an eigenvalue: A − σM is exactly singular, the solver steps off by ε
    D = sp.diags(np.arange(10.0), format="csr")
    res2 = smallest_eigenpairs(D, sp.identity(10), k=3, sigma=4.0)
    np.testing.assert_allclose(res2.eigenvalues, [3.0, 4.0, 5.0], atol=1e-13)
    assert res2.shift == 4.0 - default_shift(D, sp.identity(10, format="csr"))     # stepped off the eigenvalue
    np.testing.assert_allclose((D - res2.shift * sp.identity(10)) @ res2.factor.solve(np.ones(10)), np.ones(10))
    cold = smallest_eigenpairs(A, sp.identity(n), k=1)
    warm = smallest_eigenpairs(A, sp.identity(n), k=1, v0=cold.eigenvectors[:, 0])
    assert cold.method == "lanczos" and warm.method == "rayleigh-ritz"
    assert warm.solves == 0 < cold.solves              # an exact eigenvector passes the test before any solve
    assert warm.eigenvalues[0] == pytest.approx(0.0, abs=1e-13)


# ---------------------------------------------------------------------- convergence criterion
def test_residual_criterion_and_convergence_error():
    n = 300
    A, Mm = path_laplacian(n), sp.identity(n)
    with pytest.raises(ConvergenceError) as info:
        smallest_eigenpairs(A, Mm, k=4, solver=SolverOptions(maxiter=5, tol=1e-17))
    part = info.value.result
    assert not part.converged and part.residuals.shape == (4,) and part.method == "lanczos"
    loose = smallest_eigenpairs(A, Mm, k=4, solver=SolverOptions(tol=1e-4))
    tight = smallest_eigenpairs(A, Mm, k=4, solver=SolverOptions(tol=1e-13))
    assert loose.method == tight.method == "lanczos"
    assert loose.solves < tight.solves
    assert np.all(loose.residuals <= 1e-4) and np.all(tight.residuals <= 1e-13)
    exact = 2 - 2 * np.cos(np.pi * np.arange(4) / n)
    assert np.abs(tight.eigenvalues - exact).max() < 1e-13
    # the criterion stays meaningful at λ = 0 (where ‖r‖/‖Au‖ is 1 by construction): the kernel
    # vector has a tiny backward error, a slightly perturbed one is rejected, and η is scale-free
    u = tight.eigenvectors[:, :1]
    assert backward_errors(A, Mm, [0.0], u)[0] < 1e-15
    v = u + 1e-6 * np.random.default_rng(0).normal(size=u.shape)
    eta_v = backward_errors(A, Mm, [0.0], v)[0]
    assert eta_v == pytest.approx(np.linalg.norm(A @ v) / (4 * np.linalg.norm(v)), rel=1e-12)  # ‖A‖₁ = 4
    assert eta_v > 1e4 * 1e-10
    assert backward_errors(1e8 * A, 1e-3 * Mm, [0.0], 5 * v)[0] == pytest.approx(eta_v, rel=1e-12)
    lam3 = tight.eigenvalues[3]
    np.testing.assert_allclose(backward_errors(A, Mm, tight.eigenvalues, tight.eigenvectors),
                               tight.residuals, rtol=1e-6, atol=4 * np.finfo(float).eps)
    assert backward_errors(A, Mm, [lam3 * (1 + 1e-6)], tight.eigenvectors[:, 3])[0] > 1e-10


def test_default_shift_scales_with_matrices():
    A, M = path_laplacian(20), sp.identity(20, format="csr")
    eps = default_shift(A, M)
    assert eps == pytest.approx(4 * np.sqrt(np.finfo(float).eps))
    assert default_shift(7 * A, M) == pytest.approx(7 * eps)
    assert default_shift(A, 5 * M) == pytest.approx(eps / 5)
    r1 = smallest_eigenpairs(A, M, k=3)
    r2 = smallest_eigenpairs(1e6 * A, 1e-3 * M, k=3)
    np.testing.assert_allclose(r2.eigenvalues, 1e9 * r1.eigenvalues, rtol=1e-10, atol=1e-3)


# ---------------------------------------------------------------------- solve
@pytest.mark.parametrize("complex_", [False, True])
def test_solve_matches_dense(complex_):
    A, M = pencil(30, np.linspace(0, 10, 30), complex_, seed=4)
    rng = np.random.default_rng(0)
    b = rng.normal(size=(30, 3)) + 1j * rng.normal(size=(30, 3))
    x = solve(sp.csr_matrix(A), sp.csr_matrix(M), 0.37, b)
    np.testing.assert_allclose((A - 0.37 * M) @ x, b, atol=1e-10)
    x1 = solve(A, M, 0.37, b[:, 0].real)
    np.testing.assert_allclose((A - 0.37 * M) @ x1, b[:, 0].real, atol=1e-10)
    with pytest.raises(InvalidOperatorError):
        solve(path_laplacian(5), sp.identity(5), 0.0, np.ones(5))   # singular
    with pytest.raises(ShapeError):
        solve(A, M, 0.37, np.ones(29))
    with pytest.raises(InvalidParameterError):
        solve(A, M, np.nan, np.ones(30))
    with pytest.raises(NonFiniteError):
        solve(A, M, 0.37, np.full(30, np.nan))


# ---------------------------------------------------------------------- bad input
def test_typed_errors_on_bad_input():
    A, M = path_laplacian(10), sp.identity(10, format="csr")
    with pytest.raises(ShapeError):
        smallest_eigenpairs(sp.csr_matrix(np.ones((3, 4))), sp.identity(3), k=1)
    with pytest.raises(ShapeError):
        smallest_eigenpairs(A, sp.identity(9), k=1)
    with pytest.raises(ShapeError):
        smallest_eigenpairs(np.ones(5), np.ones(5), k=1)
    with pytest.raises(InvalidParameterError):
        smallest_eigenpairs(A, M, k=11)
    with pytest.raises(InvalidParameterError):
        smallest_eigenpairs(A, M, k=0)
    with pytest.raises(InvalidParameterError):
        smallest_eigenpairs(A, M, k=1, solver=SolverOptions(tol=0.0))
    with pytest.raises(InvalidParameterError):
        smallest_eigenpairs(A, M, k=1, sigma=np.nan)
    bad = A.toarray()
    bad[3, 4] = np.nan
    with pytest.raises(NonFiniteError, match=r"A\[3, 4\]"):
        smallest_eigenpairs(bad, M, k=1)
    nonherm = A.toarray()
    nonherm[0, 1] = 5.0
    with pytest.raises(InvalidOperatorError, match="not Hermitian"):
        smallest_eigenpairs(nonherm, M, k=1)
    with pytest.raises(InvalidOperatorError, match="not Hermitian"):
        smallest_eigenpairs(1j * A, M, k=1)           # anti-Hermitian
    with pytest.raises(InvalidOperatorError, match="positive definite"):
        smallest_eigenpairs(A, -M, k=1)
    with pytest.raises(InvalidOperatorError, match="not positive semidefinite"):
        smallest_eigenpairs(A - 0.5 * M, M, k=2)
    far = sp.diags(np.r_[-100.0, np.arange(1.0, 10.0)], format="csr")   # negative eigenvalue far from 0
    with pytest.raises(InvalidOperatorError, match="not positive semidefinite"):
        smallest_eigenpairs(far, M, k=2)
    assert smallest_eigenpairs(far, M, k=1, sigma=-90.0).eigenvalues[0] == pytest.approx(-100.0)
    with pytest.raises(ShapeError):
        backward_errors(A, M, [0.0, 1.0], np.ones((10, 3)))
    with pytest.raises(ShapeError):
        smallest_eigenpairs(A, M, k=1, v0=np.ones(9))
    with pytest.raises(NonFiniteError):
        smallest_eigenpairs(A, M, k=1, v0=np.full(10, np.inf))


def test_block_size_option_and_cluster_message():
    import scipy.sparse as sp_

    from dhlb.errors import ConvergenceError as _CE
    from dhlb.errors import InvalidParameterError as _IPE
    from dhlb.linalg.eigen import smallest_eigenpairs as _se

    # a 12-fold cluster just above the lowest eigenvalue
    d = np.concatenate([[0.0], 1.0 + 1e-7 * np.arange(12), 5.0 + np.arange(40)])
    A, M = sp_.diags(d).tocsr(), sp_.identity(d.size, format="csr")
    res = _se(A, M, k=2, solver=SolverOptions(block_size=16))
    assert res.converged and res.block_size == 16
    np.testing.assert_allclose(res.eigenvalues, d[:2], atol=1e-9)
    with pytest.raises(_IPE, match="block_size"):
        _se(A, M, k=3, solver=SolverOptions(block_size=2))
    with pytest.raises(_CE, match="raise block_size"):
        _se(A, M, k=2, solver=SolverOptions(block_size=5, maxiter=3))


# ---------------------------------------------------------------------- ARPACK: multiplicities, counts
def test_multiple_eigenvalues_are_all_found():
    """A single-vector Krylov method can miss a copy of a multiple eigenvalue; the block completion finds it."""
    N = 24                                               # periodic N × N grid: eigenvalues of multiplicity 4
    T = sp.diags([-np.ones(N - 1), 2 * np.ones(N), -np.ones(N - 1)], [-1, 0, 1]).tolil()
    T[0, N - 1] = T[N - 1, 0] = -1
    I = sp.identity(N)
    A = (sp.kron(T, I) + sp.kron(I, T)).tocsr()
    w = 2 - 2 * np.cos(2 * np.pi * np.arange(N) / N)
    exact = np.sort((w[:, None] + w[None, :]).ravel())
    for k in (5, 9, 13, 17):
        res = smallest_eigenpairs(A, sp.identity(N * N), k=k)
        np.testing.assert_allclose(res.eigenvalues, exact[:k], atol=1e-10)


def test_dense_path_for_small_problems(monkeypatch):
    import dhlb.linalg.eigen as E

    monkeypatch.setattr(E, "DENSE_MAX", 400)
    n = 30
    A, M = path_laplacian(n), sp.identity(n, format="csr")
    res = smallest_eigenpairs(A, M, k=n)                 # every pair: too many for a Lanczos basis
    assert res.method == "dense" and res.converged and res.factorizations == 0
    np.testing.assert_allclose(res.eigenvalues, 2 - 2 * np.cos(np.pi * np.arange(n) / n), atol=1e-12)
    x = res.factor.solve(np.ones(n))                     # the factor of A − σM, σ = −ε
    np.testing.assert_allclose((A - res.shift * M) @ x, np.ones(n), rtol=1e-6)
    assert smallest_eigenpairs(A, M, k=2, solver="superlu").method == "lanczos"   # a named backend: sparse
    small = sp.diags(np.r_[-40.0, -2e-7, np.linspace(0.5, 3.0, 48)]).tocsr()      # psd=False: the lowest pairs,
    low = smallest_eigenpairs(small, sp.identity(50), k=2, psd=False)             # not the ones nearest to −ε
    assert low.method == "dense"
    np.testing.assert_allclose(low.eigenvalues, [-40.0, -2e-7])




@pytest.mark.parametrize("backend", ["superlu", None])
def test_solve_positive_definite_checks_lambda(backend):
    n = 40
    A, M = path_laplacian(n), sp.identity(n, format="csr")
    lam1 = 2 - 2 * np.cos(np.pi / n)                      # smallest nonzero eigenvalue; λ₀ = 0
    b = np.linspace(1, 2, n)
    x = solve(A, M, -0.1, b, backend=backend, positive_definite=True)
    np.testing.assert_allclose((A + 0.1 * M) @ x, b, atol=1e-12)
    for lam in (0.5 * lam1, 1.0):                         # above λ₀ = 0: indefinite
        with pytest.raises(InvalidOperatorError, match=f"not positive definite for λ = {lam:.10g}"):
            solve(A, M, lam, b, backend=backend, positive_definite=True)
        xi = solve(A, M, lam, b, backend=backend)         # the indefinite solve still works
        np.testing.assert_allclose((A - lam * M) @ xi, b, atol=1e-9)
    with pytest.raises(InvalidOperatorError, match="λ = 0"):
        solve(A, M, 0.0, b, backend=backend, positive_definite=True)   # singular: not PD either


# ---------------------------------------------------------------------- indefinite A (psd=False)
@pytest.mark.parametrize("complex_", [False, True])
def test_indefinite_pencil_lowest_pairs_certified_by_inertia(complex_):
    """psd=False: the k algebraically smallest pairs, also when some lie far below the default shift."""
    n = 1200
    rng = np.random.default_rng(3)
    d = np.sort(rng.uniform(1.0, 50.0, n))
    d[:3] = [-40.0, -2e-7, 0.5]                        # one far below, one just below −ε, one above
    Q = sp.diags(np.exp(1j * rng.uniform(0, 2 * np.pi, n)) if complex_ else np.ones(n))
    A = (Q @ sp.diags(d) @ Q.conj().T + 1e-3 * path_laplacian(n)).tocsr()
    M = sp.identity(n, format="csr")
    exact = np.linalg.eigvalsh(A.toarray())[:4]
    with pytest.raises(InvalidOperatorError, match="not positive semidefinite"):
        smallest_eigenpairs(A, M, k=2)
    res = smallest_eigenpairs(A, M, k=4, psd=False)
    np.testing.assert_allclose(res.eigenvalues, exact, rtol=1e-9, atol=1e-12)
    assert res.converged and res.factorizations >= 2          # −ε saw 2 below, the nearest search missed −40
    shifted = smallest_eigenpairs(A + 41.0 * M, M, k=1, psd=False)       # PSD now: one factorization suffices
    assert shifted.factorizations == 1 and shifted.eigenvalues[0] == pytest.approx(exact[0] + 41.0, rel=1e-9)
    with pytest.raises(InvalidParameterError, match="psd"):
        smallest_eigenpairs(A, M, k=1, psd="no")



def test_the_pencil_is_not_copied_nor_changed():
    """A canonical float or complex pencil is used as it is; duplicates in the caller's matrix are summed in a copy."""
    from dhlb.linalg._checks import validate_pair

    n = 40
    A = sp.diags([-np.ones(n - 1), 2 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1], format="csr").astype(complex)
    M = sp.identity(n, format="csr")
    A2, M2 = validate_pair(A, M)
    assert np.shares_memory(A2.data, A.data) and np.shares_memory(M2.data, M.data)
    D = sp.csr_matrix((np.ones(n + 1), np.r_[0, 0, np.arange(1, n)], np.r_[0, 2, np.arange(3, n + 2)]),
                      shape=(n, n))                                    # entry (0, 0) stored twice: not canonical
    assert not D.has_canonical_format
    before = (D.indptr.copy(), D.indices.copy(), D.data.copy())
    _, D2 = validate_pair(A, D)
    assert all(np.array_equal(a, b) for a, b in zip(before, (D.indptr, D.indices, D.data)))   # the input is untouched
    assert D2[0, 0] == 2.0 and D2.nnz == n and not np.shares_memory(D2.data, D.data)
