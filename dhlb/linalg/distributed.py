"""Distributed linear algebra under MPI: every rank holds only its own rows of ``A`` and ``M``.

A global ``n × n`` sparse matrix is split into contiguous blocks of rows, ``[start, stop)`` on
rank ``r`` in rank order (a renumbered ordering; columns are global ids).  A :class:`RowBlock` is
one rank's block, handed to PETSc as a distributed ``AIJ`` matrix (:func:`petsc_matrix`) without
any rank ever holding the global matrix.  Every function that takes a :class:`RowBlock` (or an
owned slice of a vector) is *collective*: all ranks must call it.

Eigenpairs
    :func:`dhlb.linalg.distributed_eigen.distributed_eigenpairs` (SLEPc) works on these row blocks.

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

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

import dhlb.errors as _errors
from dhlb.errors import DhlbError, InvalidOperatorError, ShapeError
from dhlb.linalg.backends_petsc import (
    _aij,
    petsc_available,  # noqa: F401 -- the examples skip without PETSc
)

__all__ = ["RowBlock", "world", "check_hermitian_distributed", "default_shift_distributed", "gather_to_root",
           "norm1_distributed", "petsc_matrix", "row_layout", "scatter_values", "start_vector"]

_HERMITIAN_RTOL = 1e-10     # as dhlb.linalg._checks._check_hermitian
_EPS = np.finfo(float).eps


# ---------------------------------------------------------------------- MPI plumbing
class _SelfComm:
    """The communicator of a single process (no mpi4py): the mpi4py calls used here, without communication."""

    rank, size = 0, 1

    def bcast(self, obj, root=0):
        return obj

    def scatter(self, objs, root=0):
        return objs[0]

    def gather(self, obj, root=0):
        return [obj]

    def allreduce(self, obj, op=None):
        return obj

    def allgather(self, obj):
        return [obj]


def world():
    """``MPI.COMM_WORLD`` of mpi4py, or a one-process stand-in when mpi4py is not installed.

    Returns
    -------
    mpi4py.MPI.Comm or a stand-in with ``rank``, ``size``, ``bcast``, ``scatter``, ``gather``, ``allreduce``

    Examples
    --------
    >>> comm = world()
    >>> 0 <= comm.rank < comm.size
    True
    """
    try:
        from mpi4py import MPI
    except ImportError:
        return _SelfComm()
    return MPI.COMM_WORLD


def _size() -> int:
    comm = world()
    return comm.size


def _allreduce(value, op: str):
    comm = world()
    if comm.size == 1:
        return value
    from mpi4py import MPI

    return comm.allreduce(value, op={"sum": MPI.SUM, "max": MPI.MAX, "min": MPI.MIN}[op])


def _collective(err: DhlbError) -> DhlbError:
    err.mpi_collective = True  # raised on every rank: the abort hook prints it once (rank 0)
    return err


def _agree(err: DhlbError | None) -> None:
    """Raise the same typed error on every rank if ``err`` is set on any rank (the lowest such rank's)."""
    comm = world()
    size = comm.size
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
    comm = world()
    if comm.size == 1:
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
    comm = world()
    layouts = [tuple((B.start, B.stop, B.n) for B in blocks.values())]
    if comm.size > 1:
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
    comm = world()
    if comm.size == 1:
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
    comm = world()
    if comm.size == 1:
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
    return _aij(B.indptr, B.indices, B.data, B.n)
