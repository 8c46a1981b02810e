"""The ``petsc`` backend (PETSc/SLEPc, complex scalars): skipped where petsc4py/slepc4py do not import.

In-process tests run on one MPI rank; the ``mpirun -n 2`` tests launch tests/mpi/run_checks.py
and the MPI command line (``python -m dhlb.cli.mpi``) when ``mpirun`` is on the path.
Set up the environment with ``.ci/mpi-setup.sh`` (docs/mpi.md) and run this file with its python.
"""

import itertools
import json
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb.errors import InvalidOperatorError
from dhlb.linalg import SolverOptions, smallest_eigenpairs
from dhlb.linalg.backends import _REGISTRY, register_backend
from dhlb.linalg.backends_petsc import PetscBackend, petsc_available, row_ranges
from tests.mpi_launch import MPIRUN, mpirun

ROOT = Path(__file__).resolve().parents[1]
needs_petsc = pytest.mark.skipif(not petsc_available(), reason="petsc4py/slepc4py (complex) not importable")
needs_mpirun = pytest.mark.skipif(not (petsc_available() and MPIRUN), reason="needs petsc4py and mpirun")


@pytest.fixture(autouse=True)
def _registered():
    if petsc_available() and "petsc" not in _REGISTRY:
        register_backend("petsc", PetscBackend, ("petsc4py", "slepc4py", "mpi4py"))


@given(st.integers(1, 10_000), st.integers(1, 64))
def test_row_ranges_partition_rows_in_balanced_contiguous_blocks(n, size):
    r = row_ranges(n, size)
    assert len(r) == size and r[0][0] == 0 and r[-1][1] == n
    assert all(a[1] == b[0] for a, b in itertools.pairwise(r))
    counts = [b - a for a, b in r]
    assert max(counts) - min(counts) <= 1 and counts == sorted(counts, reverse=True)


def _path(n):
    return sp.diags([-np.ones(n - 1), np.r_[1, 2 * np.ones(n - 2), 1], -np.ones(n - 1)], [-1, 0, 1], format="csr")


@needs_petsc
def test_path_graph_eigenvalues_match_the_closed_form():
    n = 800                                            # λ_j = 2 - 2 cos(πj/n), proofs/ of the path Laplacian
    res = smallest_eigenpairs(_path(n), sp.identity(n, format="csr"), k=4, solver=SolverOptions(backend="petsc"))
    assert res.converged and res.backend == "petsc" and res.residuals.max() <= 1e-10
    assert np.allclose(res.eigenvalues, 2 - 2 * np.cos(np.pi * np.arange(4) / n), rtol=0, atol=1e-12)


def _hermitian_pencil(seed, n):
    rng = np.random.default_rng(seed)
    G = sp.random(n, n, density=4 / n, random_state=rng) + 1j * sp.random(n, n, density=4 / n, random_state=rng)
    A = (G @ G.conj().T).tocsr()                      # Hermitian PSD, with a kernel when G is rank deficient
    d = rng.uniform(0.5, 2.0, n)
    M = (sp.diags(d) + 0.1 * sp.diags(np.sqrt(d[:-1] * d[1:]), 1) + 0.1 * sp.diags(np.sqrt(d[:-1] * d[1:]), -1))
    return A, M.tocsr()


@needs_petsc
@settings(max_examples=8, deadline=None)
@given(st.integers(0, 2**31), st.integers(1, 5))
def test_random_complex_hermitian_pencils_agree_with_dense_eigh(seed, k):
    A, M = _hermitian_pencil(seed, 450)
    res = smallest_eigenpairs(A, M, k=k, solver=SolverOptions(backend="petsc"))
    ref = sla.eigh(A.toarray(), M.toarray(), eigvals_only=True, subset_by_index=[0, k - 1])
    scale = abs(A).sum(axis=0).max()
    assert res.converged and np.all(res.residuals <= 1e-10)
    assert np.allclose(res.eigenvalues, ref, rtol=0, atol=1e-8 * scale)
    U = res.eigenvectors
    assert np.allclose(U.conj().T @ (M @ U), np.eye(k), atol=1e-8)


@needs_petsc
def test_factor_solves_complex_and_real_systems():
    A, M = _hermitian_pencil(3, 300)
    K = (A + M).tocsr()
    b = np.arange(300) + 1j
    x = PetscBackend().factorize(K, positive_definite=True).solve(np.column_stack([b, 2 * b]))
    assert np.allclose(K @ x, np.column_stack([b, 2 * b]), atol=1e-10 * np.linalg.norm(b))
    xr = PetscBackend().factorize(_path(50) + sp.identity(50)).solve(np.ones(50))
    assert xr.dtype == np.float64 and np.allclose((_path(50) + sp.identity(50)) @ xr, 1)


