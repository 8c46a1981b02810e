"""Memory of sparse factorizations: an estimate before the work, the memory available, the check.

A direct factorization of a matrix from a 2-D mesh needs ``O(n log n)`` memory and one from a
3-D mesh ``O(n^{4/3})``; on a large mesh it can exceed what the machine (or the process's limit)
allows, and SuperLU then fails from deep inside (``SystemError … gstrf``, "malloc fails").  Before
factorizing, :func:`check_factorization_memory` compares :func:`factor_bytes` with
:func:`available_bytes` and raises :class:`~dhlb.errors.InsufficientMemoryError` naming the size,
the estimate and what would fit.

The estimate is a model fitted to the nested-dissection factorizations of this package's
matrices (SuperLU, L and U stored in full, measured peak resident memory of the factorization):

* surface-like patterns (growth dimension < 2.2, see :func:`dhlb.linalg.pattern_dimension`):
  ``bytes ≈ s · 44 · n log₂ n`` with ``s`` the bytes per scalar (8 real, 16 complex);
* volume-like patterns: ``bytes ≈ s · 5 · n^{4/3} · (nnz/n)``.

The model is calibrated to overestimate (it is compared with measured factors in the tests): a
refusal should never be needed on a problem that would fit, but a factorization that the model
lets through can still fail, and that failure is reported the same way.

Examples
--------
>>> factor_bytes(1_000_000, 7_000_000, complex_=True, dimension=2.0) > 1e9   # a 1M-vertex surface: GBs
True
>>> available_bytes() > 0
True
"""

from __future__ import annotations

import math

from dhlb import _memory_errors as _memory
from dhlb.errors import InsufficientMemoryError

__all__ = ["InsufficientMemoryError", "available_bytes", "check_factorization_memory", "factor_bytes",
           "release_free_memory", "set_memory_limit"]

_LIMIT: int | None = None


def set_memory_limit(nbytes: int | None) -> None:
    """Pretend that at most ``nbytes`` are available (``None``: the machine's own figure).

    For tests and for users who share a machine: every later memory check (of a factorization, and every
    guard of a parameter that scales work, e.g. :func:`dhlb.mesh.ball_tet_mesh`'s ``n``) uses
    ``min(nbytes, available_bytes())``.  The environment variable ``DHLB_MEMORY_LIMIT`` (bytes,
    or with a suffix ``K``, ``M``, ``G``) does the same.

    Parameters
    ----------
    nbytes : int or None
        The number of bytes to pretend are at most available, or ``None`` to drop the limit set before.

    Examples
    --------
    >>> set_memory_limit(10**6); available_bytes() <= 10**6
    True
    >>> set_memory_limit(None)
    """
    global _LIMIT
    _LIMIT = None if nbytes is None else int(nbytes)
    _memory.set_limit(_LIMIT)


def _env_limit() -> int | None:
    return _memory.env_limit()


def available_bytes() -> int:
    """Bytes this process can still allocate: the least of free memory, cgroup and ``RLIMIT_AS`` room.

    The cgroup figure is the room under the memory limit (cgroup v2 ``memory.max``, v1
    ``memory.limit_in_bytes``) of the process's own cgroup and of every ancestor, less the usage without
    the reclaimable file cache; the ``RLIMIT_AS`` figure (``ulimit -v``, as batch schedulers set it) is the
    limit less the address space in use (``VmSize``). A limit set by :func:`set_memory_limit` or
    ``DHLB_MEMORY_LIMIT`` counts as one more figure. Every memory guard of dhlb uses these figures
    (they are read in one place, the private module ``dhlb._memory_errors``).

    Returns
    -------
    int
        The least of the figures that can be read here, at least 0; ``2**62`` when none can.

    Examples
    --------
    >>> isinstance(available_bytes(), int)
    True
    """
    have = _memory.available_bytes()
    return have if _LIMIT is None else max(0, min(have, _LIMIT))


