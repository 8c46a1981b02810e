"""Linear-algebra backends of :mod:`dhlb.linalg.eigen`: one small interface, several implementations.

A *backend* is an object with

``name`` : str
    Reported in :attr:`dhlb.fem.EigenResult.backend`.
``factorize(K, positive_definite=False)``
    Returns a *factor*: an object with ``solve(B)`` solving ``K X = B`` for ``B`` of shape
    ``(n,)`` or ``(n, r)`` and a ``name`` (the method that was actually used; a Cholesky backend
    asked to factorize an indefinite matrix falls back to SuperLU and says so).  Raises
    :class:`~dhlb.errors.InvalidOperatorError` if ``K`` is singular, or not positive definite when
    ``positive_definite=True`` was asserted (the check is part of the factorization).
``eigensolve(A, M, X, *, shift, tol, maxiter)`` (iterative backends only)
    Improves the block ``X`` towards the lowest eigenvectors of ``A u = λ M u`` and returns
    ``(X, iterations)``; :func:`~dhlb.fem.smallest_eigenpairs` does the final Rayleigh–Ritz and
    the backward-error test.

Implemented backends (see ``docs/performance.md`` for measurements):

=============== ======================================================================== ==============
name            method                                                                   needs
=============== ======================================================================== ==============
``superlu``     :func:`scipy.sparse.linalg.splu`, symmetric mode, nested dissection      scipy, pymetis
``cholmod``     CHOLMOD supernodal ``L Lᴴ``, complex Hermitian directly                  cvxopt, pymetis
``cholespy``    CHOLMOD inside cholespy, real only: the real 2N embedding of ``K``        cholespy
``amg-lobpcg``  LOBPCG preconditioned by smoothed-aggregation AMG; O(N) memory           pyamg
``petsc``       SLEPc Krylov–Schur, shift-and-invert by MUMPS, under MPI                 petsc4py, slepc4py
=============== ======================================================================== ==============

Symbolic analysis (fill-reducing ordering) is computed once per sparsity pattern and reused: the
cache is keyed by ``(backend, shape, dtype kind, hash of indptr/indices)`` (:func:`cache_info`).
All factorizations and solves run under :func:`blas_guard`, which limits the BLAS thread pools
to :data:`BLAS_THREADS` threads (threadpoolctl, a dependency) so that users need not set
``OPENBLAS_NUM_THREADS``; a thread variable the user did set wins.

Examples
--------
>>> import numpy as np, scipy.sparse as sp
>>> K = sp.csc_matrix([[2.0, -1.0], [-1.0, 2.0]])
>>> get_backend("superlu").factorize(K, positive_definite=True).solve(np.array([1.0, 0.0])).round(6).tolist()
[0.666667, 0.333333]
>>> "superlu" in available_backends()
True
"""

from __future__ import annotations

import contextlib
import hashlib
import importlib.util
import os
from collections import OrderedDict

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from dhlb.errors import InvalidOperatorError, InvalidParameterError
from dhlb.linalg.memory import InsufficientMemoryError, available_bytes, check_factorization_memory
from dhlb.linalg.ordering import nested_dissection

__all__ = ["BLAS_THREADS", "SuperLUBackend", "available_backends", "blas_guard", "cache_info", "clear_cache",
           "distributes", "get_backend", "pattern_dimension", "register_backend", "select_backend"]

BLAS_THREADS = 1
"""Number of BLAS threads allowed inside factorizations and solves (``None``: leave them alone).

A thread variable the user set (:data:`THREAD_VARIABLES`) wins: then the pools are left alone."""

THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS",
                    "VECLIB_MAXIMUM_THREADS", "GOTO_NUM_THREADS")
"""Environment variables through which a user sets the BLAS threads explicitly."""

_CACHE_SIZE = 8
_cache: OrderedDict = OrderedDict()
_stats = {"hits": 0, "misses": 0}


# ---------------------------------------------------------------------- thread guard, pattern cache
_guard_depth = 0


@contextlib.contextmanager
def blas_guard():
    """Context manager limiting BLAS threads to :data:`BLAS_THREADS` (threadpoolctl).

    A no-op when the user set a thread variable (:data:`THREAD_VARIABLES`: their setting wins), when
    ``BLAS_THREADS`` is None, or without threadpoolctl.  Re-entrant: only the outermost guard talks to
    threadpoolctl (0.05 ms through the handle :func:`_blas_pools` keeps), nested ones are free.

    Examples
    --------
    >>> with blas_guard():
    ...     pass
    """
    global _guard_depth
    pools = None if _guard_depth or BLAS_THREADS is None or _user_set_threads() else _blas_pools()
    with contextlib.nullcontext() if pools is None else pools.limit(limits=BLAS_THREADS):
        _guard_depth += 1
        try:
            yield
        finally:
            _guard_depth -= 1