@needs_petsc
def test_singular_matrix_is_an_invalid_operator():
    with pytest.raises(InvalidOperatorError, match="singular"):
        PetscBackend().factorize(_path(200))            # the path Laplacian has the constants in its kernel


@needs_petsc
def test_indefinite_a_is_reported_not_psd():
    n = 500
    A = (_path(n) - 0.5 * sp.identity(n)).tocsr()
    with pytest.raises(InvalidOperatorError, match="not positive semidefinite"):
        smallest_eigenpairs(A, sp.identity(n, format="csr"), k=1, solver=SolverOptions(backend="petsc"))


@needs_mpirun
@pytest.mark.slow
def test_two_ranks_bunny_landau_and_mismatched_input():
    proc, _ = mpirun(2, [str(ROOT / "tests" / "mpi" / "run_checks.py")], timeout=600)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    lines = [ln for ln in proc.stdout.splitlines() if ln.startswith("[2 ranks]")]
    assert len(lines) == 5 and all(": ok " in ln for ln in lines), proc.stdout


@needs_mpirun
@pytest.mark.slow
def test_bad_input_on_one_rank_ends_all_ranks_with_one_error():
    proc, elapsed = mpirun(2, [str(ROOT / "tests" / "mpi" / "run_checks.py"), "--bad-input"], timeout=120)
    assert proc.returncode != 0 and elapsed < 60
    assert proc.stderr.count("NonFiniteError: A[7, 7] = nan is not finite") == 1, proc.stderr
    assert "bad input was not detected" not in proc.stdout


@needs_mpirun
@pytest.mark.slow
def test_mpi_command_line_writes_the_default_backends_field_once(tmp_path):
    mesh = str(ROOT / "tests" / "data" / "bunny-7k.obj")
    out = tmp_path / "field"
    proc, _ = mpirun(2, ["-m", "dhlb.linalg.backends_petsc", "field", mesh, "--n", "4", "--backend", "petsc",
                       "--no-png", "-o", str(out)], timeout=600)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.count("34 singularities") == 1           # rank 0 alone prints
    from dhlb.cli import main

    assert main(["field", mesh, "--n", "4", "--no-png", "-q", "-o", str(tmp_path / "ref")]) == 0
    got, ref = (json.loads((tmp_path / f"{b}.json").read_text()) for b in ("field", "ref"))
    assert abs(got["eigenvalue"] / ref["eigenvalue"] - 1) < 1e-9
    assert got["index_sum"] == ref["index_sum"]
    a, b = np.load(tmp_path / "field.npz"), np.load(tmp_path / "ref.npz")
    assert np.array_equal(a["singular_faces"], b["singular_faces"])
    assert np.array_equal(a["singular_index"], b["singular_index"])
    assert np.array_equal(a["face_index"], b["face_index"])


# ---------------------------------------------------------------------- dhlb.linalg.distributed (issue 31)
from dhlb.errors import InsufficientMemoryError, NonFiniteError, ShapeError  # noqa: E402
from dhlb.linalg import backends_petsc  # noqa: E402
from dhlb.linalg._checks import norm1  # noqa: E402
from dhlb.linalg.distributed import (  # noqa: E402
    RowBlock,
    check_hermitian_distributed,
    default_shift_distributed,
    gather_to_root,
    norm1_distributed,
    scatter_values,
    start_vector,
)
from dhlb.linalg.distributed_eigen import distributed_eigenpairs  # noqa: E402
from dhlb.linalg.eigen import default_shift  # noqa: E402


def _blocks(A, M):
    n = A.shape[0]
    return RowBlock.from_global(A, 0, n), RowBlock.from_global(M, 0, n)


def _grid3(m):
    """Dirichlet Laplacian of an m³ grid: λ_min = 3 (2 − 2 cos(π/(m+1)))."""
    T = sp.diags([-np.ones(m - 1), 2 * np.ones(m), -np.ones(m - 1)], [-1, 0, 1])
    Id = sp.identity(m)
    return (sp.kron(sp.kron(T, Id), Id) + sp.kron(sp.kron(Id, T), Id) + sp.kron(sp.kron(Id, Id), T)).tocsr()


