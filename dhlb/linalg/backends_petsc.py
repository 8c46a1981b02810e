"""Distributed backend ``petsc``: SLEPc eigensolvers and PETSc solves, complex scalars, under MPI.

Run a script (or ``dhlb``) under ``mpirun -n P`` with ``backend="petsc"``; every rank runs the
same Python code, and each call into this backend is *collective* (all ranks must make it, with
the same matrices).  Needs petsc4py and slepc4py built with complex scalars and mpi4py (Debian:
``python3-petsc4py-complex python3-slepc4py-complex python3-mpi4py``; see ``docs/mpi.md``).

Distribution
    The input matrices are scipy matrices held by every rank (every rank assembled them, or read
    them).  Each rank copies the rows ``row_ranges(n, P)[rank]`` into a distributed PETSc ``AIJ``
    matrix (contiguous, balanced blocks, PETSc's own default layout), so the PETSc solvers see a
    row-partitioned matrix; results (eigenvectors, solutions) are gathered to every rank, so the
    Python API is unchanged.  Before any collective work the ranks compare a fingerprint of their
    inputs (shape, number of nonzeros, a hash of pattern and values); if they differ, or a rank
    failed to prepare its part, every rank raises the same
    :class:`~dhlb.errors.InvalidOperatorError` naming the ranks (no rank is left waiting).
    An exception that escapes on one rank only (e.g. raised while validating input before this
    backend is reached) would leave the others waiting in a collective call: with more than one
    rank, importing this module installs :func:`install_abort_hook`, which prints the error once
    and calls ``MPI_Abort``, ending all ranks.  Import it (or register the backend) before any
    per-rank work, or run the script as ``python -m mpi4py script.py``, which does the same.
Eigenpairs (``eigensolve``)
    SLEPc ``EPS``, Krylov–Schur, generalized Hermitian problem (``GHEP``) in shift-and-invert
    mode at ``−ε`` (``ε`` the Gershgorin shift of :func:`dhlb.linalg.eigen.default_shift`), i.e.
    on ``(A + εM)⁻¹ M``, whose largest eigenvalues are the smallest of ``A u = λ M u``; the shifted
    matrix is factorized by MUMPS (distributed LU; SuperLU_dist if MUMPS is missing; PETSc's own
    LU on one rank).  SLEPc's convergence test is set to ``EPS_CONV_NORM``,
    ``‖A x − λ M x‖ / ((‖A‖ + |λ| ‖M‖) ‖x‖)``, the normwise backward error ``η`` of
    :func:`~dhlb.linalg.smallest_eigenpairs`, which does the final Rayleigh–Ritz and the
    backward-error test on the gathered vectors (and calls again, from them, if one misses it).
Linear solves (``factorize``)
    A ``KSP`` of type ``preonly`` with an LU factorization (same solver choice); ``solve(B)``
    distributes ``B`` by rows and gathers ``X``.  A singular matrix (MUMPS reports a zero pivot)
    raises :class:`~dhlb.errors.InvalidOperatorError`.

Examples
--------
>>> row_ranges(10, 3)
[(0, 4), (4, 7), (7, 10)]
>>> import numpy as np, scipy.sparse as sp
>>> K = sp.csr_matrix(np.array([[2.0, -1.0], [-1.0, 2.0]]))
>>> x = PetscBackend().factorize(K).solve(np.array([1.0, 0.0])) if petsc_available() else np.array([2, 1]) / 3
>>> x.real.round(6).tolist()
[0.666667, 0.333333]
"""

from __future__ import annotations

import hashlib
import importlib.util
import sys
import time

import numpy as np
import scipy.sparse as sp

from dhlb.errors import DhlbError, InsufficientMemoryError, InvalidOperatorError, ShapeError

__all__ = ["MUMPS_ICNTL", "MUMPS_ORDERING", "PetscBackend", "comm_rank_size", "install_abort_hook", "petsc_available",
           "row_ranges"]

_SOLVERS = ("mumps", "superlu_dist", "petsc")


# ---------------------------------------------------------------------- availability, layout
def petsc_available() -> bool:
    """Whether petsc4py, slepc4py and mpi4py import and PETSc uses complex scalars.

    Examples
    --------
    >>> isinstance(petsc_available(), bool)
    True
    """
    for mod in ("petsc4py", "slepc4py", "mpi4py"):
        try:
            if importlib.util.find_spec(mod) is None:
                return False
        except (ImportError, ValueError):
            return False
    try:
        from petsc4py import PETSc
    except ImportError:  # pragma: no cover - a broken installation
        return False
    return np.dtype(PETSc.ScalarType).kind == "c"


