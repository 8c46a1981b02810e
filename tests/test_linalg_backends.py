"""Tests of dhlb.linalg.backends: every installed backend gives the same eigenpairs and solves."""

import re
import warnings

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse as sp

from dhlb.errors import InvalidOperatorError, InvalidParameterError
from dhlb.fem import bundle_matrices
from dhlb.linalg import SolverOptions, backward_errors, smallest_eigenpairs, solve
from dhlb.linalg import backends as B

ALL = ["superlu", "cholmod", "cholespy", "amg-lobpcg"]
NEEDS = {"cholmod": "cvxopt", "cholespy": "cholespy", "amg-lobpcg": "pyamg"}


def _param(name):
    mod = NEEDS.get(name)
    missing = mod is not None and not B._importable(mod)
    return pytest.param(name, marks=pytest.mark.skipif(missing, reason=f"{mod} is not installed"))


BACKENDS = [_param(b) for b in ALL]
DIRECT = [_param(b) for b in ALL if b != "amg-lobpcg"]


# ---------------------------------------------------------------------- problems (built once)
@pytest.fixture(scope="module")
def torus_problem():
    """n = 4 tangent bundle of the example torus: complex Hermitian, 2-D pattern."""
    from dhlb.io import example_path, read_surface
    from dhlb.mesh import tangent_bundle

    tb = tangent_bundle(*read_surface(example_path("torus.obj")), n=4)
    A, M = bundle_matrices(tb.bundle, tb.geometry)
    return A.tocsr(), M.tocsr()


@pytest.fixture(scope="module")
def box_problem():
    """Curved line bundle (velocity of a rigid rotation, curl = 2 e_z) on a 5³ tet box: 3-D pattern."""
    from dhlb.geometry import EuclideanComplex
    from dhlb.mesh import box_tet_mesh
    from dhlb.vortex import velocity_bundle

    mesh = box_tet_mesh(5, lower=-1.0, upper=1.0)
    rot = mesh.points[:, [1, 0, 2]] * np.array([-1.0, 1.0, 0.0])
    bundle = velocity_bundle(mesh.complex, mesh.points, rot, hbar=0.5)
    A, M = bundle_matrices(bundle, EuclideanComplex(mesh.complex, points=mesh.points))
    return A.tocsr(), M.tocsr()


def _dense_reference(A, M, k):
    return sla.eigh(A.toarray(), M.toarray(), subset_by_index=[0, k - 1])


@pytest.mark.parametrize("problem", ["torus_problem", "box_problem"])
@pytest.mark.parametrize("backend", BACKENDS)
def test_same_eigenpairs_on_every_backend(backend, problem, request):
    A, M = request.getfixturevalue(problem)
    assert np.iscomplexobj(A.data) and np.abs(A.data.imag).max() > 1e-3     # a genuinely curved bundle
    k, tol = 4, 1e-10
    lam_ref, U_ref = _dense_reference(A, M, k + 1)
    assert lam_ref[k] - lam_ref[k - 1] > 1e-3 * lam_ref[k]                   # k-th pair well separated
    res = smallest_eigenpairs(A, M, k=k, solver=SolverOptions(tol=tol, backend=backend))
    assert res.converged and res.backend == backend
    # eigenvalues to the accuracy implied by the backward error: |δλ| <= η (‖A‖₁ + |λ| ‖M‖₁) κ(M)-ish
    normA, normM = abs(A).sum(0).max(), abs(M).sum(0).max()
    np.testing.assert_allclose(res.eigenvalues, lam_ref[:k], rtol=0, atol=1e3 * tol * (normA + lam_ref[k] * normM))
    np.testing.assert_allclose(res.eigenvectors.conj().T @ (M @ res.eigenvectors), np.eye(k), atol=1e-10)
    np.testing.assert_allclose(backward_errors(A, M, res.eigenvalues, res.eigenvectors), res.residuals,
                               rtol=1e-6, atol=1e-15)
    assert np.all(res.residuals <= tol)
    # the same invariant subspace as the dense solver (eigenvalues may be multiple: compare spans)
    cosines = np.linalg.svd(U_ref[:, :k].conj().T @ (M @ res.eigenvectors), compute_uv=False)
    np.testing.assert_allclose(cosines, 1.0, atol=1e-6)


