"""The three coefficient fields of discrete vector bundles: R, C (floating point) and GF(p) (exact).

:func:`field_ops` turns a field specification (``"R"``, ``"C"`` or ``("GF", p)``) into an
object with one uniform set of batched operations, so that the bundle code is written once.
Floating-point fields compare with an absolute tolerance relative to ``max(1, |entries|)``;
GF(p) compares exactly.

Examples
--------
>>> import numpy as np
>>> F = field_ops(("GF", 3))
>>> F.name, F.exact
("('GF', 3)", True)
>>> F.nullspace(np.array([[1, 1]])).T.tolist()
[[2, 1]]
"""

from __future__ import annotations

import numpy as np

from dhlb.bundles import finite_field as ff
from dhlb.errors import InvalidConnectionError, NonFiniteError

__all__ = ["field_ops", "RealOps", "ComplexOps", "PrimeFieldOps"]


class _FloatOps:
    exact = False
    dtype: type = np.float64
    name = "R"

    def __init__(self, atol: float = 1e-9):
        self.atol = float(atol)

    @property
    def spec(self):
        return self.name

    def asarray(self, values, what: str = "values") -> np.ndarray:
        arr = np.asarray(values)
        if arr.dtype == object or not (np.issubdtype(arr.dtype, np.number) or arr.dtype == bool):
            raise InvalidConnectionError(f"{what} must be numeric arrays, got dtype {arr.dtype}")
        if self.dtype is np.float64 and np.iscomplexobj(arr):
            if np.any(arr.imag != 0):
                raise InvalidConnectionError(f"{what} of a real bundle must be real; use field='C'")
            arr = arr.real
        arr = arr.astype(self.dtype)
        if not np.all(np.isfinite(arr)):
            raise NonFiniteError(f"{what} contain NaN or infinity")
        return arr

    def eye(self, K: int) -> np.ndarray:
        return np.eye(K, dtype=self.dtype)

    def matmul(self, A, B) -> np.ndarray:
        return np.matmul(A, B)

    def inv(self, A) -> tuple[np.ndarray, np.ndarray]:
        """Batched inverse and a mask of (numerically) singular matrices."""
        A = np.asarray(A, dtype=self.dtype)
        if A.shape[-1] == 1:
            a = A[..., 0, 0]
            bad = np.abs(a) <= 1e-14 * np.maximum(1.0, np.abs(a))
            safe = np.where(bad, 1, a)
            return (1.0 / safe)[..., None, None].astype(self.dtype), bad
        s = np.linalg.svd(A, compute_uv=False)
        bad = s[..., -1] <= 1e-13 * s[..., 0]
        safe = np.where(bad[..., None, None], np.eye(A.shape[-1], dtype=self.dtype), A)
        return np.linalg.inv(safe), bad

    def close(self, A, B) -> np.ndarray:
        """Bool per batch element: ``A ≈ B`` entrywise (last two axes)."""
        diff = np.abs(np.asarray(A) - np.asarray(B))
        scale = np.maximum(1.0, np.maximum(np.abs(A), np.abs(B)))
        return np.all(diff <= self.atol * scale, axis=(-2, -1))

    def nullspace(self, A) -> np.ndarray:
        """Orthonormal basis (columns) of the numerical kernel of one matrix."""
        A = np.asarray(A, dtype=self.dtype)
        n = A.shape[1]
        if A.shape[0] == 0:
            return np.eye(n, dtype=self.dtype)
        # full V only when there are fewer rows than columns (else V is square anyway):
        # full U would cost (rows)^2 memory on large loop-generator systems
        _, s, vh = np.linalg.svd(A, full_matrices=A.shape[0] < n)
        tol = self.atol * max(1.0, float(s[0]) if s.size else 1.0)
        rank = int(np.sum(s > tol))
        return vh[rank:].conj().T.astype(self.dtype)

    def is_invertible(self, A) -> bool:
        s = np.linalg.svd(np.asarray(A), compute_uv=False)
        return bool(s[-1] > 1e-8 * max(1.0, s[0]))

    def random(self, shape, rng: np.random.Generator) -> np.ndarray:
        return rng.standard_normal(shape).astype(self.dtype)

    def unitary_defect(self, A) -> np.ndarray:
        """Per batch element ``max |AᴴA − I|``."""
        A = np.asarray(A)
        G = np.conj(np.swapaxes(A, -1, -2)) @ A
        return np.max(np.abs(G - np.eye(A.shape[-1])), axis=(-2, -1))


