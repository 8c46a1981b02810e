"""Coefficient groups of discrete forms: Z, R, C, S¹ (as angles) and C* (nonzero complex).

Each group is a small stateless object that knows how its values are stored, validated,
combined, differentiated and paired with integer chains (see the table in
``docs/conventions.md``).  :class:`dhlb.forms.Cochain` delegates every group-dependent step
to these objects, so the cochain code itself is group-agnostic.

===== ============================== ============== ====================================
name  stored as                      group law      ``d``
===== ============================== ============== ====================================
Z     int64                          ``+``          ``d_k @ ω``
R     float64                        ``+``          ``d_k @ ω``
C     complex128                     ``+``          ``d_k @ ω``
S1    float64 angles in (−π, π]      ``+`` mod 2π   ``d_k @ ω`` wrapped into (−π, π]
C*    complex128, nonzero            ``×``          ``Π ω(face_i)^((−1)^i)``
===== ============================== ============== ====================================

Examples
--------
>>> import numpy as np
>>> from dhlb.forms.groups import get_group, wrap_angle
>>> get_group("s1").name, get_group("complex").name
('S1', 'C')
>>> wrap_angle(np.array([np.pi, -np.pi, 3 * np.pi / 2])).round(4).tolist()
[3.1416, 3.1416, -1.5708]
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from dhlb.errors import InvalidCochainError, NonFiniteError
from dhlb.topology._names import described_simplex as simplex_name  # (public here: "edge (7, 9)")

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["Group", "get_group", "wrap_angle", "GROUP_NAMES", "simplex_name", "DEFAULT_RTOL"]

TWO_PI = 2.0 * np.pi
#: relative tolerance used when a method is called with ``tol=None``
DEFAULT_RTOL = 1e-9


def wrap_angle(theta: ArrayLike) -> np.ndarray | float:
    """Representative of ``theta`` modulo 2π in the half-open interval (−π, π].

    Parameters
    ----------
    theta : float or array_like of float
        Angles in radians, any shape.

    Returns
    -------
    float or float64 array
        ``theta`` wrapped into (−π, π], of the shape of ``theta`` (a float for a scalar).

    Examples
    --------
    >>> wrap_angle(-np.pi) == np.pi
    True
    """
    t = np.asarray(theta, dtype=np.float64)
    w = t - TWO_PI * np.ceil((t - np.pi) / TWO_PI)
    w = np.where(w <= -np.pi, w + TWO_PI, w)
    w = np.where(w > np.pi, w - TWO_PI, w)
    return w if w.ndim else float(w)



class Group:
    """A coefficient group; subclasses implement the group-dependent steps."""

    name = ""
    dtype = np.float64
    additive = True
    identity = 0

    def __repr__(self) -> str:
        return f"Group({self.name!r})"

    # ------------------------------------------------------------------ validation
    def coerce(self, values, X, k: int) -> np.ndarray:
        """Validated values of a k-form on ``X`` as a fresh 1-D array of :attr:`dtype`."""
        n = X.n_simplices(k)
        try:
            arr = np.array(values)
        except (ValueError, TypeError) as exc:
            raise InvalidCochainError(
                f"values of a {k}-form must be a 1-D numeric array of length {n}: {exc}"
            ) from None
        if arr.ndim != 1 or arr.shape[0] != n:
            raise InvalidCochainError(
                f"values of a {k}-form must have shape ({n},) (one per {k}-simplex), got shape {arr.shape}"
            )
        if arr.dtype.kind == "b":
            arr = arr.astype(np.int64)
        if arr.dtype.kind not in "iufc":
            raise InvalidCochainError(
                f"values of a {k}-form must be numbers (int64/float/complex), got dtype {arr.dtype}"
                + (" (integers too large for int64, or non-numbers)" if arr.dtype == object else "")
            )
        if arr.dtype.kind in "fc":
            bad = ~np.isfinite(arr)
            if np.any(bad):
                i = int(np.argmax(bad))
                raise NonFiniteError(f"the value on the {simplex_name(X, k, i)} is {arr[i]}; values must be finite")
        return self._convert(arr, X, k)

    def _convert(self, arr: np.ndarray, X, k: int) -> np.ndarray:
        raise NotImplementedError

    @staticmethod
    def _require_real(arr: np.ndarray, X, k: int, hint: str = "") -> np.ndarray:
        if arr.dtype.kind == "c":
            bad = arr.imag != 0
            if np.any(bad):
                i = int(np.argmax(bad))
                raise InvalidCochainError(
                    f"the value on the {simplex_name(X, k, i)} is complex ({arr[i]}) but the group is real{hint}"
                )
            arr = arr.real
        return arr

    # ------------------------------------------------------------------ algebra
    def d(self, X, k: int, values: np.ndarray) -> np.ndarray:
        """Values of the exterior derivative ``d_k ω`` (length ``n_{k+1}``)."""
        if k + 1 > X.dim:
            return np.zeros(0, self.dtype)
        return np.asarray(X.boundary(k + 1).T @ values, dtype=self.dtype)

    def op(self, a, b):
        """The group law, elementwise."""
        return a + b

    def inv(self, a):
        """The group inverse, elementwise."""
        return -a

    def power(self, a, n):
        """``n``-fold group law of ``a`` with itself (integer ``n``)."""
        return n * a

    def pair(self, values: np.ndarray, coeffs: np.ndarray):
        """``Σ c_σ ω_σ`` in the group; ``coeffs`` has shape (n_k,) or (m, n_k)."""
        return coeffs @ values

    def distance(self, values) -> np.ndarray:
        """Distance of each value from the identity (the quantity compared with tolerances)."""
        return np.abs(values)

    def default_tol(self, values) -> float:
        """Tolerance used for ``tol=None``: :data:`DEFAULT_RTOL` times the size of the values."""
        v = np.asarray(values)
        return DEFAULT_RTOL * max(1.0, float(np.max(np.abs(v), initial=0.0)))


class _Integers(Group):
    name, dtype = "Z", np.int64

    def _convert(self, arr, X, k):
        arr = self._require_real(arr, X, k)
        if arr.dtype.kind == "u" and arr.size and arr.max() > np.iinfo(np.int64).max:
            i = int(np.argmax(arr))
            raise InvalidCochainError(f"the value on the {simplex_name(X, k, i)} does not fit into int64")
        if arr.dtype.kind == "f":
            bad = (arr != np.round(arr)) | (np.abs(arr) >= 2.0**62)
            if np.any(bad):
                i = int(np.argmax(bad))
                raise InvalidCochainError(
                    f"the value on the {simplex_name(X, k, i)} is {arr[i]!r}, not an integer; group Z needs integers"
                )
        return arr.astype(np.int64)

    def default_tol(self, values) -> float:
        return 0.0


class _Reals(Group):
    name, dtype = "R", np.float64

    def _convert(self, arr, X, k):
        return self._require_real(arr, X, k).astype(np.float64)


class _Complexes(Group):
    name, dtype = "C", np.complex128

    def _convert(self, arr, X, k):
        return arr.astype(np.complex128)


class _Circle(Group):
    """S¹ = R / 2πZ, stored as angles in (−π, π]."""

    name, dtype = "S1", np.float64

    def _convert(self, arr, X, k):
        hint = "; S1 values are angles: convert unit complex numbers with Cochain(..., group='C*').to_group('S1')"
        return np.asarray(wrap_angle(self._require_real(arr, X, k, hint)), dtype=np.float64).reshape(-1)

    def d(self, X, k, values):
        return np.asarray(wrap_angle(super().d(X, k, values)), np.float64).reshape(-1)

    def op(self, a, b):
        return wrap_angle(a + b)

    def inv(self, a):
        return wrap_angle(-a)

    def power(self, a, n):
        return wrap_angle(n * a)

    def pair(self, values, coeffs):
        return wrap_angle(coeffs @ values)

    def distance(self, values):
        return np.abs(wrap_angle(values))

    def default_tol(self, values) -> float:
        return DEFAULT_RTOL * np.pi


class _NonzeroComplexes(Group):
    r"""C* = C \ {0} under multiplication."""

    name, dtype, additive, identity = "C*", np.complex128, False, 1

    def _convert(self, arr, X, k):
        arr = arr.astype(np.complex128)
        bad = arr == 0
        if np.any(bad):
            i = int(np.argmax(bad))
            raise InvalidCochainError(f"the value on the {simplex_name(X, k, i)} is 0; group C* needs nonzero values")
        return arr

    def d(self, X, k, values):
        if k + 1 > X.dim:
            return np.zeros(0, np.complex128)
        vals = values[X.faces(k + 1)]
        return np.prod(vals[:, 0::2], axis=1) / np.prod(vals[:, 1::2], axis=1)

    def op(self, a, b):
        return a * b

    def inv(self, a):
        return 1.0 / a

    def power(self, a, n):
        return a ** int(n)

    def pair(self, values, coeffs):
        # Π ω^c through the principal logarithm (exp(2πi m) = 1 for integer c): no overflow
        # of intermediate products, and one vectorized product for many chains.
        return np.exp(coeffs @ np.log(values))

    def distance(self, values):
        return np.abs(np.log(values))

    def default_tol(self, values) -> float:
        v = np.asarray(values)
        return DEFAULT_RTOL * max(1.0, float(np.max(np.abs(np.log(np.abs(v))), initial=0.0)))


_GROUPS = {g.name: g for g in (_Integers(), _Reals(), _Complexes(), _Circle(), _NonzeroComplexes())}
_ALIASES = {
    "z": "Z", "int": "Z", "integer": "Z", "integers": "Z",
    "r": "R", "real": "R", "reals": "R", "float": "R",
    "c": "C", "complex": "C",
    "s1": "S1", "s": "S1", "s^1": "S1", "u1": "S1", "u(1)": "S1", "circle": "S1", "s¹": "S1",
    "c*": "C*", "cstar": "C*", "c_*": "C*", "complex*": "C*",
}  # fmt: skip
#: canonical names of the coefficient groups
GROUP_NAMES = tuple(_GROUPS)


def get_group(group: str | Group) -> Group:
    """The :class:`Group` for a name (case-insensitive; aliases such as ``"circle"``, ``"cstar"``).

    Parameters
    ----------
    group : str or Group
        A name in :data:`GROUP_NAMES` or an alias; a :class:`Group` is returned as it is.

    Returns
    -------
    Group
        The (shared, stateless) group object.

    Raises
    ------
    InvalidCochainError
        For an unknown name.

    Examples
    --------
    >>> g = get_group("circle")
    >>> g.name, get_group("CSTAR").name, get_group(g) is g
    ('S1', 'C*', True)
    """
    if isinstance(group, Group):
        return group
    key = _ALIASES.get(str(group).strip().lower())
    if key is None:
        raise InvalidCochainError(f"unknown coefficient group {group!r}; use one of {', '.join(GROUP_NAMES)}")
    return _GROUPS[key]