@pytest.mark.parametrize("backend", BACKENDS)
def test_same_solve_on_every_backend(backend, torus_problem):
    A, M = torus_problem
    rng = np.random.default_rng(1)
    b = rng.normal(size=(A.shape[0], 2)) + 1j * rng.normal(size=(A.shape[0], 2))
    lam = -0.5 * abs(A).sum(0).max() / M.diagonal().real.max() * 1e-3        # below the spectrum: PD
    x = solve(A, M, lam, b, backend=backend)
    ref = np.linalg.solve((A - lam * M).toarray(), b)
    np.testing.assert_allclose(x, ref, rtol=1e-8, atol=1e-8 * np.abs(ref).max())
    x1 = solve(A, M, lam, b[:, 0].real, backend=backend)                       # real rhs, complex matrix
    np.testing.assert_allclose(x1, np.linalg.solve((A - lam * M).toarray(), b[:, 0].real),
                               rtol=1e-8, atol=1e-8 * np.abs(ref).max())


@pytest.mark.parametrize("backend", DIRECT)
def test_indefinite_shift_and_singular_on_direct_backends(backend, torus_problem):
    A, M = torus_problem
    lam_ref = _dense_reference(A, M, 6)[0]
    sigma = 0.5 * (lam_ref[2] + lam_ref[3])                                    # inside the spectrum
    res = smallest_eigenpairs(A, M, k=2, sigma=sigma, solver=SolverOptions(backend=backend))
    np.testing.assert_allclose(np.sort(res.eigenvalues), np.sort(lam_ref[[2, 3]]), rtol=1e-8)
    assert res.backend in (backend, "superlu")                                 # Cholesky falls back to LU
    b = np.ones(A.shape[0])
    x = solve(A, M, sigma, b, backend=backend)
    np.testing.assert_allclose((A - sigma * M) @ x, b, atol=1e-8)
    with pytest.raises(InvalidOperatorError):                                  # A − λM exactly singular
        solve(sp.diags(np.arange(5.0)), sp.identity(5), 2.0, np.ones(5), backend=backend)
    with pytest.raises(InvalidOperatorError, match="not positive semidefinite"):
        smallest_eigenpairs(A - 2 * lam_ref[0] * M, M, k=1, solver=SolverOptions(backend=backend))


@pytest.mark.parametrize("backend", BACKENDS)
def test_real_matrices_and_warm_start(backend):
    n = 60                                                  # path graph: λ_j = 2 − 2cos(πj/n)
    A = sp.diags([-np.ones(n - 1), np.r_[1, 2 * np.ones(n - 2), 1], -np.ones(n - 1)], [-1, 0, 1], format="csr")
    res = smallest_eigenpairs(A, sp.identity(n), k=3, solver=SolverOptions(backend=backend))
    np.testing.assert_allclose(res.eigenvalues, 2 - 2 * np.cos(np.pi * np.arange(3) / n), atol=1e-10)
    assert res.eigenvectors.dtype == np.float64 and res.backend == backend
    warm = smallest_eigenpairs(A, sp.identity(n), k=3, v0=res.eigenvectors, solver=SolverOptions(backend=backend))
    assert warm.iterations <= res.iterations and warm.converged


@pytest.mark.skipif(not B._importable("pyamg"), reason="pyamg is not installed")
def test_amg_lobpcg_rejects_sigma(torus_problem):
    A, M = torus_problem
    with pytest.raises(InvalidParameterError, match="sigma"):
        smallest_eigenpairs(A, M, k=1, sigma=1.0, solver=SolverOptions(backend="amg-lobpcg"))


