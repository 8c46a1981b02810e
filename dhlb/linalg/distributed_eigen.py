"""The smallest eigenpairs of a Hermitian pencil whose rows are spread over the MPI ranks (SLEPc).

:func:`distributed_eigenpairs` takes each rank's :class:`~dhlb.linalg.distributed.RowBlock` of ``A``
and ``M`` (no rank holds a global matrix) and returns the eigenvalues on every rank and each rank's
rows of the eigenvectors. It is collective.

The smallest eigenpairs of the Hermitian pencil ``A u = λ M u``, validated collectively (a bad
input on any rank raises the same typed :mod:`dhlb.errors` exception on every rank, naming the
rank and the row), by one of

* ``"krylovschur"``: SLEPc's Krylov–Schur in shift-and-invert mode at ``−ε`` (``ε`` of
  :func:`default_shift_distributed`) with MUMPS' distributed LU of ``A + εM`` (the options of
  :func:`dhlb.linalg.backends_petsc._direct_pc`: null-pivot detection, ordering
  :data:`~dhlb.linalg.backends_petsc.MUMPS_ORDERING`);
* ``"lobpcg-gamg"``: SLEPc's LOBPCG (``ST`` ``precond``) preconditioned by one V-cycle of
  PETSc's algebraic multigrid ``GAMG`` on ``A + εM``: ``O(n)`` memory, the distributed twin of
  the ``amg-lobpcg`` backend (measured on the ~97k-unknown vortex matrices of a tet box: see
  :data:`METHODS`).

``"auto"`` follows :func:`dhlb.linalg.select_backend` on one process: ``lobpcg-gamg`` for a
volume-like pattern (at least 10 nonzeros per row) of at least
:data:`~dhlb.linalg.backends.ITERATIVE_3D` unknowns; otherwise it factorizes, unless the factor,
estimated by :func:`dhlb.linalg.memory.factor_bytes` (the model of the one-process memory
check) and divided by the number of ranks, does not fit in the memory available on the
tightest rank.
Both use SLEPc's ``EPS_CONV_NORM`` test; afterwards a Rayleigh–Ritz step on the distributed
vectors, ``M``-normalization, the normwise backward errors
``η = ‖Ax − λMx‖ / ((‖A‖₁ + |λ| ‖M‖₁) ‖x‖)`` (all by PETSc products and MPI reductions) and a
phase normalization (``Σ_g conj(s_g) x_g`` real positive, ``s`` the :func:`start_vector`) that
does not depend on the number of ranks.  A pair that misses ``tol`` is solved again from the
current vectors, then reported (``converged=False`` and a note).

Examples
--------
>>> import numpy as np, scipy.sparse as sp
>>> from dhlb.linalg.backends_petsc import petsc_available
>>> from dhlb.linalg.distributed import RowBlock
>>> n = 400
>>> A = sp.diags([-np.ones(n - 1), np.r_[1, 2 * np.ones(n - 2), 1], -np.ones(n - 1)], [-1, 0, 1], format="csr")
>>> blocks = [RowBlock.from_global(S, 0, n) for S in (A, sp.identity(n, format="csr"))]   # one process
>>> exact = 2 - 2 * np.cos(np.pi * np.arange(2) / n)            # the path Laplacian's closed form
>>> lam = distributed_eigenpairs(*blocks, 2, tol=1e-12).eigenvalues if petsc_available() else exact
>>> np.allclose(lam, exact, atol=1e-10)
True
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as sla

from dhlb.errors import InvalidOperatorError, NotSemidefiniteError, ShapeError
from dhlb.linalg.backends import ITERATIVE_3D
from dhlb.linalg.backends_petsc import (
    _direct_pc,
    _factor_stats,
    _forget_options,
    _null_pivots,
    _petsc_failure,
    install_abort_hook,
)
from dhlb.linalg.distributed import (
    RowBlock,
    _agree,
    _allreduce,
    _collective,
    _hermitian_problem,
    _positive_diagonal_problem,
    _size,
    _validate_layout,
    default_shift_distributed,
    norm1_distributed,
    petsc_matrix,
    start_vector,
    world,
)
from dhlb.linalg.memory import available_bytes, factor_bytes

__all__ = ["METHODS", "DistributedEigen", "distributed_eigenpairs"]

METHODS = ("krylovschur", "lobpcg-gamg")
"""The eigensolvers of :func:`distributed_eigenpairs` (``method="auto"`` picks one).