def _user_set_threads() -> bool:
    return any(os.environ.get(v) for v in THREAD_VARIABLES)


_pools = None


def _blas_pools():
    """The threadpoolctl handle on the BLAS libraries of this process (None without threadpoolctl).

    Made once: finding the libraries takes about 5 ms, limiting them through the handle 0.05 ms
    (a fresh ``threadpool_limits`` each time took 1.4 ms).  It is made when this module is
    imported, after numpy's, scipy's and cvxopt's BLAS are loaded.
    """
    global _pools
    if _pools is None and _importable("threadpoolctl"):
        from threadpoolctl import ThreadpoolController

        _pools = ThreadpoolController().select(user_api="blas")
    return _pools


def pattern_key(name: str, K: sp.csc_matrix) -> tuple:
    """Cache key of the sparsity pattern of a canonical CSC matrix ``K`` for backend ``name``."""
    h = hashlib.blake2b(np.ascontiguousarray(K.indptr, dtype=np.int64).view(np.uint8), digest_size=16)
    h.update(np.ascontiguousarray(K.indices, dtype=np.int64).view(np.uint8))
    return (name, K.shape, K.dtype.kind, K.nnz, h.hexdigest())


def cached_symbolic(key: tuple, compute):
    """The symbolic analysis stored under ``key``, computing (and storing) it on a miss."""
    if key in _cache:
        _stats["hits"] += 1
        _cache.move_to_end(key)
        return _cache[key]
    _stats["misses"] += 1
    value = compute()
    _cache[key] = value
    while len(_cache) > _CACHE_SIZE:
        _cache.popitem(last=False)
    return value


def cache_info() -> dict:
    """``{"hits", "misses", "size"}`` of the symbolic-analysis cache.

    Examples
    --------
    >>> sorted(cache_info())
    ['hits', 'misses', 'size']
    """
    return {**_stats, "size": len(_cache)}


def clear_cache() -> None:
    """Empty the symbolic-analysis cache and reset its counters."""
    _cache.clear()
    _stats.update(hits=0, misses=0)


def canonical_csc(K) -> sp.csc_matrix:
    """``K`` as a CSC matrix with sorted, summed indices (the form every backend receives)."""
    K = sp.csc_matrix(K)
    K.sum_duplicates()
    K.sort_indices()
    return K


# ---------------------------------------------------------------------- SuperLU
class _PermutedLU:
    """Solve ``K x = b`` with an LU factorization ``G`` of ``K[q][:, q]``: ``x[q] = G⁻¹ b[q]``.

    ``negative_pivots`` is the number of negative pivots of a symmetric ``L D Lᴴ`` factorization
    (no pivoting took place), which by Sylvester's law of inertia is the number of negative
    eigenvalues of ``K``; ``None`` when SuperLU had to pivot off the diagonal.
    """

    name = "superlu"

    def __init__(self, lu, q=None, dtype=np.float64):
        self.lu, self.q, self.dtype = lu, q, np.dtype(dtype)   # not lu.L.dtype: SuperLU copies L on every access
        self._neg = -1

    @property
    def negative_pivots(self) -> int | None:
        if self._neg == -1:  # computed on demand: SuperLU hands out U only as a copy
            lu = self.lu
            self._neg = int(np.sum(lu.U.diagonal().real < 0)) if np.array_equal(lu.perm_r, lu.perm_c) else None
        return self._neg

    def solve(self, B):
        B = np.asarray(B)
        dtype = np.result_type(B.dtype, self.dtype)
        if self.q is None:
            return self.lu.solve(np.ascontiguousarray(B, dtype=dtype))
        X = np.empty(B.shape, dtype=dtype)
        X[self.q] = self.lu.solve(np.ascontiguousarray(B[self.q], dtype=dtype))
        return X