# ---------------------------------------------------------------------- selection
def test_auto_selection_rules(torus_problem, monkeypatch):
    avail = B.available_backends()
    assert avail[0] == "superlu" and set(avail) <= set(ALL)
    assert B.select_backend(1000, 7000) == "cholmod"                           # small: CHOLMOD (AMD) too
    assert "cholmod" in avail                                                   # cvxopt is a dependency
    direct = "cholmod"
    assert B.select_backend(50_000, 350_000) == direct                          # 2-D pattern
    three_d = "amg-lobpcg" if "amg-lobpcg" in avail else direct
    assert B.select_backend(50_000, 750_000) == three_d                         # 3-D pattern
    assert B.select_backend(30_000, 450_000, dimension=2.6) == three_d          # 3-D, >= 10k: not SuperLU's rule
    assert B.select_backend(50_000, 750_000, shifted=True) == "superlu"         # maybe indefinite: L D Lᴴ
    assert B.select_backend(50_000, 750_000, eigen=False) == direct             # PD linear solve: Cholesky
    assert B.select_backend(50_000, 750_000, eigen=False, shifted=True) == "superlu"
    assert B.select_backend(3_000_000, 21_000_000) == direct                    # a huge surface: still direct
    # availability is honoured: with only SuperLU installed everything goes to SuperLU
    monkeypatch.setattr(B, "available_backends", lambda: ["superlu"])
    assert B.select_backend(50_000, 750_000) == B.select_backend(3_000_000, 2e7) == "superlu"
    monkeypatch.undo()
    A, M = torus_problem
    assert A.shape[0] <= 400                                                     # the example torus is small:
    assert smallest_eigenpairs(A, M, k=1).backend == "dense"                     # auto solves it densely
    assert smallest_eigenpairs(A, M, k=1, solver=SolverOptions(backend="auto")).method == "dense"
    big = sp.block_diag([A] * 3, format="csr"), sp.block_diag([M] * 3, format="csr")
    assert smallest_eigenpairs(*big, k=1).backend == B.select_backend(big[0].shape[0], big[0].nnz) == "cholmod"


def test_bad_backend_name_lists_available(monkeypatch):
    A, M = sp.identity(3, format="csr"), sp.identity(3, format="csr")
    with pytest.raises(InvalidParameterError, match=r"unknown backend 'lapack'.*superlu") as info:
        smallest_eigenpairs(A, M, k=1, solver=SolverOptions(backend="lapack"))
    for name in B.available_backends():
        assert repr(name) in str(info.value)
    with pytest.raises(InvalidParameterError, match="unknown backend"):
        solve(A, M, 0.5, np.ones(3), backend="mumps")
    monkeypatch.setattr(B, "available_backends", lambda: ["superlu"])         # registered, not installed
    with pytest.raises(InvalidParameterError, match=r"'cholmod' is not installed.*cvxopt"):
        smallest_eigenpairs(A, M, k=1, solver=SolverOptions(backend="cholmod"))
    with pytest.raises(TypeError, match="factorize"):
        smallest_eigenpairs(A, M, k=1, solver=SolverOptions(backend=object()))


# ---------------------------------------------------------------------- symbolic reuse, thread guard
@pytest.mark.parametrize("backend", [b for b in DIRECT if b.values[0] in ("superlu", "cholmod")])
def test_symbolic_analysis_is_reused_across_a_parameter_sweep(backend, torus_problem, monkeypatch):
    import dhlb.linalg.backends_cholesky as C
    import dhlb.linalg.ordering as O

    A, M = torus_problem
    monkeypatch.setattr(O, "ND_MIN", 10)         # the torus counts as large: both order by (cached) METIS
    monkeypatch.setattr(C, "METIS_MIN", 10)
    B.clear_cache()
    lams = []
    for t in (1.0, 2.0, 3.0):                       # same pattern, new values: a sweep over a scale
        res = smallest_eigenpairs(t * A, M, k=2, solver=SolverOptions(backend=backend))
        lams.append(res.eigenvalues)
    info = B.cache_info()
    assert info == {"misses": 1, "hits": 2, "size": 1}      # one analysis, then numeric factorizations only
    np.testing.assert_allclose(lams[1], 2 * lams[0], rtol=1e-9)
    np.testing.assert_allclose(lams[2], 3 * lams[0], rtol=1e-9)
    B.clear_cache()
    assert B.cache_info() == {"hits": 0, "misses": 0, "size": 0}


@pytest.mark.skipif(not B._importable("threadpoolctl"), reason="threadpoolctl is not installed")
def test_blas_threads_are_limited_inside_factorizations(monkeypatch):
    from threadpoolctl import threadpool_info, threadpool_limits

    for v in B.THREAD_VARIABLES:  # a user's variable would win (next test)
        monkeypatch.delenv(v, raising=False)
    seen = []

    class Spy(B.SuperLUBackend):
        name = "spy"

        def factorize(self, K, *, positive_definite=False):
            seen.append([p["num_threads"] for p in threadpool_info() if p["user_api"] == "blas"])
            return super().factorize(K, positive_definite=positive_definite)

    n = 30
    A = sp.diags([-np.ones(n - 1), np.r_[1, 2 * np.ones(n - 2), 1], -np.ones(n - 1)], [-1, 0, 1], format="csr")
    with threadpool_limits(limits=2, user_api="blas"):
        before = [p["num_threads"] for p in threadpool_info() if p["user_api"] == "blas"]
        assert smallest_eigenpairs(A, sp.identity(n), k=1, solver=SolverOptions(backend=Spy())).backend == "superlu"
        solve(A, sp.identity(n), -1.0, np.ones(n), backend=Spy())
        after = [p["num_threads"] for p in threadpool_info() if p["user_api"] == "blas"]
    assert len(seen) == 2 and all(t == [B.BLAS_THREADS] * len(t) for t in seen)
    assert after == before                                   # restored on exit