@needs_petsc
def test_distributed_path_graph_matches_the_closed_form():
    n = 800
    res = distributed_eigenpairs(*_blocks(_path(n), sp.identity(n, format="csr")), 4, tol=1e-10)
    assert res.converged and res.method == "krylovschur" and res.factorizations == 1 and res.residuals.max() <= 1e-10
    assert np.allclose(res.eigenvalues, 2 - 2 * np.cos(np.pi * np.arange(4) / n), rtol=0, atol=1e-12)
    assert np.allclose(res.vectors.conj().T @ res.vectors, np.eye(4), atol=1e-10)
    assert np.all(res.vectors.T @ start_vector(0, n) > 0)        # the phase normalization
    assert res.stats["icntl_24"] == 1 and res.stats["icntl_7"] == backends_petsc.MUMPS_ORDERING


@needs_petsc
@settings(max_examples=6, deadline=None)
@given(st.integers(0, 2**31), st.integers(1, 4))
def test_distributed_random_complex_hermitian_pencils_agree_with_dense_eigh(seed, k):
    A, M = _hermitian_pencil(seed, 300)
    res = distributed_eigenpairs(*_blocks(A, M), k, tol=1e-10)
    ref = sla.eigh(A.toarray(), M.toarray(), eigvals_only=True, subset_by_index=[0, k - 1])
    assert res.converged and np.all(res.residuals <= 1e-10)
    assert np.allclose(res.eigenvalues, ref, rtol=0, atol=1e-8 * abs(A).sum(axis=0).max())
    U = res.vectors
    assert np.allclose(U.conj().T @ (M @ U), np.eye(k), atol=1e-8)


@needs_petsc
def test_lobpcg_gamg_on_a_3d_grid_matches_the_closed_form():
    m = 14
    res = distributed_eigenpairs(*_blocks(_grid3(m), sp.identity(m**3, format="csr")), 1, tol=1e-10,
                                 method="lobpcg-gamg")
    exact = 3 * (2 - 2 * np.cos(np.pi / (m + 1)))
    assert res.converged and res.method == "lobpcg-gamg" and res.factorizations == 0 and res.solves > 0
    assert abs(res.eigenvalues[0] / exact - 1) < 1e-8


@needs_petsc
def test_lobpcg_gamg_on_tet_vortex_matrices_matches_krylovschur():
    from dhlb.fem import bundle_matrices
    from dhlb.geometry import EuclideanComplex
    from dhlb.mesh import box_tet_mesh
    from dhlb.vortex import FilamentField, vortex_ring
    from dhlb.vortex.velocity import velocity_bundle

    mesh = box_tet_mesh(10, lower=-1.5, upper=1.5)
    v = FilamentField([vortex_ring(0.8, center=(0.01, 0.02, 0.03), n=48)], 2 * np.pi, core_radius=0.15)
    L = velocity_bundle(mesh.complex, mesh.points, v, 1.0)
    A, M = (sp.csr_matrix(S) for S in bundle_matrices(L, EuclideanComplex(mesh.complex, points=mesh.points)))
    B = _blocks(A, M)
    gam = distributed_eigenpairs(*B, 2, tol=1e-10, method="lobpcg-gamg")
    ks = distributed_eigenpairs(*B, 2, tol=1e-10, method="krylovschur")
    assert gam.converged and ks.converged
    assert np.allclose(gam.eigenvalues, ks.eigenvalues, rtol=1e-8, atol=0)
    assert default_shift_distributed(*B) == default_shift(A, M)


@needs_petsc
def test_auto_falls_back_to_lobpcg_gamg_when_the_factor_does_not_fit():
    from dhlb.linalg.memory import set_memory_limit

    B = _blocks(_grid3(8), sp.identity(512, format="csr"))
    assert distributed_eigenpairs(*B, 1, tol=1e-10).method == "krylovschur"
    set_memory_limit(10_000)
    try:
        res = distributed_eigenpairs(*B, 1, tol=1e-10)
    finally:
        set_memory_limit(None)
    assert res.method == "lobpcg-gamg" and "GiB per rank" in res.note and res.converged


@needs_petsc
def test_auto_takes_lobpcg_gamg_for_a_large_volume_pattern_as_select_backend_does():
    from dhlb.linalg.backends import ITERATIVE_3D
    from dhlb.linalg.distributed_eigen import _choose

    A = _grid3(22)            # 10,648 unknowns, 7 nonzeros per row: a surface-like count, factorized
    assert _choose(_blocks(A, A)[0], "auto")[0] == "krylovschur"
    A27 = (abs(A) @ abs(A)).tocsr()          # 27-point pattern: >= 10 nonzeros per row, like a tet mesh
    assert A27.shape[0] >= ITERATIVE_3D and A27.nnz >= 10 * A27.shape[0]
    method, note = _choose(_blocks(A27, A27)[0], "auto")
    assert method == "lobpcg-gamg" and "amg-lobpcg on one process" in note