def comm_rank_size() -> tuple[int, int]:
    """``(rank, size)`` of ``MPI_COMM_WORLD``; ``(0, 1)`` without mpi4py/PETSc.

    Examples
    --------
    >>> rank, size = comm_rank_size()
    >>> 0 <= rank < size
    True
    """
    if not petsc_available():
        return 0, 1
    from petsc4py import PETSc

    return PETSc.COMM_WORLD.rank, PETSc.COMM_WORLD.size


def row_ranges(n: int, size: int) -> list[tuple[int, int]]:
    """Balanced contiguous row blocks ``[(start, stop), ...]`` of ``n`` rows over ``size`` ranks.

    The first ``n % size`` ranks get one row more: PETSc's ``PETSC_DECIDE`` layout.

    Examples
    --------
    >>> row_ranges(5, 2)
    [(0, 3), (3, 5)]
    """
    counts = np.full(size, n // size) + (np.arange(size) < n % size)
    stops = np.cumsum(counts)
    return [(int(b - c), int(b)) for b, c in zip(stops, counts)]


_hook_installed = False


def install_abort_hook() -> None:
    """Make an uncaught exception on any MPI rank print once and end every rank (``MPI_Abort``).

    Without it, a rank that fails outside a collective call leaves the others waiting forever.
    Installed by :class:`PetscBackend` when more than one rank runs; harmless on one rank.

    Examples
    --------
    >>> install_abort_hook()
    """
    global _hook_installed
    if _hook_installed or comm_rank_size()[1] == 1:
        return
    previous = sys.excepthook

    def hook(kind, value, tb):
        from mpi4py import MPI

        rank = MPI.COMM_WORLD.rank
        if getattr(value, "mpi_collective", False) and rank != 0:
            time.sleep(10)  # raised on every rank alike: rank 0 prints it once and ends the run
        elif isinstance(value, DhlbError):
            sys.stderr.write(f"dhlb (MPI rank {rank}): {kind.__name__}: {value}\n")
        else:
            previous(kind, value, tb)
        sys.stderr.flush()
        MPI.COMM_WORLD.Abort(1)

    sys.excepthook = hook
    _hook_installed = True


# ---------------------------------------------------------------------- collective helpers
def _world():
    from petsc4py import PETSc

    return PETSc.COMM_WORLD


def _fingerprint(*mats) -> str:
    h = hashlib.blake2b(digest_size=12)
    for S in mats:
        h.update(repr((S.shape, S.nnz, S.dtype.str)).encode())
        for arr in (S.indptr, S.indices, S.data):
            h.update(np.ascontiguousarray(arr).view(np.uint8))
    return h.hexdigest()


def _agree(what: str, prepare):
    """Run ``prepare()`` on every rank; raise the same error on all ranks if any failed or inputs differ.

    ``prepare`` returns ``(value, fingerprint)``; the fingerprints must agree across ranks.
    """
    comm = _world()
    try:
        value, fp = prepare()
        status = ("ok", fp)
    except DhlbError as err:
        value, status = None, ("error", f"{type(err).__name__}: {err}")
    if comm.size == 1:
        if status[0] == "error":
            raise InvalidOperatorError(f"{what}: {status[1]}")
        return value
    statuses = comm.tompi4py().allgather(status)
    failed = [(r, msg) for r, (kind, msg) in enumerate(statuses) if kind == "error"]
    if failed:
        r, msg = failed[0]
        raise InvalidOperatorError(f"{what}: MPI rank {r} of {comm.size} failed ({msg}); every rank stops")
    fps = [fp for _, fp in statuses]
    if len(set(fps)) > 1:
        bad = [r for r, fp in enumerate(fps) if fp != fps[0]]
        raise InvalidOperatorError(f"{what}: MPI ranks {bad} were given different matrices than rank 0; every rank "
                                   "must call the petsc backend with the same A and M (build them the same way on "
                                   "all ranks)")
    return value


def _check_square(S, name):
    S = sp.csr_matrix(S)
    if S.ndim != 2 or S.shape[0] != S.shape[1] or S.shape[0] == 0:
        raise ShapeError(f"{name} must be a non-empty square matrix, got shape {S.shape}")
    if not np.all(np.isfinite(S.data)):
        raise InvalidOperatorError(f"{name} contains NaN or inf")
    S = S.astype(np.complex128)
    S.sum_duplicates()
    S.sort_indices()
    return S


def _aij(indptr, indices, data, n: int):
    """A distributed ``n × n`` PETSc AIJ matrix whose rows on this rank are the CSR ``(indptr, indices, data)``.

    ``indices`` are global column ids; the ranks' rows follow each other in rank order.
    """
    from petsc4py import PETSc

    nloc = len(indptr) - 1
    csr = (np.asarray(indptr, dtype=PETSc.IntType), np.asarray(indices, dtype=PETSc.IntType),
           np.asarray(data, dtype=PETSc.ScalarType))
    A = PETSc.Mat().createAIJ(size=((nloc, n), (nloc, n)), csr=csr, comm=_world())
    A.assemble()
    return A


def _petsc_mat(S: sp.csr_matrix):
    """The rows of this rank of the (globally held) CSR ``S`` as a distributed PETSc AIJ matrix."""
    comm = _world()
    n = S.shape[0]
    r0, r1 = row_ranges(n, comm.size)[comm.rank]
    ip = S.indptr[r0:r1 + 1]
    return _aij(ip - ip[0], S.indices[ip[0]:ip[-1]], S.data[ip[0]:ip[-1]], n)


def _vec_from(A, x):
    """A PETSc vector of ``A``'s row layout holding this rank's rows of the global array ``x``."""
    v = A.createVecRight()
    r0, r1 = v.getOwnershipRange()
    v.setArray(np.asarray(x[r0:r1], dtype=np.complex128))
    return v


def _gather(v) -> np.ndarray:
    """The global array of a distributed PETSc vector, on every rank."""
    local = np.array(v.getArray(readonly=True), dtype=np.complex128)
    comm = _world()
    if comm.size == 1:
        return local
    return np.concatenate(comm.tompi4py().allgather(local))


MUMPS_ORDERING = 7
"""MUMPS' ``ICNTL(7)``, the sequential ordering of the analysis (0 AMD, 2 AMF, 3 SCOTCH, 4 PORD, 5 METIS, 6 QAMD,
7 automatic); set on every factorization (:func:`_direct_pc`) and read back in the tests.

Automatic, chosen by measurement (``benchmarks/bench_mumps_ordering.py``, docs/mpi.md): on every matrix
measured it picks PORD (``INFOG(7) = 4``), which against AMD has 39 % fewer factor entries on the
1.31M-face icosphere field (8.6e7 against 1.42e8) and on a 384k-tet box, and factorizes 2–5× faster.
PORD itself (4) is not forced: on a matrix of two or three rows it stops the process ("no valid number of
stages in multisector"). Debian's MUMPS has neither METIS nor SCOTCH (3 and 5 silently give PORD); where
they exist, automatic may pick them."""

MUMPS_ICNTL: dict = {}
"""Extra MUMPS ``ICNTL`` settings ``{i: value}`` for every factorization (tuning, and the tests' forced failures)."""

_MUMPS_FAILURES = {
    -8: "MUMPS' integer workspace is too small (raise ICNTL(14))",
    -9: "MUMPS' workspace is too small (raise ICNTL(14))",
    -10: "numerically singular",
    -13: "a memory allocation failed inside MUMPS (out of memory)",
    -19: "the memory limit ICNTL(23) of MUMPS is too small",
}
_MUMPS_MEMORY = (-8, -9, -13, -19)


def _direct_pc(ksp) -> str:
    """Set ``ksp`` to ``preonly`` + LU by the first available distributed direct solver; returns its name.

    The MUMPS options (null-pivot detection ``ICNTL(24) = 1``, the ordering :data:`MUMPS_ORDERING`,
    :data:`MUMPS_ICNTL`) go under the options prefix that ``ksp`` itself reads (for an eigensolver's
    spectral transformation that is the ``EPS`` prefix + ``st_``), so the factor sees them.
    """
    from petsc4py import PETSc

    ksp.setType("preonly")
    pc = ksp.getPC()
    pc.setType("lu")
    size = _world().size
    for solver in _SOLVERS:
        if (solver == "petsc" and size > 1) or (solver != "petsc" and not PETSc.Sys.hasExternalPackage(solver)):
            continue
        pc.setFactorSolverType(solver)
        if solver == "mumps":
            opts = PETSc.Options(ksp.getOptionsPrefix() or "")
            for i, value in {24: 1, 7: MUMPS_ORDERING, **MUMPS_ICNTL}.items():
                opts.setValue(f"mat_mumps_icntl_{i}", int(value))
        return solver
    raise InvalidOperatorError("PETSc has no direct solver for a distributed matrix (neither MUMPS nor "
                               "SuperLU_dist); rebuild PETSc with --download-mumps or run on one rank")


def _forget_options(prefix: str) -> None:
    """Delete the options :func:`_direct_pc` set under ``prefix`` (once the factor is gone).

    So PETSc's options database does not grow by a few entries with every solve of a long-running program.
    """
    from petsc4py import PETSc

    opts = PETSc.Options(prefix)
    for i in {24: 1, 7: MUMPS_ORDERING, **MUMPS_ICNTL}:
        opts.delValue(f"mat_mumps_icntl_{i}")


def _mumps(pc):
    """The MUMPS factor matrix of ``pc``, or ``None`` (another solver, or not set up)."""
    from petsc4py import PETSc

    try:
        F = pc.getFactorMatrix()
        F.getMumpsInfog(1)
    except (PETSc.Error, AttributeError):
        return None
    return F


def _null_pivots(pc) -> int:
    """The null pivots MUMPS found (``INFOG(28)``, with ``ICNTL(24) = 1``); 0 for other solvers."""
    F = _mumps(pc)
    return 0 if F is None else int(F.getMumpsInfog(28))


def _petsc_failure(err, pc, what: str, singular_hint: str = "") -> DhlbError:
    """The typed error for a PETSc failure while factorizing or solving with ``pc``.

    Names PETSc's error code and message; it says "singular" only when MUMPS reports it
    (``INFOG(1) = -10``), and its workspace and memory failures raise
    :class:`~dhlb.errors.InsufficientMemoryError`.
    """
    lines = [ln.split("] ", 1)[-1].strip() for ln in str(err).strip().splitlines() if ln.strip()]
    petsc = f"PETSc error code {getattr(err, 'ierr', '?')}" + (f": {lines[-1]}" if len(lines) > 1 else "")
    F = _mumps(pc)
    code = 0 if F is None else int(F.getMumpsInfog(1))
    if code == -10:
        return InvalidOperatorError(f"{what} is numerically singular (MUMPS INFOG(1) = -10; {petsc})"
                                    + (f"; {singular_hint}" if singular_hint else ""))
    if code < 0:
        words = _MUMPS_FAILURES.get(code, "MUMPS failed")
        msg = (f"{what}: {words} (MUMPS INFOG(1) = {code}, INFOG(2) = {int(F.getMumpsInfog(2))}; {petsc})")
        return InsufficientMemoryError(msg) if code in _MUMPS_MEMORY else InvalidOperatorError(msg)
    return InvalidOperatorError(f"{what}: PETSc failed ({petsc})")


def _raise_if_failed(ksp, what):
    from petsc4py import PETSc

    reason = ksp.getConvergedReason()
    if reason < 0:
        name = {v: k for k, v in vars(PETSc.KSP.ConvergedReason).items() if isinstance(v, int)}.get(reason, reason)
        raise InvalidOperatorError(f"{what}: the PETSc solve failed ({name})")


def _factor_stats(ksp, solver) -> dict:
    """Size of the factor and flops of the factorization as reported by MUMPS (empty for other solvers).

    Includes ``ICNTL(7)`` and ``ICNTL(24)`` read back from the factor and the ordering MUMPS used
    (``INFOG(7)``).
    """
    F = _mumps(ksp.getPC()) if solver == "mumps" else None
    if F is None:
        return {"solver": solver}
    entries = F.getMumpsInfog(29)  # negative: millions of entries
    return {"solver": solver, "factor_entries": float(entries if entries >= 0 else -entries * 1e6),
            "factor_flops": float(F.getMumpsRinfog(3)),
            "peak_mb_max_rank": float(F.getMumpsInfog(21)), "peak_mb_total": float(F.getMumpsInfog(22)),
            "icntl_7": int(F.getMumpsIcntl(7)), "icntl_24": int(F.getMumpsIcntl(24)),
            "ordering_used": int(F.getMumpsInfog(7))}


# ---------------------------------------------------------------------- factor
class _PetscFactor:
    """``solve(B)`` with an LU factorization of a distributed matrix (MUMPS); collective."""

    name = "petsc"

    def __init__(self, K: sp.csr_matrix, prefix: str):
        from petsc4py import PETSc

        self.n, self.real = K.shape[0], not np.any(K.data.imag)
        self.K = _petsc_mat(K)
        self.ksp = PETSc.KSP().create(comm=_world())
        self.ksp.setOptionsPrefix(prefix)
        self.ksp.setOperators(self.K)
        self.solver = _direct_pc(self.ksp)
        self.name = f"petsc-{self.solver}"
        self.ksp.setFromOptions()
        self.ksp.setErrorIfNotConverged(True)  # a failed factorization raises here, with MUMPS' INFOG(1)
        try:
            self.ksp.setUp()
        except PETSc.Error as err:
            raise _petsc_failure(err, self.ksp.getPC(), "the matrix to factorize") from err
        self.ksp.setErrorIfNotConverged(False)
        self._x = self.K.createVecLeft()
        self._probe()

    def _probe(self):
        # MUMPS reports a failed factorization through the PC on the first solve, so solve once now;
        # with null-pivot detection (ICNTL(24) = 1) it counts the null pivots in INFOG(28)
        b = self.K.createVecRight()
        b.set(1.0)
        self.ksp.solve(b, self._x)
        _raise_if_failed(self.ksp, "factorize")
        if null := _null_pivots(self.ksp.getPC()):
            raise InvalidOperatorError(f"the matrix to factorize is singular (MUMPS found {null} null pivot(s))")
        if not np.all(np.isfinite(self._x.getArray(readonly=True))):
            raise InvalidOperatorError("the matrix to factorize is singular (the factorization produced inf/NaN)")

    def _solve1(self, b):
        bv = _vec_from(self.K, b)
        self.ksp.solve(bv, self._x)
        _raise_if_failed(self.ksp, "solve")
        return _gather(self._x)

    def solve(self, B):
        """Solve ``K X = B`` for ``B`` of shape ``(n,)`` or ``(n, r)`` (collective; ``X`` on every rank)."""
        B = np.asarray(B)
        if B.shape[:1] != (self.n,) or B.ndim > 2:
            raise ShapeError(f"B must have shape ({self.n},) or ({self.n}, r), got {B.shape}")
        X = self._solve1(B) if B.ndim == 1 else np.column_stack([self._solve1(B[:, j]) for j in range(B.shape[1])])
        return X.real if self.real and not np.iscomplexobj(B) else X


# ---------------------------------------------------------------------- backend
class PetscBackend:
    """SLEPc Krylov–Schur in shift-and-invert mode (MUMPS) and PETSc KSP solves, under MPI.

    See the module docstring.  Every method is collective over ``MPI_COMM_WORLD``.

    Examples
    --------
    >>> import numpy as np, scipy.sparse as sp
    >>> from dhlb.linalg import SolverOptions, smallest_eigenpairs
    >>> n = 500
    >>> A = sp.diags([-np.ones(n - 1), np.r_[1, 2 * np.ones(n - 2), 1], -np.ones(n - 1)], [-1, 0, 1])
    >>> be = PetscBackend() if petsc_available() else None            # None: the default backend
    >>> lam = smallest_eigenpairs(A, sp.identity(n), k=2, solver=SolverOptions(backend=be)).eigenvalues
    >>> np.allclose(lam, 2 - 2 * np.cos(np.pi * np.arange(2) / n), atol=1e-12)
    True
    """

    name = "petsc"
    method = "slepc-krylovschur"

    def __init__(self):
        if not petsc_available():
            raise InvalidOperatorError("the petsc backend needs petsc4py and slepc4py with complex scalars and "
                                       "mpi4py (see docs/mpi.md)")
        install_abort_hook()
        self._eps = None
        self._count = 0
        self.stats: dict = {}

    def _prefix(self):
        self._count += 1
        return f"dhlb{id(self) % 100000}_{self._count}_"

    def factorize(self, K, *, positive_definite: bool = False):
        """A distributed LU factorization of ``K`` (``solve(B)``); collective.

        ``positive_definite`` is accepted for the interface; MUMPS' LU does not report the
        inertia of a complex Hermitian matrix, so definiteness is not checked here (the
        eigensolver checks it through the eigenvalues it finds).
        """
        K = _agree("petsc factorize", lambda: (lambda S: (S, _fingerprint(S)))(_check_square(K, "K")))
        return _PetscFactor(K, self._prefix())

    def _setup_eps(self, A, M, shift, ncv):
        from slepc4py import SLEPc

        key = (_fingerprint(A, M), shift, ncv)
        if self._eps is not None and self._eps[0] == key:
            return self._eps[1]
        prefix = self._prefix()
        Ap, Mp = _petsc_mat(A), _petsc_mat(M)
        E = SLEPc.EPS().create(comm=_world())
        E.setOptionsPrefix(prefix)
        E.setOperators(Ap, Mp)
        E.setProblemType(SLEPc.EPS.ProblemType.GHEP)
        E.setType(SLEPc.EPS.Type.KRYLOVSCHUR)
        E.setWhichEigenpairs(SLEPc.EPS.Which.TARGET_REAL)
        E.setTarget(-shift)
        E.setConvergenceTest(SLEPc.EPS.Conv.NORM)
        st = E.getST()
        st.setType(SLEPc.ST.Type.SINVERT)
        self.solver = _direct_pc(st.getKSP())
        E.setFromOptions()
        self._eps = (key, E, Ap, Mp)
        return E

    def eigensolve(self, A, M, X, *, shift: float, tol: float, maxiter: int):
        """Improve the block ``X`` towards the lowest eigenvectors of ``A u = λ M u``; ``(X, iterations)``.

        ``shift`` is ``ε > 0``: the factorized matrix is ``A + εM``.  Collective; the returned
        block (the converged Ritz vectors, completed by columns of ``X``) is on every rank.
        """
        from petsc4py import PETSc

        def prepare():
            Ac, Mc = _check_square(A, "A"), _check_square(M, "M")
            Xa = np.asarray(X)
            if Xa.ndim != 2 or Xa.shape[0] != Ac.shape[0] or Mc.shape != Ac.shape:
                raise ShapeError(f"A {Ac.shape}, M {Mc.shape} and X {Xa.shape} do not match")
            return (Ac, Mc, Xa), _fingerprint(Ac, Mc)

        Ac, Mc, Xa = _agree("petsc eigensolve", prepare)
        n, p = Xa.shape
        ncv = min(n, max(2 * p + 1, p + 15))
        E = self._setup_eps(Ac, Mc, float(shift), ncv)
        Ap = self._eps[2]
        E.setDimensions(nev=p, ncv=ncv)
        E.setTolerances(tol=float(tol), max_it=int(maxiter))
        E.setInitialSpace([_vec_from(Ap, Xa[:, j]) for j in range(p)])
        what, hint = f"A + εM (ε = {shift:.3g})", "so A is not positive semidefinite or M is not positive definite"
        pc = E.getST().getKSP().getPC()
        try:
            E.setUp()
            if null := _null_pivots(pc):
                raise InvalidOperatorError(f"{what} is singular: MUMPS found {null} null pivot(s); {hint}")
            E.solve()
        except PETSc.Error as err:
            raise _petsc_failure(err, pc, what, hint) from err
        self.stats = _factor_stats(E.getST().getKSP(), self.solver)
        nconv = min(E.getConverged(), p)
        if nconv == 0 and E.getIterationNumber() >= maxiter:
            return Xa, int(maxiter)
        vr = Ap.createVecRight()
        cols = []
        for i in range(nconv):
            E.getEigenpair(i, vr)
            cols.append(_gather(vr))
        out = np.column_stack(cols + [Xa[:, j] for j in range(nconv, p)]).astype(np.complex128)
        if not np.iscomplexobj(Xa):
            out = out.real if np.abs(out.imag).max() <= 1e-14 * np.abs(out).max() else out
        return out, max(1, int(E.getIterationNumber()))


if petsc_available():  # under mpirun -n P > 1: from the import on, a failure on one rank ends all ranks
    install_abort_hook()


def __getattr__(name):
    # deprecated: the MPI command line moved to dhlb.cli.mpi (a command line is not a solver backend)
    if name == "mpi_main":
        import importlib

        from dhlb._deprecation import warn_moved

        warn_moved("dhlb.linalg.backends_petsc.mpi_main", "dhlb.cli.mpi.mpi_main")
        return importlib.import_module("dhlb.cli.mpi").mpi_main
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


if __name__ == "__main__":  # pragma: no cover - the old entry point: python -m dhlb.linalg.backends_petsc
    import runpy
    import warnings

    warnings.warn("python -m dhlb.linalg.backends_petsc is deprecated and will be removed in dhlb 0.3; "
                  "use python -m dhlb.cli.mpi", DeprecationWarning, stacklevel=1)
    runpy.run_module("dhlb.cli.mpi", run_name="__main__", alter_sys=True)