def test_a_users_thread_variable_wins(monkeypatch):
    """With OPENBLAS_NUM_THREADS (or another thread variable) set, dhlb leaves the pools alone."""
    from threadpoolctl import threadpool_info, threadpool_limits

    monkeypatch.setenv("OPENBLAS_NUM_THREADS", "2")
    with threadpool_limits(limits=2, user_api="blas"):
        before = [p["num_threads"] for p in threadpool_info() if p["user_api"] == "blas"]
        with B.blas_guard():
            inside = [p["num_threads"] for p in threadpool_info() if p["user_api"] == "blas"]
    assert inside == before
    monkeypatch.delenv("OPENBLAS_NUM_THREADS")
    for v in B.THREAD_VARIABLES:
        monkeypatch.delenv(v, raising=False)
    with threadpool_limits(limits=2, user_api="blas"), B.blas_guard():
        inside = [p["num_threads"] for p in threadpool_info() if p["user_api"] == "blas"]
    assert inside and all(t == B.BLAS_THREADS for t in inside)


def test_real_embedding_is_symmetric_and_equivalent():
    pytest.importorskip("cholespy")
    from dhlb.linalg.backends_cholesky import real_embedding

    rng = np.random.default_rng(3)
    Z = rng.normal(size=(6, 6)) + 1j * rng.normal(size=(6, 6))
    K = Z @ Z.conj().T + np.eye(6)
    K = 0.5 * (K + K.conj().T)                              # exactly Hermitian
    E = real_embedding(sp.csc_matrix(K)).toarray()
    np.testing.assert_array_equal(E, E.T)
    np.testing.assert_allclose(np.sort(np.linalg.eigvalsh(E)), np.sort(np.repeat(np.linalg.eigvalsh(K), 2)),
                               rtol=1e-12)
    x = rng.normal(size=6) + 1j * rng.normal(size=6)
    y = E @ np.r_[x.real, x.imag]
    np.testing.assert_allclose(y[:6] + 1j * y[6:], K @ x, rtol=1e-12)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        np.testing.assert_allclose(B.get_backend("cholespy").factorize(sp.csc_matrix(K)).solve(K @ x), x, rtol=1e-10)


def test_pattern_dimension_tells_surfaces_with_blocks_from_tet_meshes(torus_problem):
    """nnz per row is ~14 both for a surface with 2 × 2 blocks (real embedding) and for P1 on
    tets; the ball-growth dimension separates them, and auto selection uses it."""
    from dhlb.geometry import EuclideanComplex
    from dhlb.linalg.backends_cholesky import real_embedding
    from dhlb.mesh import box_tet_mesh

    A, _ = torus_problem
    n = A.shape[0]
    perm = np.empty(2 * n, dtype=int)
    perm[0::2], perm[1::2] = np.arange(n), np.arange(n, 2 * n)      # interleave (Re, Im) per vertex
    E = real_embedding(A).tocsr()[perm][:, perm]
    assert E.nnz / E.shape[0] >= 10 and A.nnz / n < 10
    assert B.pattern_dimension(A.tocsr()) < 2.2 and B.pattern_dimension(E) < 2.2
    mesh = box_tet_mesh(16)
    S = EuclideanComplex(mesh.complex, points=mesh.points).stiffness_matrix().tocsr()
    assert S.nnz / S.shape[0] >= 10 and B.pattern_dimension(S) >= 2.2
    direct = "cholmod" if "cholmod" in B.available_backends() else "superlu"
    three_d = "amg-lobpcg" if "amg-lobpcg" in B.available_backends() else direct
    assert B.select_backend(50_000, 700_000, dimension=2.0) == direct
    assert B.select_backend(50_000, 700_000, dimension=lambda: 2.6) == three_d