``lobpcg-gamg`` is SLEPc 3.18's LOBPCG (``ST`` ``precond``) with one GAMG V-cycle of ``A + εM``:
measured on the vortex matrices of ``box_tet_mesh(45)`` (97,336 unknowns, k = 1, tol 1e-10, 2
shared cores): 26 iterations in 3.0 s on 1 rank, 30 iterations in 5.5 s on 2 ranks.  Krylov–Schur
in shift-and-invert mode with an inner CG + GAMG solve (relative tolerance 1e-10) converges on
small problems but had not finished after minutes on that one.
"""

_RESTARTS = 2               # solves after the first when a pair misses tol


def _vecs(P, X: np.ndarray) -> list:
    """PETSc vectors of ``P``'s layout holding the owned rows ``X[:, j]``."""
    out = []
    for j in range(X.shape[1]):
        v = P.createVecRight()
        v.setArray(np.asarray(X[:, j], dtype=np.complex128))
        out.append(v)
    return out


def _apply(P, X: np.ndarray) -> np.ndarray:
    """The owned rows of ``P X`` (one PETSc mat-mult per column)."""
    x, y = P.createVecRight(), P.createVecLeft()
    out = np.empty((P.getLocalSize()[0], X.shape[1]), dtype=np.complex128)
    for j in range(X.shape[1]):
        x.setArray(np.asarray(X[:, j], dtype=np.complex128))
        P.mult(x, y)
        out[:, j] = y.getArray(readonly=True)
    return out


def _inner(X: np.ndarray, Y: np.ndarray) -> np.ndarray:
    """``Xᴴ Y`` of distributed blocks (an MPI sum of the local products)."""
    local = X.conj().T @ Y
    comm = world()
    if comm.size == 1:
        return local
    from mpi4py import MPI

    out = np.empty_like(local)
    comm.Allreduce(np.ascontiguousarray(local), out, op=MPI.SUM)
    return out


# ---------------------------------------------------------------------- eigenpairs
@dataclass
class DistributedEigen:
    """Result of :func:`distributed_eigenpairs` (the same on every rank except ``vectors``).

    Attributes
    ----------
    eigenvalues : (k,) float array
        Ascending.
    vectors : (stop - start, k) complex array
        This rank's rows of the ``M``-orthonormal eigenvectors (phase: ``Σ_g s_g x_g > 0``).
    residuals : (k,) float array
        Normwise backward errors ``η``.
    converged : bool
        Whether every ``η <= tol``.
    iterations : int
        Outer iterations of the eigensolver, summed over its solves.
    shift : float
        ``ε``: the solver worked with ``A + εM``.
    method : str
        ``"krylovschur"`` or ``"lobpcg-gamg"``.
    factorizations, solves : int
        Direct factorizations, and applications of the inner solver (factor solves or V-cycles).
    stats : dict
        MUMPS' figures (factor entries, flops, peak MB, the ordering used and the ICNTLs read back
        from the factor), or the preconditioner's.
    note : str
        Why ``auto`` chose the method, restarts, what did not converge.
    """

    eigenvalues: np.ndarray
    vectors: np.ndarray
    residuals: np.ndarray
    converged: bool
    iterations: int
    shift: float
    method: str
    factorizations: int
    solves: int
    stats: dict = field(default_factory=dict)
    note: str = ""


