"""Integer k-chains of a simplicial complex, and validation of chain arguments.

A k-chain is one integer coefficient per canonically oriented k-simplex, in the row order of
``X.simplices(k)``; the boundary is ``∂_k`` (``X.boundary(k)``).  Chains are what discrete forms
are integrated over (:meth:`dhlb.forms.Cochain.pair`).
"""

from __future__ import annotations

import numbers
from typing import TYPE_CHECKING

import numpy as np

from dhlb.errors import InvalidCochainError, NotAPathError, SimplexNotFoundError

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from dhlb.topology.complex import SimplicialComplex

__all__ = ["Chain"]


def _same_complex(X, Y) -> bool:
    return X is Y or X == Y


def _check_complex(X):
    from dhlb.topology.complex import SimplicialComplex

    if not isinstance(X, SimplicialComplex):
        raise InvalidCochainError(f"forms and chains live on a SimplicialComplex, got {type(X).__name__}")
    return X


def _as_rows(rows) -> np.ndarray:
    try:
        arr = np.asarray(rows)
    except ValueError:
        arr = np.zeros(0)
    if arr.ndim != 2 or arr.shape[0] == 0 or arr.dtype.kind not in "iu":
        raise InvalidCochainError("rows must be a non-empty list of integer vertex tuples of equal length")
    return arr


def _check_degree(k) -> int:
    if not isinstance(k, numbers.Integral) or isinstance(k, bool) or k < 0:
        raise InvalidCochainError(f"the degree k of a form or chain must be a non-negative integer, got {k!r}")
    return int(k)


def _coefficients(chain, X, k, integer: bool) -> np.ndarray:
    """Coefficient array of a chain argument, validated against the complex and degree."""
    if isinstance(chain, Chain):
        if chain.k != k or not _same_complex(chain.complex, X):
            raise InvalidCochainError(f"cannot pair a {k}-form with a {chain.k}-chain or a chain on another complex")
        return chain.coefficients
    try:
        c = np.asarray(chain)
    except ValueError:  # ragged nested lists
        c = np.zeros((0, 0, 0))
    n = X.n_simplices(k)
    if c.ndim not in (1, 2) or c.shape[-1] != n or c.dtype.kind not in "biuf":
        raise InvalidCochainError(f"a {k}-chain is a numeric array of shape ({n},) or (m, {n}); got {c.shape}")
    if c.dtype.kind == "f":
        if not np.all(np.isfinite(c)):
            raise InvalidCochainError("chain coefficients must be finite")
        if integer:
            if np.any(c != np.round(c)):
                raise InvalidCochainError(
                    "this group needs integer chain coefficients (S1, C*, Z are not real vector spaces)"
                )
            c = c.astype(np.int64)
    return c.astype(np.int64) if c.dtype.kind in "bu" else c


