"""MPI checks of the ``petsc`` backend; run ``mpirun -n P python tests/mpi/run_checks.py [--bad-input]``.

Every rank runs every check; rank 0 prints one line per check and the script exits 1 if any
check failed on any rank.  ``--bad-input``: rank 1 (the last rank) passes a matrix with a NaN, the
others a valid one; the run must end on every rank with one clear error (exit code != 0), not hang.
"""

import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from mpi4py import MPI  # noqa: E402

from dhlb.errors import InvalidOperatorError  # noqa: E402
from dhlb.fem import bundle_matrices, smallest_eigenpairs  # noqa: E402
from dhlb.fields import direction_field  # noqa: E402
from dhlb.io import read_surface  # noqa: E402
from dhlb.linalg import SolverOptions  # noqa: E402
from dhlb.linalg.backends import _REGISTRY, register_backend  # noqa: E402
from dhlb.linalg.backends_petsc import PetscBackend  # noqa: E402
from tests.fem_fixtures import flat_torus_landau  # noqa: E402

if "petsc" not in _REGISTRY:  # until the registry lists it
    register_backend("petsc", PetscBackend, ("petsc4py", "slepc4py", "mpi4py"))

COMM = MPI.COMM_WORLD
RANK, SIZE = COMM.rank, COMM.size


def check_bunny_field():
    """``direction_field(solver="petsc")`` under mpirun is the distributed field (issue 42, point 10): all ranks
    compute it together and every rank gets it; before, every rank assembled and held the whole problem."""
    V, F = read_surface(ROOT / "tests" / "data" / "bunny-7k.obj")
    got = direction_field(V, F, n=4, solver=SolverOptions(backend="petsc"))   # on every rank, as on one process
    ref = direction_field(V, F, n=4)
    rel = abs(got.eigenvalue / ref.eigenvalue - 1)
    assert rel <= 1e-9, f"eigenvalue {got.eigenvalue!r} vs {ref.eigenvalue!r}: relative {rel:.2e} > 1e-9"
    a, b = ref.singularities, got.singularities
    assert np.array_equal(a.faces, b.faces) and np.array_equal(a.index, b.index), "singularities differ"
    if SIZE > 1:
        par = got.solver.get("parallel") or {}
        assert par.get("ranks") == SIZE, f"not distributed: solver {got.solver}"
        assert max(par["local_vertices"]) < ref.mesh.n_vertices, "a rank held the whole mesh"
    return f"eigenvalue rel. diff {rel:.1e}, {len(b.faces)} singularities identical, distributed over {SIZE} ranks"


def check_aligned_field_is_replicated_and_says_so():
    """An aligned field has no distributed form: it runs on every rank, and rank 0 warns that it is not distributed."""
    import warnings

    from dhlb.errors import DhlbWarning

    V, F = read_surface(ROOT / "tests" / "data" / "bunny-7k.obj")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        got = direction_field(V, F, n=4, align="curvature", solver=SolverOptions(backend="petsc"))
    said = [str(w.message) for w in caught
            if issubclass(w.category, DhlbWarning) and "not distributed" in str(w.message)]
    assert len(said) == (1 if RANK == 0 and SIZE > 1 else 0), said
    ref = direction_field(V, F, n=4, align="curvature")
    assert np.array_equal(got.singularities.faces, ref.singularities.faces), "aligned singularities differ"
    return f"{len(got.singularities.faces)} singularities on every rank; rank 0 said: {said[0][:60] if said else ''}..."


def check_vortex_filaments_distribute():
    """``vortex_filaments(solver="petsc")`` under mpirun is the distributed pipeline (every rank gets the result)."""
    from dhlb.cli.vortex import demo_velocity
    from dhlb.mesh import box_tet_mesh
    from dhlb.vortex import vortex_filaments

    mesh = box_tet_mesh(12, lower=-1.0, upper=1.0)
    field, _ = demo_velocity("linked-rings", mesh.points)
    res = vortex_filaments(mesh, None, field, 1.0, solver="petsc")   # on every rank, as on one process
    assert len(res.filaments) == 2 and res.linking_numbers.tolist() == [[0, 1], [1, 0]], res.linking_numbers
    if SIZE > 1:
        solver = res.statistics["solver"]
        assert (solver.get("parallel") or {}).get("ranks") == SIZE, f"not distributed: {solver}"
    return f"2 linked filaments, distributed over {SIZE} ranks"