class RealOps(_FloatOps):
    """Operations over R (float64)."""

    dtype = np.float64
    name = "R"


class ComplexOps(_FloatOps):
    """Operations over C (complex128)."""

    dtype = np.complex128
    name = "C"

    def random(self, shape, rng: np.random.Generator) -> np.ndarray:
        """Random complex matrices of the given shape (standard normal real and imaginary parts)."""
        return rng.standard_normal(shape) + 1j * rng.standard_normal(shape)


class PrimeFieldOps:
    """Exact operations over GF(p) (int64 in ``0 .. p-1``)."""

    exact = True
    dtype = np.int64

    def __init__(self, p: int):
        self.p = ff.check_prime(p)
        self.atol = 0.0

    @property
    def name(self) -> str:
        """The field's name, ``"('GF', p)"``."""
        return str(("GF", self.p))

    @property
    def spec(self):
        """The field specification ``("GF", p)`` accepted by :func:`field_ops`."""
        return ("GF", self.p)

    def asarray(self, values, what: str = "values") -> np.ndarray:
        """Validated int64 array of ``values`` reduced mod p (``what`` names them in errors)."""
        arr = np.asarray(values)
        if arr.dtype == bool:
            arr = arr.astype(np.int64)
        if not np.issubdtype(arr.dtype, np.integer):
            if np.issubdtype(arr.dtype, np.floating) and np.all(np.isfinite(arr)) and np.all(arr == np.round(arr)):
                arr = arr.astype(np.int64)
            else:
                raise InvalidConnectionError(f"{what} over GF({self.p}) must be integers")
        return arr.astype(np.int64) % self.p

    def eye(self, K: int) -> np.ndarray:
        """The K×K identity matrix (int64)."""
        return np.eye(K, dtype=np.int64)

    def matmul(self, A, B) -> np.ndarray:
        """Batched matrix product mod p."""
        return ff.matmul_mod(A, B, self.p)

    def inv(self, A) -> tuple[np.ndarray, np.ndarray]:
        """Batched inverse mod p and a mask of singular matrices."""
        return ff.inv_mod(A, self.p)

    def close(self, A, B) -> np.ndarray:
        """Bool per batch element: ``A == B`` mod p (last two axes)."""
        return np.all((np.asarray(A) - np.asarray(B)) % self.p == 0, axis=(-2, -1))

    def nullspace(self, A) -> np.ndarray:
        """A basis (columns) of the kernel of one matrix mod p."""
        return ff.nullspace_mod(A, self.p)

    def is_invertible(self, A) -> bool:
        """True if the square matrix ``A`` is invertible mod p."""
        return not bool(ff.inv_mod(A, self.p)[1])

    def random(self, shape, rng: np.random.Generator) -> np.ndarray:
        """Uniformly random matrices with entries in ``0 .. p-1``."""
        return rng.integers(0, self.p, size=shape, dtype=np.int64)

    def unitary_defect(self, A):  # pragma: no cover - guarded by the bundle constructor
        """Not defined over GF(p): always raises :class:`~dhlb.errors.InvalidConnectionError`."""
        raise InvalidConnectionError("metric=True is only meaningful over R or C")


def field_ops(field, atol: float = 1e-9):
    """Operations object for ``"R"``, ``"C"`` or ``("GF", p)``.

    Examples
    --------
    >>> field_ops("C").dtype
    <class 'numpy.complex128'>
    """
    if isinstance(field, (RealOps, ComplexOps, PrimeFieldOps)):
        return field
    if isinstance(field, str):
        if field.upper() == "R":
            return RealOps(atol)
        if field.upper() == "C":
            return ComplexOps(atol)
    if isinstance(field, (tuple, list)) and len(field) == 2 and str(field[0]).upper() in ("GF", "F"):
        return PrimeFieldOps(field[1])
    raise InvalidConnectionError(f"unknown field {field!r}: use 'R', 'C' or ('GF', p) with p prime")
