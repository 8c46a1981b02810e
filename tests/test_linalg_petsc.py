"""The ``petsc`` backend (PETSc/SLEPc, complex scalars): skipped where petsc4py/slepc4py do not import.

In-process tests run on one MPI rank; the ``mpirun -n 2`` tests launch tests/mpi/run_checks.py
and the MPI command line (``python -m dhlb.cli.mpi``) when ``mpirun`` is on the path.
Set up the environment with ``.ci/mpi-setup.sh`` (docs/mpi.md) and run this file with its python.
"""

import itertools
import json
import os
import shutil
import subprocess
import sys
import time
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

ROOT = Path(__file__).resolve().parents[1]
needs_petsc = pytest.mark.skipif(not petsc_available(), reason="petsc4py/slepc4py (complex) not importable")
MPIRUN = shutil.which("mpirun")
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


def _mpirun(args, timeout):
    cmd = [MPIRUN, "-n", "2"] + (["--allow-run-as-root"] if os.geteuid() == 0 else []) + [sys.executable] + args
    env = {**os.environ, "OMPI_MCA_rmaps_base_oversubscribe": "1", "OPENBLAS_NUM_THREADS": "1"}
    t = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env, cwd=ROOT)
    return proc, time.perf_counter() - t


@needs_mpirun
@pytest.mark.slow
def test_two_ranks_bunny_landau_and_mismatched_input():
    proc, _ = _mpirun([str(ROOT / "tests" / "mpi" / "run_checks.py")], timeout=600)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    lines = [ln for ln in proc.stdout.splitlines() if ln.startswith("[2 ranks]")]
    assert len(lines) == 3 and all(": ok " in ln for ln in lines), proc.stdout


@needs_mpirun
@pytest.mark.slow
def test_bad_input_on_one_rank_ends_all_ranks_with_one_error():
    proc, elapsed = _mpirun([str(ROOT / "tests" / "mpi" / "run_checks.py"), "--bad-input"], timeout=120)
    assert proc.returncode != 0 and elapsed < 60
    assert proc.stderr.count("NonFiniteError: A[7, 7] = nan is not finite") == 1, proc.stderr
    assert "bad input was not detected" not in proc.stdout


@needs_mpirun
@pytest.mark.slow
def test_mpi_command_line_writes_the_default_backends_field_once(tmp_path):
    mesh = str(ROOT / "tests" / "data" / "bunny-7k.obj")
    out = tmp_path / "field"
    proc, _ = _mpirun(["-m", "dhlb.linalg.backends_petsc", "field", mesh, "--n", "4", "--backend", "petsc",
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