def factor_bytes(n: int, nnz: int, *, complex_: bool, dimension: float, triangles: int = 2) -> int:
    """Model of the peak bytes of a nested-dissection SuperLU factorization (see module docstring).

    Parameters
    ----------
    n, nnz : int
        Size and nonzeros of the matrix.
    complex_ : bool
        Complex scalars (16 bytes) or real (8).
    dimension : float
        Growth dimension of the matrix graph (:func:`dhlb.linalg.pattern_dimension`).
    triangles : {2, 1}
        2 for an LU factorization that stores L and U (SuperLU), 1 for a Cholesky factor.

    Examples
    --------
    >>> factor_bytes(10_000, 70_000, complex_=False, dimension=2.0) < factor_bytes(10_000, 70_000,
    ...                                                                          complex_=True, dimension=2.0)
    True
    """
    s = (16 if complex_ else 8) * triangles / 2
    n = max(int(n), 2)
    if dimension < 2.2:
        return int(s * 44 * n * math.log2(n))
    return int(s * 5 * n ** (4 / 3) * max(nnz / n, 1.0))


def check_factorization_memory(n: int, nnz: int, *, complex_: bool, dimension, backend: str,
                               alternatives=(), triangles: int = 2) -> int:
    """Raise :class:`InsufficientMemoryError` if the factorization would not fit; return the estimate.

    ``dimension`` may be a callable (computed only when the problem is large enough to matter, and
    then only when a volume's fill would not fit: the estimate returned is then that bound);
    ``alternatives`` names the backends that would fit (e.g. ``("amg-lobpcg",)``), for the message.

    Examples
    --------
    >>> check_factorization_memory(100, 700, complex_=False, dimension=2.0, backend="superlu") > 0
    True
    """
    if n < 20_000 and _LIMIT is None and _env_limit() is None:  # small: never the problem, skip the look-ups
        return factor_bytes(n, nnz, complex_=complex_, dimension=2.0, triangles=triangles)
    have = available_bytes()
    if callable(dimension):
        worst = factor_bytes(n, nnz, complex_=complex_, dimension=3.0, triangles=triangles)
        if worst <= have:   # fits even with a volume's fill: the pattern's dimension is not needed
            return worst
    d = dimension() if callable(dimension) else dimension
    need = factor_bytes(n, nnz, complex_=complex_, dimension=d, triangles=triangles)
    if need > have:
        alt = (f"; the iterative backend {', '.join(map(repr, alternatives))} needs O(n) memory and would fit"
               if alternatives else "; an iterative backend needs O(n) memory: pip install pyamg, then "
               "backend='amg-lobpcg'")
        raise InsufficientMemoryError(
            f"a {backend} factorization of this {n:,}-unknown {'complex' if complex_ else 'real'} matrix "
            f"({nnz:,} nonzeros, a {'surface' if d < 2.2 else 'volume'}-like pattern) needs about "
            f"{need / 2**30:.2f} GiB, but only {have / 2**30:.2f} GiB are available{alt}",
            needed=need, available=have)
    return need


TRIM_MIN = 100_000
"""From this many unknowns on, a factorization returns freed memory to the system (:func:`release_free_memory`)."""


def release_free_memory() -> bool:
    """Return the memory Python has freed to the operating system, so that it no longer counts as resident.

    A large factor is allocated by ``mmap`` outside the heap, so the holes that freed arrays leave in
    the heap (glibc keeps them for reuse; an array below its adaptive ``mmap`` threshold of up to
    32 MiB lives there) stay resident beside it.  This runs a garbage collection, then glibc's
    ``malloc_trim(0)``.  Measured before the factorization of the 1.31M-face icosphere's cross
    field: 650 MiB given back in 0.1 s.  Elsewhere (macOS, Windows, musl) it only collects.

    Returns
    -------
    bool
        Whether ``malloc_trim`` ran.

    Examples
    --------
    >>> isinstance(release_free_memory(), bool)
    True
    """
    import gc

    gc.collect()
    trim = _malloc_trim()
    return bool(trim is not None and trim(0) is not None)


def _malloc_trim():
    """The C library's ``malloc_trim`` (glibc), or None where it has none."""
    import ctypes
    import sys

    if not sys.platform.startswith("linux"):
        return None
    try:
        return ctypes.CDLL(None).malloc_trim
    except (OSError, AttributeError):   # musl: no malloc_trim
        return None
