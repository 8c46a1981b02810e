"""Distributed linear algebra under MPI: every rank holds only its own rows of ``A`` and ``M``.

A global ``n × n`` sparse matrix is split into contiguous blocks of rows, ``[start, stop)`` on
rank ``r`` in rank order (a renumbered ordering; columns are global ids).  A :class:`RowBlock` is
one rank's block, handed to PETSc as a distributed ``AIJ`` matrix (:func:`petsc_matrix`) without
any rank ever holding the global matrix.  Every function that takes a :class:`RowBlock` (or an
owned slice of a vector) is *collective*: all ranks must call it.

Eigenpairs (:func:`distributed_eigenpairs`)
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

Vectors
    :func:`scatter_values` fetches the values at any global ids (halo entries) of a distributed
    vector (``MPI_Alltoallv``), :func:`gather_to_root` concatenates the owned slices on one rank.

Without mpi4py every function that needs no PETSc runs as one process (``size 1``).

Examples
--------
>>> import numpy as np, scipy.sparse as sp
>>> S = sp.diags([-np.ones(5), 2 * np.ones(6), -np.ones(5)], [-1, 0, 1], format="csr")
>>> B = RowBlock.from_global(S, *row_layout(6)[:2])        # one process: all 6 rows
>>> (B.start, B.stop, B.n), norm1_distributed(B)
((0, 6, 6), 4.0)
>>> scatter_values(np.arange(6.0), 0, 6, 6, np.array([5, 0, 5])).tolist()
[5.0, 0.0, 5.0]
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

import dhlb.errors as _errors
from dhlb.errors import DhlbError, InvalidOperatorError, NotSemidefiniteError, ShapeError
from dhlb.linalg.backends import ITERATIVE_3D
from dhlb.linalg.backends_petsc import (
    _direct_pc,
    _factor_stats,
    _null_pivots,
    _petsc_failure,
    install_abort_hook,
    petsc_available,  # noqa: F401 -- the examples skip without PETSc
)
from dhlb.linalg.memory import available_bytes, factor_bytes

__all__ = ["METHODS", "DistributedEigen", "RowBlock", "check_hermitian_distributed", "default_shift_distributed",
           "distributed_eigenpairs", "gather_to_root", "norm1_distributed", "petsc_matrix", "row_layout",
           "scatter_values", "start_vector"]

METHODS = ("krylovschur", "lobpcg-gamg")
"""The eigensolvers of :func:`distributed_eigenpairs` (``method="auto"`` picks one).