def test_cholmod_nested_dissection_for_large_matrices_gives_the_same_eigenpairs(torus_problem, monkeypatch):
    import dhlb.linalg.backends_cholesky as C
    import dhlb.linalg.ordering as O

    A, M = torus_problem
    ref = smallest_eigenpairs(A, M, k=2, solver=SolverOptions(backend="superlu"))
    monkeypatch.setattr(C, "METIS_MIN", 10)  # the torus counts as "large": METIS' order is passed to CHOLMOD
    monkeypatch.setattr(O, "ND_MIN", 10)
    B.clear_cache()
    res = smallest_eigenpairs(A, M, k=2, solver=SolverOptions(backend="cholmod"))
    assert res.backend == "cholmod" and B.cache_info()["misses"] >= 1
    np.testing.assert_allclose(res.eigenvalues, ref.eigenvalues, rtol=1e-9)


def test_cholmod_solves_complex_right_hand_sides_with_real_and_complex_factors():
    rng = np.random.default_rng(3)
    n = 60
    R = sp.random(n, n, density=0.1, random_state=4)
    K = (R @ R.T + n * sp.identity(n)).tocsc()                       # real SPD
    H = (K + 1j * (R - R.T)).tocsc()                                 # complex Hermitian PD (diagonally dominant)
    B2 = rng.standard_normal((n, 3)) + 1j * rng.standard_normal((n, 3))
    for mat in (K, H):
        fac = B.get_backend("cholmod").factorize(mat, positive_definite=True)
        assert fac.name == "cholmod"
        for rhs in (B2, B2[:, 0], B2.real[:, 1]):
            x = fac.solve(rhs)
            assert x.shape == rhs.shape
            np.testing.assert_allclose(mat @ x, rhs, atol=1e-10 * np.abs(rhs).max())
        before = B2.copy()
        fac.solve(B2)
        assert np.array_equal(B2, before)                            # the right-hand side is not overwritten


def test_cholmod_leaves_cvxopts_global_options_as_it_found_them():
    from cvxopt import cholmod

    before = dict(cholmod.options)
    cholmod.options["supernodal"] = 0                            # a user's own setting
    try:
        K = sp.csc_matrix(np.array([[4.0, 1.0], [1.0, 3.0]]))
        fac = B.get_backend("cholmod").factorize(K, positive_definite=True)
        np.testing.assert_allclose(K @ fac.solve(np.ones(2)), np.ones(2))
        assert cholmod.options == {"supernodal": 0}
        with pytest.raises(InvalidOperatorError):
            B.get_backend("cholmod").factorize(sp.csc_matrix(np.diag([1.0, -1.0])), positive_definite=True)
        assert cholmod.options == {"supernodal": 0}
    finally:
        cholmod.options.clear()
        cholmod.options.update(before)


def test_cholmod_refuses_or_falls_back_on_an_indefinite_matrix():
    K = sp.diags([2.0, -1.0, 3.0]).tocsc()
    with pytest.raises(InvalidOperatorError, match=r"not positive definite \(CHOLMOD"):
        B.get_backend("cholmod").factorize(K, positive_definite=True)
    fac = B.get_backend("cholmod").factorize(K)
    assert fac.name == "superlu"
    np.testing.assert_allclose(fac.solve(np.ones(3)), [0.5, -1.0, 1 / 3])