@given(st.integers(0, 5000), st.lists(st.integers(0, 5000), max_size=6), st.integers(0, 2**32))
def test_start_vector_does_not_depend_on_the_split(n, cuts, seed):
    cuts = sorted({0, n, *(c for c in cuts if c <= n)})
    parts = [start_vector(a, b, seed) for a, b in itertools.pairwise(cuts)]
    whole = start_vector(0, n, seed)
    assert np.array_equal(np.concatenate(parts) if parts else np.zeros(0), whole)
    assert n < 100 or not np.array_equal(whole, start_vector(0, n, seed + 1))


def test_scatter_gather_norm1_and_shift_on_one_process():
    A, M = _hermitian_pencil(5, 200)
    B, C = _blocks(A, M)
    x = np.column_stack([np.arange(200) * (1 + 2j), np.ones(200)])
    wanted = np.array([199, 0, 7, 7, 150])
    assert np.array_equal(scatter_values(x, 0, 200, 200, wanted), x[wanted])
    assert np.array_equal(scatter_values(x[:, 0].real, 0, 200, 200, wanted), x[wanted, 0].real)
    assert np.array_equal(gather_to_root(x), x)
    assert np.isclose(norm1_distributed(B), norm1(A), rtol=1e-14)
    assert default_shift_distributed(B, C) == default_shift(A, M)
    with pytest.raises(ShapeError, match="outside"):
        scatter_values(x, 0, 200, 200, np.array([200]))


@needs_petsc
def test_distributed_bad_inputs_raise_typed_errors_naming_rank_and_row():
    n = 50
    A, M = _path(n).astype(complex).tolil(), sp.identity(n, format="csr")
    A[7, 8] = -1 + 0.5j                                          # A[8, 7] stays -1: not Hermitian
    with pytest.raises(InvalidOperatorError, match=r"A is not Hermitian: A\[7, 8\].*row 7.*MPI rank 0 of 1"):
        distributed_eigenpairs(*_blocks(A.tocsr(), M), 1, tol=1e-10)
    with pytest.raises(InvalidOperatorError, match="not Hermitian"):
        check_hermitian_distributed(RowBlock.from_global(A.tocsr(), 0, n))
    S = _path(n).tocsr()
    S.data[S.indptr[12]] = np.nan
    with pytest.raises(NonFiniteError, match=r"A\[12, 11\] = nan is not finite \[MPI rank 0 of 1\]"):
        distributed_eigenpairs(*_blocks(S, M), 1, tol=1e-10)
    B = RowBlock.from_global(_path(n), 0, n)
    short = RowBlock(B.indptr[:-1], B.indices, B.data, 0, n, n)
    with pytest.raises(ShapeError, match="len\\(indptr\\) - 1 = 49"):
        distributed_eigenpairs(short, RowBlock.from_global(M, 0, n), 1, tol=1e-10)
    with pytest.raises(ShapeError, match="tile"):
        distributed_eigenpairs(RowBlock.from_global(_path(n), 0, n - 1), RowBlock.from_global(M, 0, n - 1), 1,
                               tol=1e-10)


# ---------------------------------------------------------------------- MUMPS options and failures (defects 1, 2)
def _factor_of(ksp):
    return ksp.getPC().getFactorMatrix()


@needs_petsc
def test_mumps_options_reach_the_factor_in_the_eigen_and_factorize_paths(monkeypatch):
    monkeypatch.setattr(backends_petsc, "MUMPS_ORDERING", 2)         # AMF: not MUMPS' default (7, automatic)
    fac = PetscBackend().factorize(_path(60) + sp.identity(60))
    F = _factor_of(fac.ksp)
    assert (F.getMumpsIcntl(24), F.getMumpsIcntl(7)) == (1, 2)
    be = PetscBackend()
    n = 300
    smallest_eigenpairs(_path(n), sp.identity(n, format="csr"), k=1, solver=SolverOptions(backend=be))
    F = _factor_of(be._eps[1].getST().getKSP())
    assert (F.getMumpsIcntl(24), F.getMumpsIcntl(7)) == (1, 2)
    res = distributed_eigenpairs(*_blocks(_path(n), sp.identity(n, format="csr")), 1, tol=1e-10)
    assert (res.stats["icntl_24"], res.stats["icntl_7"], res.stats["ordering_used"]) == (1, 2, 2)