def check_landau_3torus():
    L, geo, B = flat_torus_landau(3, 12, 2)
    A, M = bundle_matrices(L, geo)
    res = smallest_eigenpairs(A, M, k=3, solver=SolverOptions(tol=1e-10, backend="petsc"))
    ref = smallest_eigenpairs(A, M, k=3, solver=SolverOptions(tol=1e-10))
    ev = res.eigenvalues / B
    assert res.converged and res.backend == "petsc"
    assert np.ptp(ev[:2]) < 1e-8, f"lowest level not 2-fold: {ev}"
    # discretization error at m = 12, d = 2: about 2 × 0.0125 (tests/test_fem_landau.py), so 1 < ev[0] < 1.05
    assert 1 < ev[0] < 1.05 and 2.9 < ev[2] < 3.2, f"levels {ev} (want 1, 1, ~3)"
    diff = np.max(np.abs(res.eigenvalues / ref.eigenvalues - 1))
    assert diff < 1e-9, f"petsc {res.eigenvalues} vs default {ref.eigenvalues}"
    return f"levels/B = {np.round(ev, 6).tolist()}, rel. diff to default {diff:.1e}"


def check_mismatched_input_raises_everywhere():
    # every rank passes a valid pencil, but the last rank's differs: all ranks must raise the same error
    n = 600
    d = np.r_[1, 2 * np.ones(n - 2), 1] + (1e-3 if RANK == SIZE - 1 and SIZE > 1 else 0.0)
    import scipy.sparse as sp

    A = sp.diags([-np.ones(n - 1), d, -np.ones(n - 1)], [-1, 0, 1], format="csr")
    if SIZE == 1:
        return "skipped (one rank)"
    try:
        smallest_eigenpairs(A, sp.identity(n, format="csr"), k=2, solver=SolverOptions(backend="petsc"))
    except InvalidOperatorError as err:
        msg = str(err)
    else:
        raise AssertionError("no error although the ranks passed different matrices")
    msgs = COMM.allgather(msg)
    assert len(set(msgs)) == 1, f"ranks report different errors: {msgs}"
    assert f"MPI ranks [{SIZE - 1}]" in msg, msg
    return "every rank raised: " + msg[:70] + "..."


def bad_input():
    import scipy.sparse as sp

    n = 600
    A = sp.diags([-np.ones(n - 1), np.r_[1, 2 * np.ones(n - 2), 1], -np.ones(n - 1)], [-1, 0, 1], format="csr")
    if RANK == SIZE - 1:
        A = A.tolil()
        A[7, 7] = np.nan
    smallest_eigenpairs(A, sp.identity(n, format="csr"), k=2, solver=SolverOptions(backend="petsc"))
    if RANK == 0:
        print("bad input was not detected", flush=True)
    return 0


def main():
    if "--bad-input" in sys.argv:
        return bad_input()
    failed = 0
    for check in (check_bunny_field, check_aligned_field_is_replicated_and_says_so, check_vortex_filaments_distribute,
                  check_landau_3torus, check_mismatched_input_raises_everywhere):
        t = time.perf_counter()
        try:
            msg, ok = check(), True
        except AssertionError as err:
            msg, ok = f"FAILED: {err}", False
        oks = COMM.allgather(ok)
        failed += not all(oks)
        if RANK == 0:
            print(f"[{SIZE} ranks] {check.__name__}: {'ok' if all(oks) else 'FAILED on ranks '}"
                  f"{'' if all(oks) else [r for r, o in enumerate(oks) if not o]} "
                  f"({time.perf_counter() - t:.2f} s) {msg}", flush=True)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
