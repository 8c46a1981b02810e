"""The Lanczos eigensolver on a factorized shift (dhlb.fem._krylov): counts, fallback, multiplicities, orthogonality."""

import numpy as np
import pytest
import scipy.sparse as sp

from dhlb.errors import ConvergenceError
from dhlb.fem.solvers import backward_errors, smallest_eigenpairs


class CountingBackend:
    """SuperLU, counting the right-hand sides it solves."""

    name = "counting"

    def __init__(self):
        from dhlb.fem.backends import SuperLUBackend
        self.inner, self.blocks, self.columns = SuperLUBackend(), 0, 0

    def factorize(self, K, *, positive_definite=False):
        fac = self.inner.factorize(K, positive_definite=positive_definite)
        outer = self

        class Counted:
            name = "counting"

            def solve(self, B):
                outer.blocks += 1
                outer.columns += 1 if np.ndim(B) == 1 else np.shape(B)[1]
                return fac.solve(B)

        return Counted()


@pytest.mark.parametrize("k", [1, 3])
def test_iterations_count_block_solves_and_lanczos_matches_subspace(k):
    """Torus grid (spectrum known exactly, eigenvalue 4 of multiplicity 4): Lanczos with block k
    and the subspace iteration give the same eigenvalues; `iterations` counts block solves."""
    m = 16
    cyc = sp.diags([-np.ones(m - 1), 2 * np.ones(m), -np.ones(m - 1)], [-1, 0, 1], format="lil")
    cyc[0, m - 1] = cyc[m - 1, 0] = -1
    I = sp.identity(m)
    A = (sp.kron(cyc.tocsr(), I) + sp.kron(I, cyc.tocsr())).tocsr()
    lam1 = 2 - 2 * np.cos(2 * np.pi * np.arange(m) / m)
    exact = np.sort(np.add.outer(lam1, lam1).ravel())[:k]
    be = CountingBackend()
    lan = smallest_eigenpairs(A, sp.identity(m * m), k=k, backend=be)
    assert lan.method == "lanczos" and lan.block_size == (1 if k == 1 else k)
    assert be.blocks == lan.iterations and be.columns == lan.iterations * lan.block_size
    sub = smallest_eigenpairs(A, sp.identity(m * m), k=k, block_size=max(2 * k, k + 8))
    assert sub.method == "subspace"
    for res in (lan, sub):
        np.testing.assert_allclose(res.eigenvalues, exact, atol=1e-12)
        assert res.converged and np.all(res.residuals <= 1e-10)
        np.testing.assert_allclose(backward_errors(A, sp.identity(m * m), res.eigenvalues, res.eigenvectors),
                                   res.residuals, rtol=1e-6, atol=4 * np.finfo(float).eps)
    assert lan.iterations * lan.block_size < sub.iterations * sub.block_size      # fewer right-hand sides


def test_lanczos_falls_back_to_subspace_iteration():
    """A tight cluster (4 eigenvalues within 3e-7) right above λ₁ with k = 2: with maxiter = 20
    Lanczos (block 2) does not resolve it within its 10 steps and the subspace iteration (block 10
    > cluster), warm-started from its Ritz vectors, finishes; with maxiter = 40 Lanczos finishes
    itself. Both answers are checked to the backward error."""
    d = np.concatenate([[0.0], 1.0 + 1e-7 * np.arange(4), 5.0 + np.arange(80)])
    A, M = sp.diags(d).tocsr(), sp.identity(d.size, format="csr")
    mixed = smallest_eigenpairs(A, M, k=2, maxiter=20)
    assert mixed.method == "lanczos+subspace" and 10 < mixed.iterations <= 20 and mixed.block_size == 10
    pure = smallest_eigenpairs(A, M, k=2, maxiter=40)
    assert pure.method == "lanczos" and pure.iterations <= 20
    for res in (mixed, pure):
        np.testing.assert_allclose(res.eigenvalues, d[:2], atol=1e-9)
        assert res.converged and np.all(res.residuals <= 1e-10)
        np.testing.assert_allclose(backward_errors(A, M, res.eigenvalues, res.eigenvectors), res.residuals,
                                   rtol=1e-6, atol=4 * np.finfo(float).eps)
    with pytest.raises(ConvergenceError) as info:
        smallest_eigenpairs(A, M, k=2, maxiter=2, tol=1e-15)
    assert info.value.result.method == "lanczos+subspace" and info.value.result.iterations == 2


def test_lanczos_finds_every_copy_of_a_multiple_eigenvalue():
    """Exact multiplicities (3 and 2) at the bottom: block Lanczos with block k returns all copies."""
    d = np.r_[0.25, 0.25, 0.25, 0.5, 0.5, np.linspace(1, 9, 95)]
    rng = np.random.default_rng(7)
    Q, _ = np.linalg.qr(rng.normal(size=(100, 100)))
    A = Q @ np.diag(d) @ Q.T
    A = sp.csr_matrix(0.5 * (A + A.T))
    res = smallest_eigenpairs(A, sp.identity(100, format="csr"), k=5)
    assert res.method == "lanczos"
    np.testing.assert_allclose(res.eigenvalues, d[:5], atol=1e-12)


# ---------------------------------------------------------------------- positive definite solves


def test_lanczos_basis_stays_m_orthonormal_through_restarts(monkeypatch):
    """The Gram–Schmidt with a local first pass keeps VᴴMV = I to working precision (300 steps, restarts)."""
    import scipy.sparse.linalg as spla

    import dhlb.fem._krylov as K

    n = 3000
    A = sp.diags([-np.ones(n - 1), np.r_[1, 2 * np.ones(n - 2), 1], -np.ones(n - 1)], [-1, 0, 1], format="csc")
    M = sp.diags(np.linspace(1, 2, n), format="csc")
    sigma = -1e-3
    lu = spla.splu((A - sigma * M).tocsc())
    worst = []
    expand = K._expand

    def checked(V, MV, H, W, M_, j, nv, rng):
        expand(V, MV, H, W, M_, j, nv, rng)
        q = nv + W.shape[1]
        worst.append(np.abs(V[:, :q].conj().T @ MV[:, :q] - np.eye(q)).max())

    monkeypatch.setattr(K, "_expand", checked)
    x0 = np.random.default_rng(0).standard_normal((n, 1))
    out = K.lanczos(lu.solve, A, M, x0, 4, shift=sigma, tol=1e-14, maxsteps=300, capacity=20,
                    accept=lambda X, theta: None)
    assert out.steps == 300 and len(worst) == 300
    assert max(worst) < 1e-13  # one Gram–Schmidt pass without reorthogonalization: 1.1e-12