class SuperLUBackend:
    """Sparse LU by SuperLU (real or complex) in a nested-dissection order; ``factorize(K).solve(B)``.

    The Hermitian ``K`` is permuted symmetrically by :func:`dhlb.linalg.ordering.nested_dissection`
    (METIS; computed once per sparsity pattern and cached) and factorized in SuperLU's symmetric
    mode with diagonal pivots, i.e. as ``L D Lᴴ`` in LU form; small matrices (below
    :data:`~dhlb.linalg.ordering.ND_MIN` unknowns) use SuperLU's minimum degree on ``Kᵀ + K``.
    With ``positive_definite=True`` no pivoting is allowed and, by Sylvester's law of inertia,
    ``K`` is positive definite iff all pivots ``D`` are positive, which is checked (up to
    :data:`PIVOT_CHECK_MAX` unknowns); otherwise an
    off-diagonal pivot is taken when a diagonal one is below 1 % of its column.  Before
    factorizing, the memory the factor will need is estimated (:mod:`dhlb.linalg.memory`);
    a factorization that would not fit, or that runs out of memory inside SuperLU, raises
    :class:`~dhlb.linalg.memory.InsufficientMemoryError`.
    """

    name = "superlu"

    def factorize(self, K, *, positive_definite: bool = False, inertia: bool = False):
        """Factorize ``K``; raises :class:`InvalidOperatorError` if it is singular (or not PD when asked).

        ``inertia=True`` forbids pivoting off the diagonal, so that the factor's
        ``negative_pivots`` counts the negative eigenvalues of ``K`` (Sylvester's law of inertia).
        """
        K = canonical_csc(K)
        n = K.shape[0]
        complex_ = K.dtype.kind == "c"
        need = check_factorization_memory(n, K.nnz, complex_=complex_, dimension=lambda: pattern_dimension(K),
                                          backend=self.name, alternatives=_fitting_alternatives())
        kw = {"diag_pivot_thresh": 0.0 if positive_definite or inertia else 0.01, "options": {"SymmetricMode": True}}
        key = pattern_key(self.name, K)
        try:
            with blas_guard():
                q = cached_symbolic(key, lambda: nested_dissection(K))
                if q is None:
                    lu = spla.splu(K, permc_spec="MMD_AT_PLUS_A", **kw)
                else:
                    lu = spla.splu(canonical_csc(K[q][:, q]), permc_spec="NATURAL", **kw)
        except RuntimeError as err:  # "Factor is exactly singular"
            raise InvalidOperatorError(f"the matrix to factorize is singular ({err})") from err
        except (MemoryError, SystemError) as err:  # SuperLU's "malloc fails" surfaces as either
            raise InsufficientMemoryError(
                f"SuperLU ran out of memory factorizing this {n:,}-unknown matrix ({K.nnz:,} nonzeros; estimated "
                f"{need / 2**30:.2f} GiB, {available_bytes() / 2**30:.2f} GiB available now); use an iterative "
                "backend (backend='amg-lobpcg', pip install pyamg) or a machine with more memory",
                needed=need, available=available_bytes()) from err
        fac = _PermutedLU(lu, q, K.dtype)
        if positive_definite and n <= PIVOT_CHECK_MAX and np.array_equal(lu.perm_r, lu.perm_c):
            piv = lu.U.diagonal().real
            fac._neg = int(np.sum(piv < 0))
            if not np.all(piv > 0):
                raise InvalidOperatorError(f"the matrix is not positive definite ({int(np.sum(piv <= 0))} "
                                           "non-positive pivots in its L D Lᴴ factorization)")
        return fac


PIVOT_CHECK_MAX = 100_000
"""Up to this many unknowns ``positive_definite=True`` is proved by the signs of the pivots.

SuperLU hands out ``U`` only as a copy (measured: 0.8 s and 0.25 GB at 164k unknowns, half the
time of the factorization itself); above this size the eigensolver's Rayleigh–Ritz check
(no eigenvalue below the shift) and :func:`dhlb.linalg.solve`'s ``xᴴb > 0`` check remain.
"""


def _fitting_alternatives():
    return ("amg-lobpcg",) if "amg-lobpcg" in available_backends() else ()


# ---------------------------------------------------------------------- registry, selection
def _lazy(module: str, cls: str):
    def make():
        mod = importlib.import_module(module)
        return getattr(mod, cls)()
    return make


_REGISTRY = {
    "superlu": (SuperLUBackend, ()),
    "cholmod": (_lazy("dhlb.linalg.backends_cholesky", "CholmodBackend"), ("cvxopt",)),
    "cholespy": (_lazy("dhlb.linalg.backends_cholesky", "CholespyBackend"), ("cholespy",)),
    "amg-lobpcg": (_lazy("dhlb.linalg.backends_amg", "AMGLobpcgBackend"), ("pyamg",)),
    "petsc": (_lazy("dhlb.linalg.backends_petsc", "PetscBackend"), ("petsc4py", "slepc4py", "mpi4py")),
}
_INSTALL = {"cvxopt": "pip install cvxopt (a dependency of dhlb: reinstall dhlb)",
            "cholespy": "pip install cholespy", "pyamg": "pip install pyamg",
            "petsc4py": "Debian 12: .ci/mpi-setup.sh (python3-petsc4py-complex python3-slepc4py-complex "
                        "python3-mpi4py; see docs/mpi.md)",
            "slepc4py": "see docs/mpi.md", "mpi4py": "apt-get install python3-mpi4py (see docs/mpi.md)"}