@needs_petsc
def test_singular_shifted_matrix_says_singular_in_the_eigen_paths():
    n = 200
    with pytest.raises(InvalidOperatorError, match="singular: MUMPS found 1 null pivot"):
        distributed_eigenpairs(*_blocks(_path(n), sp.identity(n, format="csr")), 1, tol=1e-10, shift=0.0)
    with pytest.raises(InvalidOperatorError, match="singular: MUMPS found 1 null pivot"):
        PetscBackend().eigensolve(_path(n), sp.identity(n, format="csr"), np.ones((n, 1)), shift=0.0, tol=1e-10,
                                  maxiter=100)


@needs_petsc
def test_a_mumps_workspace_failure_names_the_petsc_code_and_not_singularity(monkeypatch):
    monkeypatch.setitem(backends_petsc.MUMPS_ICNTL, 14, -90)       # 10 % of the estimated workspace: INFOG(1) = -9
    K = _grid3(20)
    for run in (lambda: distributed_eigenpairs(*_blocks(K, sp.identity(8000, format="csr")), 1, tol=1e-10,
                                               method="krylovschur"),
                lambda: PetscBackend().factorize(K)):
        with pytest.raises(InsufficientMemoryError) as info:
            run()
        msg = str(info.value)
        assert "PETSc error code 76" in msg and "workspace is too small" in msg and "INFOG(1) = -9" in msg, msg
        assert "singular" not in msg


@needs_mpirun
@pytest.mark.slow
def test_distributed_results_do_not_depend_on_the_number_of_ranks(tmp_path):
    script = str(ROOT / "tests" / "mpi" / "linalg_checks.py")
    out = {}
    for size in (1, 2, 3):
        proc, _ = mpirun(size, [script, str(tmp_path / f"p{size}.npz")], timeout=600)
        assert proc.returncode == 0, proc.stdout + proc.stderr
        lines = [ln for ln in proc.stdout.splitlines() if ln.startswith(f"[{size} ranks]")]
        assert len(lines) == 3 and all(ln.endswith(": ok") for ln in lines), proc.stdout
        out[size] = np.load(tmp_path / f"p{size}.npz")
    ref = out[1]
    for size in (2, 3):
        got = out[size]
        assert np.all(np.abs(got["eigenvalues"] / ref["eigenvalues"] - 1) < 1e-12)
        assert np.abs(got["vectors"] - ref["vectors"]).max() < 1e-10
        assert got["shift"] == ref["shift"]
        assert abs(got["lobpcg"][0] / ref["lobpcg"][0] - 1) < 1e-8


@needs_mpirun
@pytest.mark.slow
@pytest.mark.parametrize("size", [1, 2, 3])
def test_a_nan_on_one_rank_raises_the_same_error_everywhere_with_one_line(tmp_path, size):
    proc, elapsed = mpirun(size, [str(ROOT / "tests" / "mpi" / "linalg_checks.py"), str(tmp_path / "x.npz"),
                                     "--nan"], timeout=120)
    assert proc.returncode != 0 and elapsed < 30, (elapsed, proc.stderr)
    assert proc.stderr.count("NonFiniteError: A[") == 1, proc.stderr
    assert f"is not finite [MPI rank {size - 1} of {size}]" in proc.stderr
    assert not (tmp_path / "x.npz").exists()


@needs_petsc
@pytest.mark.parametrize("n", [1, 2, 3, 5])
def test_tiny_matrices_factorize_with_the_default_ordering(n):
    # PORD forced (ICNTL(7) = 4) ends the process on 2 or 3 rows; the automatic choice does not
    K = (sp.identity(n) * 3 - sp.eye(n, k=1) - sp.eye(n, k=-1)).tocsr()
    x = PetscBackend().factorize(K).solve(np.ones(n))
    assert np.allclose(K @ x, 1)


@needs_petsc
def test_distributed_solves_leave_no_options_behind():
    from petsc4py import PETSc

    n = 300
    blocks = _blocks(_path(n) + sp.identity(n), sp.identity(n, format="csr"))
    distributed_eigenpairs(*blocks, 1, tol=1e-10)
    before = len(PETSc.Options().getAll())
    for _ in range(3):
        distributed_eigenpairs(*blocks, 1, tol=1e-10)
    assert len(PETSc.Options().getAll()) == before