def _choose(A: RowBlock, method: str) -> tuple[str, str]:
    """``(method, note)``: ``auto`` is lobpcg-gamg for a large volume mesh, else Krylov–Schur if the factor fits."""
    if method in METHODS:
        return method, ""
    if method != "auto":
        raise _collective(ShapeError(f"method must be 'auto' or one of {METHODS}, got {method!r}"))
    nnz = int(_allreduce(len(A.data), "sum"))
    if A.n >= ITERATIVE_3D and nnz >= 10 * A.n:
        # the rule of select_backend on one process (a large volume-like pattern goes to amg-lobpcg; the
        # pattern's growth dimension, which needs the whole graph, is judged by nonzeros per row alone)
        return "lobpcg-gamg", (f"auto: {A.n} unknowns with {nnz / A.n:.1f} nonzeros per row (a volume mesh of "
                               f">= {ITERATIVE_3D} vertices): lobpcg-gamg, as amg-lobpcg on one process")
    # the model of dhlb.linalg.memory (the one-process memory check), with a volume's fill for a
    # 3-D-like pattern (>= 10 nonzeros per row, as select_backend), spread over the ranks
    need = factor_bytes(A.n, nnz, complex_=True, dimension=3.0 if nnz >= 10 * A.n else 2.0) / _size()
    have = int(_allreduce(int(available_bytes()), "min"))
    if need <= have:
        return "krylovschur", ""
    return "lobpcg-gamg", (f"auto: the MUMPS factor would need about {need / 2**30:.2f} GiB per rank but only "
                           f"{have / 2**30:.2f} GiB are available: lobpcg-gamg")


def _setup_eps(Ap, Mp, method: str, k: int, shift: float, prefix: str):
    from petsc4py import PETSc
    from slepc4py import SLEPc

    E = SLEPc.EPS().create(comm=PETSc.COMM_WORLD)
    E.setOptionsPrefix(prefix)
    E.setOperators(Ap, Mp)
    E.setProblemType(SLEPc.EPS.ProblemType.GHEP)
    E.setConvergenceTest(SLEPc.EPS.Conv.NORM)
    st = E.getST()
    extra = {}
    if method == "krylovschur":
        E.setType(SLEPc.EPS.Type.KRYLOVSCHUR)
        E.setWhichEigenpairs(SLEPc.EPS.Which.TARGET_REAL)
        E.setTarget(-shift)
        st.setType(SLEPc.ST.Type.SINVERT)
        extra["solver"] = _direct_pc(st.getKSP())
        E.setDimensions(nev=k, ncv=min(Ap.getSize()[0], max(2 * k + 1, k + 15)))
    else:
        E.setType(SLEPc.EPS.Type.LOBPCG)
        E.setWhichEigenpairs(SLEPc.EPS.Which.SMALLEST_REAL)
        st.setType(SLEPc.ST.Type.PRECOND)
        K = Ap.copy()
        K.axpy(shift, Mp, structure=PETSc.Mat.Structure.DIFFERENT_NONZERO_PATTERN)   # A + εM
        st.setPreconditionerMat(K)
        ksp = st.getKSP()
        ksp.setType("preonly")
        ksp.getPC().setType("gamg")
        extra["K"] = K
        E.setDimensions(nev=k)
    E.setFromOptions()
    return E, extra


_calls = 0