def _importable(module: str) -> bool:
    try:
        return importlib.util.find_spec(module) is not None
    except (ImportError, ValueError):  # a module set to None in sys.modules, a broken parent package
        return False


def register_backend(name: str, factory, requires=()) -> None:
    """Register a backend ``factory()`` under ``name`` (``requires``: importable module names)."""
    _REGISTRY[name] = (factory, tuple(requires))


def available_backends() -> list[str]:
    """Names of the backends whose dependencies are importable, in registry order.

    Returns
    -------
    list of str
        The names; ``"superlu"`` is always among them.

    Examples
    --------
    >>> "superlu" in available_backends()                           # always available (scipy)
    True
    """
    return [n for n, (_, req) in _REGISTRY.items() if all(_importable(r) for r in req)]


def distributes(backend) -> bool:
    """Whether a call with this ``backend`` should run distributed: ``"petsc"`` under ``mpirun`` with several ranks.

    The applications that have a distributed form (:func:`dhlb.fields.direction_field` for the smoothest
    field, :func:`dhlb.vortex.vortex_filaments`) hand such a call to it; on one rank, or with another
    backend, nothing changes.

    Parameters
    ----------
    backend : str, backend object or None
        ``SolverOptions.backend``.

    Returns
    -------
    bool

    Examples
    --------
    >>> distributes(None), distributes("superlu")
    (False, False)
    """
    name = backend if isinstance(backend, str) else getattr(backend, "name", None)
    if name != "petsc":
        return False
    from dhlb.linalg.backends_petsc import comm_rank_size, petsc_available  # loads PETSc only when named

    return petsc_available() and comm_rank_size()[1] > 1


def get_backend(backend=None, *, n: int = 0, nnz: int = 0, eigen: bool = False, shifted: bool = False,
                dimension=None):
    """The backend object for ``backend`` (a name, ``None``/``"auto"``, or a backend object).

    ``None``/``"auto"`` calls :func:`select_backend` with the problem description ``n``, ``nnz``,
    ``eigen``, ``shifted``, ``dimension`` (a number or a callable computing it on demand).  An
    unknown or unavailable name raises
    :class:`~dhlb.errors.InvalidParameterError` listing the available ones.
    """
    if backend is None or (isinstance(backend, str) and backend == "auto"):
        backend = select_backend(n, nnz, eigen=eigen, shifted=shifted, dimension=dimension)
    if isinstance(backend, str):
        avail = available_backends()
        if backend not in avail:
            if backend in _REGISTRY:
                req = _REGISTRY[backend][1]
                hint = "; ".join(_INSTALL.get(r, f"pip install {r}") for r in req)
                raise InvalidParameterError(f"backend {backend!r} is not installed ({hint}); available: {avail}")
            raise InvalidParameterError(f"unknown backend {backend!r}; available: {avail} (or 'auto')")
        return _REGISTRY[backend][0]()
    if not (hasattr(backend, "factorize") and hasattr(backend, "name")):
        raise TypeError("a backend needs a `name` and a `factorize(K, positive_definite=False)` method "
                        "returning an object with `solve(B)`")
    return backend


ITERATIVE_3D = 10_000
"""From this many unknowns on, a 3-D-like pattern (>= 10 nonzeros per row) goes to ``amg-lobpcg``."""