# ---------------------------------------------------------------------- memory
def test_factorization_that_does_not_fit_says_memory(monkeypatch):
    """Issue 15 point 5: a factorization over the memory limit is refused (or falls back), never a SuperLU error."""
    from dhlb.linalg import memory

    n = 40_000                                             # a 200 × 200 grid Laplacian, 2-D pattern
    m = 200
    T = sp.diags([-np.ones(m - 1), 2 * np.ones(m), -np.ones(m - 1)], [-1, 0, 1])
    A = (sp.kron(T, sp.identity(m)) + sp.kron(sp.identity(m), T)).tocsr()
    M = sp.identity(n, format="csr")
    need = memory.factor_bytes(n, A.nnz, complex_=False, dimension=2.0)
    monkeypatch.setattr(memory, "_LIMIT", need // 4)       # an artificially small limit
    with pytest.raises(memory.InsufficientMemoryError, match=r"40,000-unknown .* needs about .* GiB") as info:
        smallest_eigenpairs(A, M, k=1, solver=SolverOptions(backend="superlu"))
    assert info.value.needed == need and info.value.available <= need // 4
    with pytest.raises(memory.InsufficientMemoryError):
        solve(A, M, -1.0, np.ones(n), backend="superlu")
    if "amg-lobpcg" in B.available_backends():             # auto: the iterative backend, and the result says so
        res = smallest_eigenpairs(A, M, k=1)
        assert res.converged and res.backend == "amg-lobpcg" and "would not fit in memory" in res.note
        np.testing.assert_allclose(res.eigenvalues, [2 * (2 - 2 * np.cos(np.pi / (m + 1)))], rtol=1e-8)


def test_memory_model_overestimates_measured_factors():
    """The model must not refuse what fits: compare it with SuperLU's actual factor storage (nested dissection)."""
    from dhlb.linalg import memory
    from dhlb.linalg.backends import SuperLUBackend, pattern_dimension

    for m in (60, 120):
        T = sp.diags([-np.ones(m - 1), 2 * np.ones(m), -np.ones(m - 1)], [-1, 0, 1])
        A = (sp.kron(T, sp.identity(m)) + sp.kron(sp.identity(m), T) + 1e-3 * sp.identity(m * m)).tocsc()
        fac = SuperLUBackend().factorize(A)
        stored = (fac.lu.L.nnz + fac.lu.U.nnz) * (8 + 4)   # values + row indices
        est = memory.factor_bytes(A.shape[0], A.nnz, complex_=False, dimension=pattern_dimension(A))
        assert stored < est < 20 * stored                  # measured 9.5–11×: the model covers SuperLU's workspace


@pytest.mark.parametrize("backend", [b for b in B.available_backends() if b != "petsc"])
def test_bitwise_reproducible_and_seeded(backend):
    """Issue 19 point 10: two runs give the same bits on every backend; the start vectors take a seed."""
    m = 40                                                 # a 40 × 41 grid: simple eigenvalues
    T1 = sp.diags([-np.ones(m - 1), 2 * np.ones(m), -np.ones(m - 1)], [-1, 0, 1])
    T2 = sp.diags([-np.ones(m), 2 * np.ones(m + 1), -np.ones(m)], [-1, 0, 1])
    A = (sp.kron(T1, sp.identity(m + 1)) + sp.kron(sp.identity(m), T2)).tocsr()
    M = sp.identity(m * (m + 1), format="csr")
    r1, r2 = (smallest_eigenpairs(A, M, k=2, solver=SolverOptions(backend=backend, seed=7)) for _ in range(2))
    assert np.array_equal(r1.eigenvalues, r2.eigenvalues) and np.array_equal(r1.eigenvectors, r2.eigenvectors)
    r3 = smallest_eigenpairs(A, M, k=2, solver=SolverOptions(backend=backend, seed=8))
    np.testing.assert_allclose(r3.eigenvalues, r1.eigenvalues, rtol=1e-8)
    with pytest.raises(InvalidParameterError, match="seed"):
        smallest_eigenpairs(A, M, k=1, solver=SolverOptions(backend=backend, seed=-1))


def test_number_of_eigenpairs_is_checked_against_memory_before_work(monkeypatch):
    """Issue 19 point 1: the number of eigenpairs scales memory; too many is refused up front, naming k."""
    from dhlb.errors import ResourceLimitError
    from dhlb.linalg import memory

    n = 5_000
    A = sp.diags(np.arange(1.0, n + 1)).tocsr()
    monkeypatch.setattr(memory, "_LIMIT", 4 * 1024**2)      # 4 MiB: room for a few vectors of 5,000 reals
    with pytest.raises(ResourceLimitError, match=r"k = 200 .* at most about k = \d+ eigenpairs"):
        smallest_eigenpairs(A, sp.identity(n, format="csr"), k=200)
    assert smallest_eigenpairs(A, sp.identity(n, format="csr"), k=2).converged


# ---------------------------------------------------------------------- every automatic choice converges (issue 29)
_AMG = B._importable("pyamg")


def _tet_pencil(m):
    from dhlb.geometry import EuclideanComplex
    from dhlb.mesh import box_tet_mesh

    mesh = box_tet_mesh(m)
    geo = EuclideanComplex(mesh.complex, points=mesh.points)
    return geo.stiffness_matrix().tocsr(), geo.mass_matrix(lumped=True).tocsr()


@pytest.mark.parametrize("m, expected, bound", [(8, "cholmod", 60), (22, "amg-lobpcg" if _AMG else "cholmod", 80)])
def test_auto_choice_on_tet_laplacians_converges_in_bounded_iterations(m, expected, bound):
    A, M = _tet_pencil(m)                     # 729 and 12,167 unknowns: below and above ITERATIVE_3D
    res = smallest_eigenpairs(A, M, k=3)
    assert res.backend == expected and res.converged
    assert res.iterations <= bound, res.iterations      # measured: 49 (ARPACK solves), 62 (LOBPCG iterations)
    assert abs(res.eigenvalues[0]) < 1e-8


def test_auto_choice_on_2d_problems_converges_in_bounded_iterations(torus_problem):
    A, M = torus_problem                                        # small: dense
    res = smallest_eigenpairs(A, M, k=4)
    assert res.backend == "dense" and res.converged
    n = 120                                                     # 14,400 unknowns, a 2-D grid: CHOLMOD
    T = sp.diags([-np.ones(n - 1), np.r_[1, 2 * np.ones(n - 2), 1], -np.ones(n - 1)], [-1, 0, 1])
    A = (sp.kron(T, sp.identity(n)) + sp.kron(sp.identity(n), T)).tocsr()
    res = smallest_eigenpairs(A, sp.identity(n * n, format="csr"), k=3)
    assert res.backend == "cholmod" and res.converged and res.iterations <= 60, res.iterations


def test_auto_choice_on_a_quaternionic_pencil_converges_in_bounded_iterations():
    from dhlb.conformal import conformal_deformation, default_charge, point_charge_factor
    from dhlb.mesh import ball_tet_mesh

    mesh = ball_tet_mesh(11)                  # 11,614 complex unknowns (rank 2): amg-lobpcg when pyamg is installed
    res = conformal_deformation(mesh, None, point_charge_factor(default_charge(mesh)))
    s = res.statistics["solver"]
    assert s["backend"] == ("amg-lobpcg" if _AMG else "superlu") and s["converged"]
    assert s["iterations"] <= 100, s          # measured: 43 LOBPCG iterations on ball_tet_mesh(14)


def test_indefinite_pencils_never_go_to_the_iterative_backend():
    A, M = _tet_pencil(22)                    # a 3-D pattern above ITERATIVE_3D, made indefinite
    K = (A - 30.0 * M).tocsr()
    res = smallest_eigenpairs(K, M, k=1, psd=False)
    assert res.backend == "superlu" and res.converged and res.factorizations <= 12
    assert res.eigenvalues[0] == pytest.approx(-30.0, abs=1e-8)


@pytest.mark.skipif(not _AMG, reason="pyamg is not installed")
def test_stalled_amg_lobpcg_stops_naming_a_direct_backend():
    """The plain connection energy of bunny-tet under the old default charge: indefinite, AMG cannot precondition it.

    Before: LOBPCG counted each breakdown as one iteration and went on for more than 12 minutes.
    """
    import os

    from dhlb.conformal import default_charge, edge_gradients, point_charge_factor, quaternion_bundle
    from dhlb.errors import ConvergenceError
    from dhlb.fem import connection_laplacian, connection_mass
    from dhlb.geometry import EuclideanComplex
    from dhlb.mesh import check_tet_mesh

    with np.load(os.path.join(os.path.dirname(__file__), "data", "bunny-tet.npz")) as z:
        mesh = check_tet_mesh(z["points"], z["tets"].astype(np.int64))
    C = default_charge(mesh)
    C[0, 3] = 0.5 * float(np.linalg.norm(np.ptp(mesh.points, axis=0)))
    geo = EuclideanComplex(mesh.complex, points=mesh.points)
    A = connection_laplacian(quaternion_bundle(mesh, edge_gradients(mesh, point_charge_factor(C))), geo)
    M = connection_mass(geo, 2)
    assert B.select_backend(A.shape[0], A.nnz, dimension=lambda: B.pattern_dimension(A)) == "amg-lobpcg"
    with pytest.raises(ConvergenceError, match=r"stalled.*backend='(superlu|cholmod)'") as info:
        smallest_eigenpairs(A, M, k=1, solver=SolverOptions(maxiter=30))
    its = int(re.search(r"after (\d+) iterations", str(info.value)).group(1))
    assert its <= 50
