"""Discrete k-forms (cochains) with coefficients in Z, R, C, S¹ or C*.

A discrete k-form is a homomorphism from k-chains to a coefficient group (seed, Definition 5):
one group element per canonically oriented k-simplex, in the row order of
``X.simplices(k)``.  The exterior derivative is ``d_k = ∂_{k+1}ᵀ`` written in the group law,
so Stokes' theorem ``⟨dω, c⟩ = ⟨ω, ∂c⟩`` holds by construction.
"""

from __future__ import annotations

import importlib
import numbers
import warnings
from typing import TYPE_CHECKING

import numpy as np

from dhlb.errors import InvalidCochainError
from dhlb.forms.chain import Chain, _as_rows, _check_complex, _check_degree, _coefficients, _same_complex
from dhlb.forms.groups import Group, get_group

if TYPE_CHECKING:
    from typing import Any

    from numpy.typing import ArrayLike

    from dhlb.topology.complex import SimplicialComplex

__all__ = ["Cochain", "Chain"]

# conversions allowed by Cochain.to_group: (source, target) -> function of the stored values
_CONVERSIONS = {
    ("Z", "R"): lambda v: v.astype(np.float64),
    ("Z", "C"): lambda v: v.astype(np.complex128),
    ("R", "C"): lambda v: v.astype(np.complex128),
    ("R", "S1"): lambda v: v,  # wrapped by the S1 constructor
    ("S1", "C*"): lambda v: np.exp(1j * v),
    ("C*", "S1"): lambda v: np.angle(v),
}