def distributed_eigenpairs(A: RowBlock, M: RowBlock, k: int = 1, *, tol: float, maxiter: int | None = None,
                           shift: float | None = None, method: str = "auto") -> DistributedEigen:
    """The ``k`` smallest eigenpairs of ``A u = λ M u`` from each rank's rows (collective).

    See the module docstring.

    Parameters
    ----------
    A, M : RowBlock
        This rank's rows of the Hermitian positive semidefinite ``A`` and positive definite ``M``.
    k : int, optional
        The number of eigenpairs.
    tol : float
        Wanted normwise backward error ``η`` of every pair.
    maxiter : int, optional
        Outer iterations per solve (default: 1000 for Krylov–Schur, 5000 for LOBPCG).
    shift : float, optional
        ``ε`` (default :func:`default_shift_distributed`).
    method : {"auto", "krylovschur", "lobpcg-gamg"}, optional
        The eigensolver.

    Returns
    -------
    DistributedEigen

    Raises
    ------
    ShapeError, NonFiniteError, InvalidOperatorError
        On every rank, when on any rank the blocks are inconsistent (the rows of all ranks must
        tile ``[0, n)`` in rank order, ``A`` and ``M`` alike), hold NaN/inf, ``A`` or ``M`` is not
        Hermitian or ``M`` has a non-positive diagonal entry; the message names the rank and row.
    InvalidOperatorError
        When ``A + εM`` is singular (MUMPS reports null pivots), or PETSc fails otherwise (its
        error code and message are given; :class:`~dhlb.errors.InsufficientMemoryError` when
        MUMPS runs out of workspace or memory).
    NotSemidefiniteError
        When an eigenvalue below ``−ε`` is found (``A`` is not positive semidefinite).

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> from dhlb.linalg.backends_petsc import petsc_available
    >>> from dhlb.linalg.distributed import RowBlock
    >>> n = 50
    >>> S = sp.diags([-np.ones(n - 1), np.r_[1, 2 * np.ones(n - 2), 1], -np.ones(n - 1)], [-1, 0, 1])
    >>> A, M = RowBlock.from_global(S, 0, n), RowBlock.from_global(sp.identity(n), 0, n)
    >>> lam = distributed_eigenpairs(A, M, 2, tol=1e-10).eigenvalues if petsc_available() else 2 - 2 * np.cos(
    ...     np.pi * np.arange(2) / n)
    >>> np.allclose(lam, 2 - 2 * np.cos(np.pi * np.arange(2) / n), atol=1e-12)
    True
    """
    global _calls

    install_abort_hook()
    if not (isinstance(k, (int, np.integer)) and 1 <= k <= A.n):
        raise _collective(ShapeError(f"k must be an integer in [1, n = {A.n}], got {k!r}"))
    _validate_layout({"A": A, "M": M})
    _agree(_positive_diagonal_problem(M))
    Ap, Mp = petsc_matrix(A), petsc_matrix(M)
    _agree(None if (p := _hermitian_problem(A, Ap, "A")) is None else InvalidOperatorError(p))
    _agree(None if (p := _hermitian_problem(M, Mp, "M")) is None else InvalidOperatorError(p))
    eps = float(default_shift_distributed(A, M) if shift is None else shift)
    method, note = _choose(A, method)
    maxiter = int(maxiter if maxiter is not None else (1000 if method == "krylovschur" else 5000))
    normA, normM = norm1_distributed(A), norm1_distributed(M)
    _calls += 1
    prefix = f"dhlb_dist{_calls}_"
    E, extra = _setup_eps(Ap, Mp, method, int(k), eps, prefix)
    pencil = _Pencil(Ap, Mp, A.start, A.stop, eps, normA, normM)
    try:
        return _solve_eps(E, pencil, int(k), _Run(method, extra.get("solver", "gamg"), float(tol), maxiter, note))
    finally:  # free the factor (MUMPS) and the matrices now, not when the garbage collector runs
        for obj in (E, Ap, Mp, extra.get("K")):
            if obj is not None:
                obj.destroy()
        _forget_options(prefix + "st_")


@dataclass(frozen=True)
class _Pencil:
    """The distributed pencil as PETSc holds it: matrices, this rank's rows, the shift and the norms of η."""

    Ap: object
    Mp: object
    start: int
    stop: int
    eps: float
    normA: float
    normM: float


@dataclass(frozen=True)
class _Run:
    """How to solve: the method, its inner solver (``mumps``, ``gamg``), tolerance, iteration limit, a note so far."""

    method: str
    solver: str
    tol: float
    maxiter: int
    note: str