``lobpcg-gamg`` is SLEPc 3.18's LOBPCG (``ST`` ``precond``) with one GAMG V-cycle of ``A + εM``:
measured on the vortex matrices of ``box_tet_mesh(45)`` (97,336 unknowns, k = 1, tol 1e-10, 2
shared cores): 26 iterations in 3.0 s on 1 rank, 30 iterations in 5.5 s on 2 ranks.  Krylov–Schur
in shift-and-invert mode with an inner CG + GAMG solve (relative tolerance 1e-10) converges on
small problems but had not finished after minutes on that one.
"""

_HERMITIAN_RTOL = 1e-10     # as dhlb.linalg._checks._check_hermitian
_RESTARTS = 2               # solves after the first when a pair misses tol
_EPS = np.finfo(float).eps


# ---------------------------------------------------------------------- MPI plumbing
def _mpi():
    """``MPI_COMM_WORLD`` (mpi4py), or ``None`` without mpi4py (one process)."""
    try:
        from mpi4py import MPI
    except ImportError:
        return None
    return MPI.COMM_WORLD


def _size() -> int:
    comm = _mpi()
    return 1 if comm is None else comm.size


def _allreduce(value, op: str):
    comm = _mpi()
    if comm is None or comm.size == 1:
        return value
    from mpi4py import MPI

    return comm.allreduce(value, op={"sum": MPI.SUM, "max": MPI.MAX, "min": MPI.MIN}[op])


def _collective(err: DhlbError) -> DhlbError:
    err.mpi_collective = True  # raised on every rank: the abort hook prints it once (rank 0)
    return err


def _agree(err: DhlbError | None) -> None:
    """Raise the same typed error on every rank if ``err`` is set on any rank (the lowest such rank's)."""
    comm = _mpi()
    size = 1 if comm is None else comm.size
    status = None if err is None else (type(err).__name__, str(err))
    statuses = [status] if size == 1 else comm.allgather(status)
    for r, st in enumerate(statuses):
        if st is not None:
            cls = getattr(_errors, st[0], InvalidOperatorError)
            if not (isinstance(cls, type) and issubclass(cls, DhlbError)):
                cls = InvalidOperatorError
            raise _collective(cls(f"{st[1]} [MPI rank {r} of {size}]")) from None   # one error line


def _agreeing(fn, *args):
    """``fn(*args)`` on every rank; a :class:`DhlbError` on any rank is raised on all of them."""
    try:
        out, err = fn(*args), None
    except DhlbError as e:
        out, err = None, e
    _agree(err)
    return out


# ---------------------------------------------------------------------- row blocks
@dataclass(frozen=True)
class RowBlock:
    """The rows ``[start, stop)`` owned by this rank of a global ``n × n`` sparse matrix, in CSR form.

    Attributes
    ----------
    indptr : (stop - start + 1,) int array
        Row pointers into ``indices``/``data`` (``indptr[0] == 0``).
    indices : (nnz_local,) int array
        Global column ids, sorted within each row.
    data : (nnz_local,) float or complex array
        The entries.
    start, stop : int
        The global rows owned by this rank.
    n : int
        The global size.

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> B = RowBlock.from_global(sp.identity(4, format="csr"), 1, 3)
    >>> B.indptr.tolist(), B.indices.tolist(), B.n_owned
    ([0, 1, 2], [1, 2], 2)
    """

    indptr: np.ndarray
    indices: np.ndarray
    data: np.ndarray
    start: int
    stop: int
    n: int

    @property
    def n_owned(self) -> int:
        """``stop - start``."""
        return int(self.stop - self.start)

    @classmethod
    def from_global(cls, S, start: int, stop: int) -> RowBlock:
        """The rows ``[start, stop)`` of the global sparse matrix ``S`` (a test helper).

        Parameters
        ----------
        S : (n, n) scipy.sparse matrix
            The global matrix (duplicates summed, columns sorted here).
        start, stop : int
            The rows to keep.

        Returns
        -------
        RowBlock
            Those rows, with global column ids.

        Examples
        --------
        >>> import numpy as np, scipy.sparse as sp
        >>> RowBlock.from_global(sp.csr_matrix(np.ones((3, 3))), 2, 3).indices.tolist()
        [0, 1, 2]
        """
        S = sp.csr_matrix(S, copy=True)
        S.sum_duplicates()
        S.sort_indices()
        ip = S.indptr[start:stop + 1]
        return cls(indptr=(ip - ip[0]).astype(np.int64), indices=S.indices[ip[0]:ip[-1]].astype(np.int64),
                   data=S.data[ip[0]:ip[-1]].copy(), start=int(start), stop=int(stop), n=int(S.shape[0]))

    def _rows(self) -> np.ndarray:
        """The local row of each stored entry."""
        return np.repeat(np.arange(self.n_owned), np.diff(self.indptr))

    def _diagonal(self) -> np.ndarray:
        """The owned diagonal entries ``B[g, g]`` (0 where not stored)."""
        d = np.zeros(self.n_owned, dtype=np.result_type(self.data.dtype, np.float64))
        rows = self._rows()
        on = self.indices == rows + self.start
        d[rows[on]] = self.data[on]
        return d


def row_layout(n_owned: int) -> tuple[int, int, int]:
    """``(start, stop, n)`` of this rank's rows from the number of rows each rank owns (collective).

    Parameters
    ----------
    n_owned : int
        The number of rows this rank owns.

    Returns
    -------
    tuple of int
        ``start`` (the rows owned by lower ranks, an exclusive prefix sum), ``stop = start + n_owned``
        and ``n`` (the sum over ranks).

    Examples
    --------
    >>> row_layout(5)                          # one process
    (0, 5, 5)
    """
    n_owned = int(n_owned)
    comm = _mpi()
    if comm is None or comm.size == 1:
        return 0, n_owned, n_owned
    start = comm.exscan(n_owned)
    start = 0 if comm.rank == 0 or start is None else int(start)
    return start, start + n_owned, int(comm.allreduce(n_owned))


def _local_problem(B: RowBlock, name: str) -> str | None:
    """A description of what is wrong with ``B`` on this rank (shapes, ids, finiteness), or ``None``."""
    for attr in ("indptr", "indices", "data"):
        if np.ndim(getattr(B, attr)) != 1:
            return f"ShapeError:{name}.{attr} must be 1-D, got shape {np.shape(getattr(B, attr))}"
    nloc, ip = B.stop - B.start, B.indptr
    if not (0 <= B.start <= B.stop <= B.n) or B.n <= 0:
        return f"ShapeError:{name} owns rows [{B.start}, {B.stop}) of n = {B.n}: not 0 <= start <= stop <= n, n > 0"
    if len(ip) != nloc + 1:
        return f"ShapeError:{name} owns {nloc} rows [{B.start}, {B.stop}) but has len(indptr) - 1 = {len(ip) - 1}"
    if ip[0] != 0 or np.any(np.diff(ip) < 0) or ip[-1] != len(B.indices) or len(B.indices) != len(B.data):
        return (f"ShapeError:{name} has inconsistent CSR arrays (indptr from {ip[0]} to {ip[-1]}, "
                f"{len(B.indices)} indices, {len(B.data)} values)")
    if not np.issubdtype(B.data.dtype, np.number) or np.issubdtype(B.data.dtype, np.bool_):
        return f"ShapeError:{name} must have numeric data, got {B.data.dtype}"
    rows = B._rows()
    bad = (B.indices < 0) | (B.indices >= B.n)
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        return f"ShapeError:{name} row {B.start + rows[i]} has column id {B.indices[i]} outside [0, {B.n})"
    unsorted = (np.diff(B.indices) <= 0) & (rows[1:] == rows[:-1])
    if np.any(unsorted):
        i = int(np.flatnonzero(unsorted)[0])
        return f"ShapeError:{name} row {B.start + rows[i]} has unsorted or repeated column ids"
    finite = np.isfinite(B.data)
    if not np.all(finite):
        i = int(np.flatnonzero(~finite)[0])
        return f"NonFiniteError:{name}[{B.start + rows[i]}, {B.indices[i]}] = {B.data[i]} is not finite"
    return None


def _validate_layout(blocks: dict) -> None:
    """Collective: each block is locally consistent, and the blocks tile ``[0, n)`` in rank order."""
    problem = None
    for name, B in blocks.items():
        problem = problem or _local_problem(B, name)
    err = None
    if problem is not None:
        kind, msg = problem.split(":", 1)
        err = getattr(_errors, kind)(msg)
    _agree(err)
    comm = _mpi()
    layouts = [tuple((B.start, B.stop, B.n) for B in blocks.values())]
    if comm is not None and comm.size > 1:
        layouts = comm.allgather(layouts[0])
    names = list(blocks)
    for r, lay in enumerate(layouts):           # the same list on every rank: the same verdict
        for (name, (a, b, n)) in zip(names[1:], lay[1:]):
            if (a, b, n) != lay[0]:
                raise _collective(ShapeError(f"{name} owns rows [{a}, {b}) of {n} but {names[0]} rows "
                                             f"[{lay[0][0]}, {lay[0][1]}) of {lay[0][2]} [MPI rank {r}]"))
    n = layouts[0][0][2]
    expect = 0
    for r, lay in enumerate(layouts):
        a, b, nr = lay[0]
        if nr != n or a != expect:
            raise _collective(ShapeError(f"the row blocks do not tile [0, {n}) in rank order: MPI rank {r} owns "
                                         f"[{a}, {b}) of n = {nr}, expected to start at {expect} of n = {n}"))
        expect = b
    if expect != n:
        raise _collective(ShapeError(f"the row blocks do not tile [0, {n}): the ranks own {expect} rows in all"))


# ---------------------------------------------------------------------- vectors
def start_vector(start: int, stop: int, seed: int = 0) -> np.ndarray:
    """Entries ``start .. stop-1`` of a pseudo-random vector whose entry ``g`` depends only on ``g`` and ``seed``.

    SplitMix64 of the global index (vectorized with ``uint64``), mapped to ``[0.5, 1.5)``: the
    concatenation over any split of ``[0, n)`` is the same vector, so start vectors, and with them
    the eigensolvers' results, do not depend on the number of ranks.

    Parameters
    ----------
    start, stop : int
        The global index range.
    seed : int, optional
        Selects an independent vector.

    Returns
    -------
    (stop - start,) float array

    Examples
    --------
    >>> a = start_vector(0, 10, seed=3)
    >>> bool(np.array_equal(a, np.r_[start_vector(0, 4, seed=3), start_vector(4, 10, seed=3)]))
    True
    >>> bool(((a >= 0.5) & (a < 1.5)).all())
    True
    """
    with np.errstate(over="ignore"):
        z = (np.arange(start, stop, dtype=np.uint64) + np.uint64(1)) * np.uint64(0x9E3779B97F4A7C15)
        z = z + np.uint64((int(seed) * 0xD1B54A32D192ED03 + 0x632BE59BD9B4E019) % 2**64)
        z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
        z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
        z = z ^ (z >> np.uint64(31))
    return 0.5 + (z >> np.uint64(11)).astype(np.float64) * 2.0**-53


def scatter_values(x_owned: np.ndarray, start: int, stop: int, n: int, wanted: np.ndarray) -> np.ndarray:
    """The entries at global ids ``wanted`` of the distributed vector whose owned slice is ``x_owned`` (collective).

    Parameters
    ----------
    x_owned : (stop - start,) or (stop - start, k) float or complex array
        This rank's rows of the distributed vector (or block of vectors).
    start, stop, n : int
        This rank's rows and the global size; the ranks' blocks tile ``[0, n)`` in rank order.
    wanted : (m,) int array
        Global ids, any order, repeats allowed (e.g. the halo: the column ids of owned rows).

    Returns
    -------
    (m,) or (m, k) array
        ``x[wanted]``, with the dtype common to all ranks.

    Raises
    ------
    ShapeError
        On every rank, when on any rank ``x_owned`` does not have ``stop - start`` rows, an id is
        outside ``[0, n)``, or the ranks' blocks or trailing shapes disagree.

    Examples
    --------
    >>> scatter_values(np.array([[1, 2], [3, 4]]), 0, 2, 2, np.array([1, 1])).tolist()
    [[3, 4], [3, 4]]
    """
    x = np.asarray(x_owned)
    wanted = np.asarray(wanted, dtype=np.int64).ravel()

    def check():
        if x.ndim not in (1, 2) or x.shape[0] != stop - start:
            raise ShapeError(f"x_owned has shape {x.shape}, expected ({stop - start},) or ({stop - start}, k)")
        if wanted.size and (wanted.min() < 0 or wanted.max() >= n):
            bad = wanted[(wanted < 0) | (wanted >= n)][0]
            raise ShapeError(f"wanted id {bad} is outside [0, {n})")

    _agreeing(check)
    comm = _mpi()
    if comm is None or comm.size == 1:
        if start != 0 or stop != n:
            raise _collective(ShapeError(f"one process owns rows [{start}, {stop}) but n = {n}"))
        return x[wanted]
    lays = comm.allgather((int(start), int(stop), int(n), x.shape[1:], x.dtype.str))
    stops = np.array([lay[1] for lay in lays])
    if (any(lay[3] != x.shape[1:] or lay[2] != n for lay in lays) or lays[0][0] != 0 or stops[-1] != n
            or any(lays[r + 1][0] != lays[r][1] for r in range(len(lays) - 1))):
        raise _collective(ShapeError(f"scatter_values: the ranks' blocks {[lay[:3] for lay in lays]} and trailing "
                                     f"shapes {[lay[3] for lay in lays]} do not form one distributed vector"))
    dtype = np.result_type(*[np.dtype(lay[4]) for lay in lays])
    x = np.ascontiguousarray(x, dtype=dtype)
    width = int(np.prod(x.shape[1:], dtype=np.int64))
    uniq, inv = np.unique(wanted, return_inverse=True)
    owner = np.searchsorted(stops, uniq, side="right")
    send = np.bincount(owner, minlength=comm.size).astype(np.int64)
    recv = np.asarray(comm.alltoall(send.tolist()), dtype=np.int64)
    sdis, rdis = np.r_[0, np.cumsum(send)[:-1]], np.r_[0, np.cumsum(recv)[:-1]]
    asked = np.empty(int(recv.sum()), dtype=np.int64)
    comm.Alltoallv([uniq, (send, sdis)], [asked, (recv, rdis)])
    reply = np.ascontiguousarray(x[asked - start])
    got = np.empty((len(uniq),) + x.shape[1:], dtype=dtype)
    comm.Alltoallv([reply, (recv * width, rdis * width)], [got, (send * width, sdis * width)])
    return got[inv]


def gather_to_root(x_owned: np.ndarray, root: int = 0) -> np.ndarray | None:
    """The owned slices of all ranks concatenated in rank order on ``root``; ``None`` elsewhere (collective).

    Parameters
    ----------
    x_owned : (n_owned, ...) array
        This rank's rows.
    root : int, optional
        The receiving rank.

    Returns
    -------
    (n, ...) array or None

    Examples
    --------
    >>> gather_to_root(np.arange(3)).tolist()
    [0, 1, 2]
    """
    x = np.asarray(x_owned)
    comm = _mpi()
    if comm is None or comm.size == 1:
        return x.copy()
    parts = comm.gather(x, root=root)
    return np.concatenate(parts, axis=0) if comm.rank == root else None


# ---------------------------------------------------------------------- norms, shift, checks
def norm1_distributed(B: RowBlock) -> float:
    """``‖B‖₁`` of a Hermitian matrix as its largest row sum of moduli (an MPI max; collective).

    Parameters
    ----------
    B : RowBlock
        This rank's rows of a Hermitian matrix (for a non-Hermitian one this is ``‖B‖_∞``).

    Returns
    -------
    float

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> norm1_distributed(RowBlock.from_global(sp.csr_matrix([[1.0, -2.0], [-2.0, 1.0j]]), 0, 2))
    3.0
    """
    sums = np.bincount(B._rows(), weights=np.abs(B.data), minlength=B.n_owned)
    return float(_allreduce(float(sums.max()) if sums.size else 0.0, "max"))


def default_shift_distributed(A: RowBlock, M: RowBlock) -> float:
    """The shift ``ε`` of :func:`dhlb.linalg.eigen.default_shift` of the global pencil, from owned rows (collective).

    ``ε = sqrt(eps) ρ``, ``ρ = max_i s_i Σ_j |A_ij| s_j``, ``s = diag(M)^{-1/2}``: the halo of ``s``
    comes from :func:`scatter_values`, the row sums are taken in the same order as scipy's
    product in the one-process function (so the result is bitwise the same), then an MPI max.

    Parameters
    ----------
    A, M : RowBlock
        This rank's rows of the Hermitian pencil (same layout; ``M`` with a positive diagonal).

    Returns
    -------
    float

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> from dhlb.linalg.eigen import default_shift
    >>> A = sp.csr_matrix([[1.0, -1.0], [-1.0, 1.0]]); M = sp.identity(2, format="csr")
    >>> default_shift_distributed(RowBlock.from_global(A, 0, 2), RowBlock.from_global(M, 0, 2)) == default_shift(A, M)
    True
    """
    s = 1.0 / np.sqrt(M._diagonal().real)
    cols, inv = np.unique(A.indices, return_inverse=True)
    halo = scatter_values(s, M.start, M.stop, M.n, cols)
    local = sp.csr_matrix((np.abs(A.data), inv.astype(np.int64), A.indptr), shape=(A.n_owned, len(cols)))
    rows = s * (local @ halo) if A.n_owned else np.zeros(0)
    rho = float(_allreduce(float(rows.max()) if rows.size else 0.0, "max"))
    return float(np.sqrt(_EPS) * (rho if rho > 0 else 1.0))


def _hermitian_problem(B: RowBlock, Bp, name: str) -> str | None:
    """Where ``B − Bᴴ`` exceeds the relative tolerance in this rank's rows (``Bp`` its PETSc matrix), or ``None``."""
    from petsc4py import PETSc

    scale = float(_allreduce(float(np.abs(B.data).max()) if B.data.size else 0.0, "max"))
    D = Bp.duplicate(copy=True)
    D.hermitianTranspose(D)                                      # in place (petsc4py's default too)
    D.axpy(-1.0, Bp, structure=PETSc.Mat.Structure.DIFFERENT_NONZERO_PATTERN)   # D = Bᴴ − B
    ip, idx, val = D.getValuesCSR()
    bad = np.abs(val) > _HERMITIAN_RTOL * scale
    D.destroy()
    if not np.any(bad):
        return None
    i = int(np.flatnonzero(bad)[0])
    r = B.start + int(np.searchsorted(ip, i, side="right") - 1)
    c = int(idx[i])
    lo, hi = B.indptr[r - B.start], B.indptr[r - B.start + 1]
    j = lo + np.searchsorted(B.indices[lo:hi], c)
    b_rc = B.data[j] if j < hi and B.indices[j] == c else 0.0
    return (f"{name} is not Hermitian: {name}[{r}, {c}] = {b_rc} but conj({name}[{c}, {r}]) = "
            f"{b_rc + val[i]} (row {r})")


def check_hermitian_distributed(A: RowBlock, name: str = "A") -> None:
    """Raise :class:`~dhlb.errors.InvalidOperatorError` on every rank if ``A`` is not Hermitian (collective).

    ``|A − Aᴴ|`` (by PETSc's Hermitian transpose) must be at most ``1e-10`` times the largest
    ``|A_ij|``, entrywise, as in the one-process check; the message names the rank and the row.

    Parameters
    ----------
    A : RowBlock
        This rank's rows.
    name : str, optional
        The matrix's name in the message.

    Raises
    ------
    InvalidOperatorError
        When ``A`` is not Hermitian (on every rank).

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> B = RowBlock.from_global(sp.csr_matrix([[2.0, 1j], [-1j, 2.0]]), 0, 2)
    >>> check_hermitian_distributed(B) if petsc_available() else None
    """
    _validate_layout({name: A})
    Ap = petsc_matrix(A)
    problem = _hermitian_problem(A, Ap, name)
    _agree(None if problem is None else InvalidOperatorError(problem))


def _positive_diagonal_problem(M: RowBlock) -> DhlbError | None:
    d = M._diagonal()
    bad = d.real <= 0
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        g = M.start + i
        return InvalidOperatorError(f"M is not positive definite: M[{g}, {g}] = {d[i]} (row {g})")
    return None


# ---------------------------------------------------------------------- PETSc matrices
def petsc_matrix(B: RowBlock):
    """A distributed PETSc ``AIJ`` matrix from this rank's rows only (collective; complex scalars).

    Parameters
    ----------
    B : RowBlock
        This rank's rows; the ranks' blocks tile ``[0, n)`` in rank order, so PETSc's ownership
        range on this rank is ``[B.start, B.stop)``.

    Returns
    -------
    petsc4py.PETSc.Mat
        The assembled ``n × n`` matrix, ``B.stop − B.start`` local rows and columns.

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> B = RowBlock.from_global(sp.identity(3, format="csr"), 0, 3)
    >>> petsc_matrix(B).getOwnershipRange() if petsc_available() else (0, 3)
    (0, 3)
    """
    from petsc4py import PETSc

    nloc = B.n_owned
    csr = (np.asarray(B.indptr, dtype=PETSc.IntType), np.asarray(B.indices, dtype=PETSc.IntType),
           np.asarray(B.data, dtype=PETSc.ScalarType))
    P = PETSc.Mat().createAIJ(size=((nloc, B.n), (nloc, B.n)), csr=csr, comm=PETSc.COMM_WORLD)
    P.assemble()
    return P


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
    comm = _mpi()
    if comm is None or comm.size == 1:
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
    try:
        return _solve_eps(E, extra, Ap, Mp, A, k, eps, tol, maxiter, normA, normM, method, note)
    finally:  # free the factor (MUMPS) and the matrices now, not when the garbage collector runs
        for obj in (E, Ap, Mp):
            obj.destroy()


def _solve_eps(E, extra, Ap, Mp, A, k, eps, tol, maxiter, normA, normM, method, note) -> DistributedEigen:
    """Run the set-up eigensolver ``E`` (restarting from its vectors if η > tol); the result on every rank."""
    from petsc4py import PETSc

    ksp = E.getST().getKSP()
    what = f"A + εM (ε = {eps:.3g})"
    try:
        E.setUp()
    except PETSc.Error as err:
        raise _collective(_petsc_failure(err, ksp.getPC(), what, singular_hint=_NOT_PSD)) from err
    if method == "krylovschur" and extra["solver"] == "mumps" and (null := _null_pivots(ksp.getPC())):
        raise _collective(InvalidOperatorError(f"{what} is singular: MUMPS found {null} null pivot(s); "
                                               f"{_NOT_PSD}"))
    s0 = start_vector(A.start, A.stop, 0)
    X = np.column_stack([s0] + [start_vector(A.start, A.stop, j) for j in range(1, k)]).astype(np.complex128)
    iterations, t0, notes, solves0 = 0, time.perf_counter(), [note] if note else [], _ksp_solves()
    for attempt in range(1 + _RESTARTS):
        E.setTolerances(tol=float(tol), max_it=maxiter)
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
        lam, X, eta = _rayleigh_ritz(Ap, Mp, X, normA, normM)
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
        stats.update(_factor_stats(ksp, extra["solver"]))
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