class Cochain:
    """A discrete k-form on a simplicial complex with values in a coefficient group.

    Parameters
    ----------
    X : SimplicialComplex
    k : int
        Degree; the form has one value per k-simplex (``X.simplices(k)`` row order).
    values : array_like, shape (n_k,)
        The values on the canonically oriented k-simplices.
    group : {"Z", "R", "C", "S1", "C*"}
        Coefficient group (aliases such as ``"circle"`` are accepted).  S¹ values are
        angles and are stored wrapped into (−π, π]; C* values are nonzero complex numbers.

    Raises
    ------
    InvalidCochainError
        Wrong length, non-integers for Z, complex values for a real group, zeros for C*,
        unknown group.
    NonFiniteError
        NaN or infinite values.  The messages name the offending simplex.

    Notes
    -----
    Group law: ``+``/``-`` for Z, R, C and S¹ (angle addition, wrapped); ``*``/``/`` for C*.
    ``n * ω`` is the n-fold sum (integer ``n``; any scalar for R and C) and ``ω ** n`` the
    n-th power in C*.  The generic law is :meth:`op` / :meth:`inverse`.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb import SimplicialComplex
    >>> from dhlb.forms import Cochain
    >>> X = SimplicialComplex([(0, 1, 2)])
    >>> f = Cochain(X, 0, [0.0, 1.0, 3.0])
    >>> f.d().values.tolist()                   # edges (0,1), (0,2), (1,2)
    [1.0, 3.0, 2.0]
    >>> f.d().d().values.tolist()
    [0.0]
    >>> g = Cochain(X, 0, [1, 2j, 4], group="C*")
    >>> g.d().values.tolist()                   # g_j / g_i on the edge (i, j)
    [2j, (4+0j), -2j]
    >>> Cochain(X, 1, [4.0, np.pi, -np.pi], group="S1").values.round(4).tolist()  # (−π, π]
    [-2.2832, 3.1416, 3.1416]
    """

    __array_ufunc__ = None  # keep numpy from broadcasting over a Cochain

    def __init__(self, X: SimplicialComplex, k: int, values: ArrayLike, group: str | Group = "R"):
        self._X = _check_complex(X)
        self._k = _check_degree(k)
        self._group = get_group(group)
        vals = self._group.coerce(values, X, self._k)
        vals.setflags(write=False)
        self._values = vals

    @classmethod
    def _wrap(cls, X, k, values, group: Group) -> Cochain:
        """Trusted constructor (values already converted by the group)."""
        out = cls.__new__(cls)
        out._X, out._k, out._group = X, k, group
        vals = np.array(values, dtype=group.dtype).reshape(-1)
        vals.setflags(write=False)
        out._values = vals
        return out

    @classmethod
    def identity(cls, X: SimplicialComplex, k: int, group: str | Group = "R") -> Cochain:
        """The identity form: 0 for additive groups, 1 for C*.

        Examples
        --------
        >>> from dhlb import SimplicialComplex
        >>> Cochain.identity(SimplicialComplex([(0, 1)]), 1, "C*").values.tolist()
        [(1+0j)]
        """
        g = get_group(group)
        return cls._wrap(_check_complex(X), _check_degree(k), np.full(X.n_simplices(k), g.identity, dtype=g.dtype), g)

    @classmethod
    def from_simplices(
        cls, X: SimplicialComplex, rows: ArrayLike, values: ArrayLike, group: str | Group = "R"
    ) -> Cochain:
        """A form given on some oriented k-simplices (input labels, vertices in any order).

        A simplex listed against its canonical orientation gets the inverse value; simplices
        not listed get the identity; listing a simplex twice is an error.

        Examples
        --------
        >>> from dhlb import SimplicialComplex
        >>> X = SimplicialComplex([(0, 1, 2)])
        >>> Cochain.from_simplices(X, [(1, 0), (1, 2)], [0.5, 2.0]).values.tolist()
        [-0.5, 0.0, 2.0]
        """
        g = get_group(group)
        arr = _as_rows(rows)
        k = arr.shape[1] - 1
        _check_complex(X)
        idx = X.index(k, arr)
        sign = X.orientation_of(arr)
        vals = np.asarray(values)
        if vals.shape != (arr.shape[0],):
            raise InvalidCochainError(f"got {arr.shape[0]} simplices but values of shape {vals.shape}")
        uniq, counts = np.unique(idx, return_counts=True)
        if np.any(counts > 1):
            twice = tuple(int(v) for v in arr[np.argmax(idx == uniq[counts > 1][0])])
            raise InvalidCochainError(f"the {k}-simplex {twice} is listed twice")
        if vals.dtype.kind not in "biufc":
            raise InvalidCochainError(f"values must be numbers, got dtype {vals.dtype}")
        full = np.full(X.n_simplices(k), g.identity, dtype=np.result_type(vals.dtype, np.int64))
        full[idx] = vals
        base = g.coerce(full, X, k)  # validates (names the simplex) and converts
        flip = idx[sign < 0]
        base[flip] = g.inv(base[flip])
        return cls._wrap(X, k, base, g)

    # ------------------------------------------------------------------ attributes
    @property
    def complex(self) -> SimplicialComplex:
        """The simplicial complex the form lives on."""
        return self._X

    @property
    def k(self) -> int:
        """The degree."""
        return self._k

    @property
    def group(self) -> str:
        """Name of the coefficient group: ``"Z"``, ``"R"``, ``"C"``, ``"S1"`` or ``"C*"``."""
        return self._group.name

    @property
    def values(self) -> np.ndarray:
        """The values, one per k-simplex (read-only array; S¹: angles in (−π, π])."""
        return self._values

    def __len__(self) -> int:
        return self._values.size

    def __repr__(self) -> str:
        return f"Cochain(k={self._k}, group={self.group!r}, n={self._values.size})"

    # ------------------------------------------------------------------ calculus
    def d(self) -> Cochain:
        """The exterior derivative ``d_k ω``, a (k+1)-form in the same group."""
        return Cochain._wrap(self._X, self._k + 1, self._group.d(self._X, self._k, self._values), self._group)

    def pair(self, chain: Chain | ArrayLike) -> Any:
        """``∫_c ω = ⟨ω, c⟩`` in the group (S¹: wrapped angle; C*: ``Π ω_σ^{c_σ}``).

        ``chain`` is a :class:`Chain` or an array of coefficients of shape (n_k,) — or
        (m, n_k) for m chains at once.  Coefficients must be integers except for R and C.

        Examples
        --------
        >>> from dhlb import SimplicialComplex
        >>> X = SimplicialComplex([(0, 1, 2)])
        >>> w = Cochain(X, 1, [1.0, 2.0, 4.0])
        >>> w.pair(Chain.path(X, [0, 1, 2, 0]))     # 1 + 4 - 2
        3.0
        """
        c = _coefficients(chain, self._X, self._k, integer=self._group.name not in ("R", "C"))
        out = self._group.pair(self._values, c)
        out = np.asarray(out)
        return out.item() if out.ndim == 0 else out

    __call__ = pair

    def is_closed(self, tol: float | None = None) -> bool:
        """True if ``dω`` is the identity up to ``tol`` (default: relative 1e-9; exact for Z).

        Examples
        --------
        >>> from dhlb import SimplicialComplex
        >>> X = SimplicialComplex([(0, 1, 2)])
        >>> Cochain(X, 1, [1.0, 1.0, 0.0]).is_closed(), Cochain(X, 1, [1.0, 0.0, 0.0]).is_closed()
        (True, False)
        >>> Cochain(X, 1, [3.0, -3.0, 2 * np.pi - 6.0], "S1").is_closed()   # dω = 2π·(−1) ≡ 0
        True
        """
        dw = self._group.d(self._X, self._k, self._values)
        tol = self._group.default_tol(self._values) if tol is None else tol
        return bool(np.all(self._group.distance(dw) <= tol))

    def is_exact(self, tol: float | None = None) -> bool:
        """True if ``ω = dα`` for a (k−1)-form α in the same group (deprecated).

        .. deprecated:: 0.2.0
            Use ``dhlb.forms.is_exact(ω, tol)``: exactness is a solve (:func:`dhlb.forms.solve_d`),
            which lives above this module.

        Warns
        -----
        DeprecationWarning
            Always; the answer is that of :func:`dhlb.forms.is_exact`.
        """
        warnings.warn("Cochain.is_exact() is deprecated; use dhlb.forms.is_exact(omega, tol)",
                      DeprecationWarning, stacklevel=2)
        # resolved at call time: forms.solve imports this module, so a static import would be a circle
        return importlib.import_module("dhlb.forms.solve").is_exact(self, tol=tol)

    # ------------------------------------------------------------------ group structure
    def _check_compatible(self, other) -> None:
        if not isinstance(other, Cochain):
            raise InvalidCochainError(f"cannot combine a Cochain with {type(other).__name__}")
        if other._k != self._k or other._group is not self._group:
            raise InvalidCochainError(
                f"cannot combine a {self._k}-form in {self.group} with a {other._k}-form in {other.group}"
            )
        if not _same_complex(self._X, other._X):
            raise InvalidCochainError("cannot combine forms on different simplicial complexes")

    def op(self, other: Cochain) -> Cochain:
        """The group law (``+`` or ``×``), valuewise."""
        self._check_compatible(other)
        return Cochain._wrap(self._X, self._k, self._group.op(self._values, other._values), self._group)

    def inverse(self) -> Cochain:
        """The inverse in the group (``-ω`` or ``1/ω``)."""
        return Cochain._wrap(self._X, self._k, self._group.inv(self._values), self._group)

    def _additive_only(self, symbol: str) -> None:
        if not self._group.additive:
            raise InvalidCochainError(f"C* is multiplicative: use * and / instead of {symbol}")

    def _multiplicative_only(self, symbol: str) -> None:
        if self._group.additive:
            raise InvalidCochainError(f"{self.group} is additive: use + and - instead of {symbol}")

    def __add__(self, other):
        self._additive_only("+")
        return self.op(other)

    def __sub__(self, other):
        self._additive_only("-")
        self._check_compatible(other)
        return self.op(other.inverse())

    def __neg__(self):
        self._additive_only("unary -")
        return self.inverse()

    def __truediv__(self, other):
        self._multiplicative_only("/")
        self._check_compatible(other)
        return self.op(other.inverse())

    def __pow__(self, n):
        self._multiplicative_only("**")
        if not isinstance(n, numbers.Integral):
            raise InvalidCochainError(f"powers of C*-forms need an integer exponent, got {n!r}")
        return Cochain._wrap(self._X, self._k, self._group.power(self._values, n), self._group)

    def __mul__(self, other):
        if isinstance(other, Cochain):
            self._multiplicative_only("*")
            return self.op(other)
        self._additive_only("* by a scalar (use ** for powers)")
        if isinstance(other, numbers.Integral) and not isinstance(other, bool):
            return Cochain._wrap(self._X, self._k, self._group.power(self._values, int(other)), self._group)
        if self.group in ("R", "C") and isinstance(other, numbers.Number) and np.isfinite(other):
            if self.group == "R" and isinstance(other, numbers.Complex) and not isinstance(other, numbers.Real):
                raise InvalidCochainError("a real form times a complex number: convert with .to_group('C') first")
            return Cochain(self._X, self._k, self._values * other, self.group)
        raise InvalidCochainError(f"{self.group}-forms can be multiplied by integers only, got {other!r}")

    __rmul__ = __mul__

    def __eq__(self, other) -> bool:
        if not isinstance(other, Cochain):
            return NotImplemented
        return (
            self._k == other._k
            and self._group is other._group
            and _same_complex(self._X, other._X)
            and np.array_equal(self._values, other._values)
        )

    __hash__ = None

    def allclose(self, other: Cochain, tol: float | None = None) -> bool:
        """True if ``self ∘ other⁻¹`` is within ``tol`` of the identity (S¹ compares mod 2π)."""
        self._check_compatible(other)
        diff = self._group.op(self._values, self._group.inv(other._values))
        tol = self._group.default_tol(np.concatenate([self._values, other._values])) if tol is None else tol
        return bool(np.all(self._group.distance(diff) <= tol))

    def to_group(self, group: str | Group) -> Cochain:
        """The image under a standard homomorphism to another group.

        Allowed: Z→R, Z→C, R→C (inclusions), R→S1 (mod 2π), S1→C* (``exp(iθ)``),
        C*→S1 (``angle(ω)``, the argument of ``ω/|ω|``); same group: a copy.  For the
        canonical real representative of an S¹-form (not a homomorphism) use :meth:`lift`.

        Examples
        --------
        >>> import numpy as np
        >>> from dhlb import SimplicialComplex
        >>> X = SimplicialComplex([(0, 1)])
        >>> Cochain(X, 1, [3 * np.pi / 2]).to_group("S1").values.round(4).tolist()
        [-1.5708]
        """
        g = get_group(group)
        if g is self._group:
            return Cochain._wrap(self._X, self._k, self._values, g)
        conv = _CONVERSIONS.get((self.group, g.name))
        if conv is None:
            allowed = ", ".join(f"{a}→{b}" for a, b in _CONVERSIONS)
            raise InvalidCochainError(f"no standard conversion {self.group}→{g.name}; allowed: {allowed}")
        return Cochain(self._X, self._k, conv(self._values), g)

    def lift(self) -> Cochain:
        """The real form with the canonical S¹ representatives in (−π, π] (S¹ only).

        Examples
        --------
        >>> from dhlb import SimplicialComplex
        >>> Cochain(SimplicialComplex([(0, 1)]), 1, [7.0], "S1").lift().values.round(4).tolist()
        [0.7168]
        """
        if self.group != "S1":
            raise InvalidCochainError(f"lift() is for S1-forms; this form has group {self.group}")
        return Cochain._wrap(self._X, self._k, self._values, get_group("R"))