class Chain:
    """An integer k-chain: one coefficient per canonically oriented k-simplex.

    Parameters
    ----------
    X : SimplicialComplex
        The complex.
    k : int >= 0
        The degree.
    coefficients : (n_k,) int array_like or Chain
        One integer per row of ``X.simplices(k)`` (floats with integer values are accepted), or
        a k-chain on ``X``. Kept as a read-only int64 array (:attr:`coefficients`).

    Raises
    ------
    InvalidCochainError
        ``X`` is not a :class:`~dhlb.topology.complex.SimplicialComplex`, ``k`` is not a
        non-negative integer, or ``coefficients`` is not a 1-D array of ``n_k`` finite integer
        values (or a chain of another degree or on another complex).

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1, 2)])
    >>> c = Chain.from_simplices(X, [(2, 1, 0)])        # the triangle, negatively oriented
    >>> c.coefficients.tolist(), c.boundary().coefficients.tolist()
    ([-1], [-1, 1, -1])
    """

    def __init__(self, X: SimplicialComplex, k: int, coefficients: ArrayLike):
        self._X, self._k = _check_complex(X), _check_degree(k)
        c = _coefficients(coefficients, X, self._k, integer=True)
        if c.ndim != 1:
            raise InvalidCochainError("a Chain holds a single chain; pass a 1-D coefficient array")
        c = np.array(c, dtype=np.int64)
        c.setflags(write=False)
        self._c = c

    @classmethod
    def from_simplices(cls, X: SimplicialComplex, rows: ArrayLike, coefficients: ArrayLike | None = None) -> Chain:
        """Σ c_i σ_i over oriented simplices given as vertex tuples (input labels, any order)."""
        arr = _as_rows(rows)
        _check_complex(X)
        k = arr.shape[1] - 1
        coeff = np.ones(arr.shape[0], np.int64) if coefficients is None else np.asarray(coefficients)
        if coeff.shape != (arr.shape[0],) or coeff.dtype.kind not in "biu":
            raise InvalidCochainError(f"need one integer coefficient per simplex ({arr.shape[0]}), got {coeff.shape}")
        out = np.zeros(X.n_simplices(k), np.int64)
        np.add.at(out, X.index(k, arr), X.orientation_of(arr) * coeff)
        return cls(X, k, out)

    @classmethod
    def path(cls, X: SimplicialComplex, vertices: ArrayLike) -> Chain:
        """The 1-chain of the edge path ``v0 → v1 → …`` (input labels); repeat v0 to close it.

        Raises
        ------
        NotAPathError
            If two consecutive vertices are not joined by an edge (the message names them).

        Examples
        --------
        >>> from dhlb import SimplicialComplex
        >>> X = SimplicialComplex([(0, 1, 2)])
        >>> c = Chain.path(X, [0, 2, 1, 0])            # edges (0,1), (0,2), (1,2)
        >>> c.coefficients.tolist(), c.is_cycle()
        ([-1, 1, -1], True)
        """
        _check_complex(X)
        v = np.asarray(vertices)
        if v.ndim != 1 or v.size < 2 or v.dtype.kind not in "iu":
            raise NotAPathError("a path is a sequence of at least two integer vertex labels")
        steps = np.stack([v[:-1], v[1:]], axis=1)
        if np.any(steps[:, 0] == steps[:, 1]):
            i = int(np.argmax(steps[:, 0] == steps[:, 1]))
            raise NotAPathError(
                f"step {i} of the path stays at vertex {int(steps[i, 0])}; consecutive vertices must differ"
            )
        ok = X.contains(1, steps) if X.dim >= 1 else np.zeros(len(steps), bool)
        if not np.all(ok):
            i = int(np.argmin(ok))
            raise NotAPathError(
                f"step {i} of the path, {int(steps[i, 0])} → {int(steps[i, 1])}, is not an edge of the complex"
            )
        try:
            return cls.from_simplices(X, steps)
        except SimplexNotFoundError as exc:  # pragma: no cover - guarded by contains() above
            raise NotAPathError(str(exc)) from None

    @property
    def complex(self) -> SimplicialComplex:
        """The simplicial complex the chain lives on."""
        return self._X

    @property
    def k(self) -> int:  # noqa: D102 (a docstring makes Sphinx links to "k" in shapes ambiguous with Cochain.k)
        return self._k

    @property
    def coefficients(self) -> np.ndarray:
        """Integer coefficients, one per k-simplex (read-only)."""
        return self._c

    def boundary(self) -> Chain:
        """∂c, a (k−1)-chain (for k = 0: the empty chain of degree 0 is not defined; raises)."""
        if self._k == 0:
            raise InvalidCochainError("the boundary of a 0-chain is not a chain of this complex (∂_0 = 0)")
        return Chain(self._X, self._k - 1, self._X.boundary(self._k) @ self._c)

    def is_cycle(self) -> bool:
        """True if ∂c = 0 (every 0-chain is a cycle)."""
        return self._k == 0 or not np.any(self._X.boundary(self._k) @ self._c)

    def __add__(self, other):
        if not isinstance(other, Chain) or other._k != self._k or not _same_complex(self._X, other._X):
            raise InvalidCochainError("can only add chains of the same degree on the same complex")
        return Chain(self._X, self._k, self._c + other._c)

    def __neg__(self):
        return Chain(self._X, self._k, -self._c)

    def __sub__(self, other):
        return self + (-other)

    def __rmul__(self, n):
        if not isinstance(n, numbers.Integral):
            raise InvalidCochainError(f"chains have integer coefficients; cannot multiply by {n!r}")
        return Chain(self._X, self._k, int(n) * self._c)

    def __repr__(self) -> str:
        return f"Chain(k={self._k}, support={int(np.count_nonzero(self._c))})"