def _solve_eps(E, pencil: _Pencil, k: int, run: _Run) -> DistributedEigen:
    """Run the set-up eigensolver ``E`` (restarting from its vectors if η > tol); the result on every rank."""
    from petsc4py import PETSc

    Ap, Mp, eps, tol, method = pencil.Ap, pencil.Mp, pencil.eps, run.tol, run.method

    ksp = E.getST().getKSP()
    what = f"A + εM (ε = {eps:.3g})"
    try:
        E.setUp()
    except PETSc.Error as err:
        raise _collective(_petsc_failure(err, ksp.getPC(), what, singular_hint=_NOT_PSD)) from err
    if method == "krylovschur" and run.solver == "mumps" and (null := _null_pivots(ksp.getPC())):
        raise _collective(InvalidOperatorError(f"{what} is singular: MUMPS found {null} null pivot(s); "
                                               f"{_NOT_PSD}"))
    s0 = start_vector(pencil.start, pencil.stop, 0)
    X = np.column_stack([s0] + [start_vector(pencil.start, pencil.stop, j) for j in range(1, k)])
    X = X.astype(np.complex128)
    iterations, t0, notes, solves0 = 0, time.perf_counter(), [run.note] if run.note else [], _ksp_solves()
    for attempt in range(1 + _RESTARTS):
        E.setTolerances(tol=tol, max_it=run.maxiter)
        E.setInitialSpace(_vecs(Ap, X))
        try:
            E.solve()
        except PETSc.Error as err:
            raise _collective(_petsc_failure(err, ksp.getPC(), what, singular_hint=_NOT_PSD)) from err
        iterations += int(E.getIterationNumber())
        nconv = min(int(E.getConverged()), k)
        vr = Ap.createVecRight()
        for i in range(nconv):
            E.getEigenpair(i, vr)
            X[:, i] = vr.getArray(readonly=True)
        lam, X, eta = _rayleigh_ritz(Ap, Mp, X, pencil.normA, pencil.normM)
        if lam[0] < -eps:
            raise _collective(NotSemidefiniteError(
                f"{what} is not positive definite, so A is not positive semidefinite or M is not positive "
                f"definite (eigenvalue {lam[0]:.6g} < −ε)"))
        X = _fix_phase(X, s0)
        if np.all(eta <= tol):
            break
        notes.append(f"solve {attempt + 1}: {nconv} of {k} pairs converged in SLEPc, max η = {eta.max():.2e} "
                     f"> tol = {tol:.1e}; " + ("solving again from these vectors" if attempt < _RESTARTS
                                                else "giving up"))
    converged = bool(np.all(eta <= tol))
    stats = {"time": time.perf_counter() - t0}
    if method == "krylovschur":
        stats.update(_factor_stats(ksp, run.solver))
    else:
        stats["preconditioner"] = "gamg"
        stats["gamg_levels"] = int(ksp.getPC().getMGLevels())
    factorizations, solves = int(method == "krylovschur"), _ksp_solves() - solves0
    return DistributedEigen(eigenvalues=lam, vectors=X, residuals=eta, converged=converged, iterations=iterations,
                            shift=eps, method=method, factorizations=factorizations, solves=solves, stats=stats,
                            note="; ".join(notes))


_NOT_PSD = "so A is not positive semidefinite or M is not positive definite"


def _ksp_solves() -> int:
    """How many ``KSPSolve`` calls this process has made (PETSc's event log, switched on here)."""
    from petsc4py import PETSc

    PETSc.Log.begin()
    return int(PETSc.Log.Event("KSPSolve").getPerfInfo()["count"])


def _rayleigh_ritz(Ap, Mp, X, normA, normM):
    """Rayleigh–Ritz on the distributed block ``X``: ``(λ, M-orthonormal X, η)``, the same ``λ, η`` on all ranks."""
    AX, MX = _apply(Ap, X), _apply(Mp, X)
    H, G = _inner(X, AX), _inner(X, MX)
    H, G = (H + H.conj().T) / 2, (G + G.conj().T) / 2
    lam, C = sla.eigh(H, G)
    X, AX, MX = X @ C, AX @ C, MX @ C
    R = AX - MX * lam[None, :]
    rn = np.sqrt(np.real(np.diag(_inner(R, R))))
    xn = np.sqrt(np.real(np.diag(_inner(X, X))))
    den = (normA + np.abs(lam) * normM) * xn
    return lam, X, rn / np.where(den > 0, den, 1.0)


def _fix_phase(X: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Make ``Σ_g s_g x_g`` real positive for each column (an MPI sum: independent of the rank count)."""
    c = _inner(s[:, None].astype(np.complex128), X).ravel()
    mod = np.abs(c)
    return X * np.where(mod > 0, mod / np.where(mod > 0, c, 1), 1)[None, :]