def pattern_dimension(A, seeds: int = 8, radius: int = 3) -> float:
    """Growth dimension ``d`` of the graph of ``A``: ``|ball(2r)| / |ball(r)| ≈ 2^d`` (median over seeds).

    Balls are grown by ``2r`` sparse products from ``seeds`` vertices spread over the index
    range.  Measured at ``r = 3`` (the median of 8 seeds): triangulated surfaces 1.8–1.95, also when
    each vertex carries a 2 × 2 block (real embedding of a complex field); tetrahedral meshes
    2.24–2.6 (small radii undercount the cubic growth).  It tells fill-in-prone 3-D problems from 2-D
    ones where nonzeros per row cannot (both have ~14). The median, not the largest ratio: one seed
    on an irregular patch of a scanned surface measured 2.64 (nefertiti) and 2.21 (the ogre), which
    made its stripe pattern an "iterative 3-D" problem whose LOBPCG stalled.

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> path = sp.diags([np.ones(99), np.ones(100), np.ones(99)], [-1, 0, 1], format="csr")
    >>> round(pattern_dimension(path), 1)
    1.0
    """
    G = sp.csr_matrix((np.ones(A.nnz, np.float32), A.indices, A.indptr), shape=A.shape)
    n = G.shape[0]
    X = np.zeros((n, seeds), np.float32)
    X[np.linspace(n // (2 * seeds), n - 1 - n // (2 * seeds), seeds).astype(int), np.arange(seeds)] = 1
    sizes = []
    for step in range(1, 2 * radius + 1):
        X = np.minimum(G @ X + X, 1)
        if step in (radius, 2 * radius):
            sizes.append(X.sum(axis=0))
    ratio = np.median(sizes[1] / np.maximum(sizes[0], 1))
    return float(np.log2(max(ratio, 1.0)))


def select_backend(n: int, nnz: int, *, eigen: bool = True, shifted: bool = False, dimension=None) -> str:
    """Name of the backend ``auto`` uses for an ``n × n`` problem with ``nnz`` nonzeros.

    * ``eigen`` (smallest eigenpairs, no ``sigma``) of a 3-D-like pattern (``nnz / n >= 10``: P1 on
      tetrahedra has ~15 per row, on triangles ~7; and, when ``dimension`` — the
      :func:`pattern_dimension` of the matrix — is given, ``dimension >= 2.2``, which excludes
      surfaces with 2 × 2 blocks per vertex) with ``n >= ITERATIVE_3D``: ``amg-lobpcg`` if pyamg
      is installed (direct factorizations of 3-D meshes fill in badly: measured 25× slower on a
      36k-vertex tet grid).  Surfaces stay direct at every size: on the 1.31M-face icosphere's cross
      field (655k unknowns) LOBPCG with an AMG preconditioner broke down at a residual of 2e-2,
      where SuperLU's factorization and 13 solves took 21 s in 3.8 GB (issue 30); a factorization
      that does not fit in memory still falls back to ``amg-lobpcg``, and says so;
    * ``shifted`` (``A − σM`` may be indefinite: ``sigma`` given, or a linear solve not asserted
      positive definite): ``superlu`` (its ``L D Lᴴ`` takes indefinite matrices);
    * otherwise ``cholmod`` (a dependency).  Its Cholesky factor is half of SuperLU's ``L`` and
      ``U``, and it is faster at every size (cross-field matrices, factorization and 15 solves,
      the ordering counted): 864 unknowns 4.6 ms against 8.5 ms, spot (2,930) 16 ms against 25 ms,
      the bunny (34,834) 0.44 s against 0.76 s, the 1.31M-face icosphere (655,362) 16 s and 790 MiB
      against 19 s and 1.36 GiB.  cholespy needs the 2N real embedding of complex matrices and
      measured slower than SuperLU: choose it explicitly.

    ``shifted`` also excludes the iterative path.

    Parameters
    ----------
    n : int
        The number of unknowns.
    nnz : int
        The number of nonzeros of the matrix.
    eigen : bool, optional
        Whether the problem is a smallest-eigenpair problem (else a linear solve).
    shifted : bool, optional
        Whether the factorized matrix may be indefinite (a shift ``sigma`` inside the spectrum, a linear
        solve not asserted positive definite).
    dimension : float or callable or None, optional
        The :func:`pattern_dimension` of the matrix, or a callable returning it (called only when needed).

    Returns
    -------
    str
        A backend name: ``"amg-lobpcg"``, ``"superlu"`` or ``"cholmod"``.

    Examples
    --------
    >>> select_backend(100, 700), select_backend(100, 700, shifted=True)
    ('cholmod', 'superlu')
    """
    avail = available_backends()
    three_d = nnz >= 10 * n and (dimension is None or (dimension() if callable(dimension) else dimension) >= 2.2)
    big = n >= ITERATIVE_3D and nnz >= 10 * n and three_d
    if eigen and not shifted and big and "amg-lobpcg" in avail:
        return "amg-lobpcg"
    if shifted or "cholmod" not in avail:
        return "superlu"
    return "cholmod"


if BLAS_THREADS is not None and not _user_set_threads():
    _blas_pools()   # find the BLAS libraries now (about 5 ms), not inside the first factorization
