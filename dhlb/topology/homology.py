"""Integral homology and cohomology (with coefficients Z, R, Z/m and S¹) of simplicial complexes.

Method
------
1. The chain complex ``C_n -> ... -> C_0`` (boundary matrices, ``docs/conventions.md``) is reduced
   by sparse elimination of ±1 pivots (:mod:`dhlb.topology._sparse_elim`).  This splits off
   contractible summands ``b -> ∂b`` and leaves a small complex with the same homology, together
   with chain maps ``ι`` (lifting cycles) and ``π^T`` (lifting cocycles), ``⟨π^T φ, ι z⟩ = ⟨φ, z⟩``.
2. On the small complex, for each ``k``: Smith form of ``∂_k`` gives a Z-basis ``Z`` of ``ker ∂_k``
   extended to a unimodular matrix; ``∂_{k+1} = Z C`` and the Smith form ``P C W = S`` gives the
   homology basis ``G = Z P^{-1}``: columns with ``s_i = 1`` are boundaries, ``s_i > 1`` torsion
   generators of order ``s_i`` (``∂_{k+1}(W e_i) = s_i G_i``), the remaining columns free
   generators.  The rows ``ε = P (Q^{-1})_{kernel rows}`` are integer cochains with
   ``ε_i(G_j) = δ_ij`` (seed, Lemma 1: every homomorphism on ``ker ∂_k`` is a form).
3. Universal coefficients, ``H^k(X; G) ≅ Hom(H_k, G) ⊕ Ext(H_{k-1}, G)``, realised by cocycles:

   * ``G = Z``: ``Hom(H_k, Z) = Z^{b_k}`` by the cocycles ``ε_i`` of the free generators (they
     are cocycles and form the dual basis); ``Ext(H_{k-1}, Z) = ⊕ Z/d`` by ``τ = δ ε_t / d`` for
     each torsion generator ``t`` (order ``d``) of ``H_{k-1}`` (``d τ = δ ε_t``, ``τ`` not exact).
   * ``G = R``: dimension ``b_k``; the cocycles ``ε_i`` as floats.
   * ``G = Z/m``: ``Hom(H_k, Z/m)``: ``ε_i mod m`` (order ``m``) and ``(m/g) ε_t mod m``
     (order ``g = gcd(d, m)``); ``Ext(H_{k-1}, Z/m)``: ``τ mod m`` (order ``gcd(d, m)``).
   * ``G = S¹`` (angles, ``docs/conventions.md``): ``Ext(H_{k-1}, S¹) = 0`` (S¹ is divisible), so
     ``H^k(X; S¹) = Hom(H_k, S¹) ≅ (S¹)^{b_k} × ⊕ Z/d``.  Torus part: ``θ ε_i`` for angles ``θ``;
     finite part: the angle cocycle ``2π ε_t / d`` (holonomy ``2π/d`` on ``t``, 0 on the other
     generators).  For RP² this is the flat bundle with holonomy π on the generator of ``H_1``.

Examples
--------
>>> import numpy as np, scipy.sparse as sp
>>> d1 = sp.csr_matrix(np.array([[-1, -1, 0], [1, 0, -1], [0, 1, 1]]))   # a hollow triangle
>>> [str(h) for h in homology_from_boundaries([sp.csr_matrix((0, 3)), d1])]
['Z', 'Z']
"""

from __future__ import annotations

from math import gcd
from typing import TYPE_CHECKING

import numpy as np

from dhlb.errors import InvalidMatrixError, InvalidParameterError
from dhlb.topology._homology_bases import HomologyBases
from dhlb.topology._intmatrix import to_int_array

if TYPE_CHECKING:
    from collections.abc import Sequence
    from typing import Any

    from dhlb.topology._protocol import ComplexLike

__all__ = [
    "HomologyGroup",
    "CohomologyGroup",
    "homology",
    "homology_from_boundaries",
    "betti_numbers",
    "cohomology",
    "cohomology_from_boundaries",
]


def _group_str(rank: int, torsion, free: str = "Z") -> str:
    parts = ([free if rank == 1 else f"{free}^{rank}"] if rank else []) + [f"Z/{t}" for t in torsion]
    return " ⊕ ".join(parts) if parts else "0"


class _Record:
    """A read-only record whose array attribute (``_lazy``) may be given as a callable, computed on first access."""

    __slots__ = ()
    _fields: tuple = ()
    _lazy: str = ""

    def _set(self, **values) -> None:
        for key in self._fields:
            object.__setattr__(self, "_v_" + key, values[key])

    def __getattr__(self, name):
        if name in type(self)._fields:
            v = object.__getattribute__(self, "_v_" + name)
            if name == self._lazy and callable(v):  # built once, on first access
                v = v()
                object.__setattr__(self, "_v_" + name, v)
            return v
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    def __setattr__(self, name, value):
        raise AttributeError(f"{type(self).__name__} is read-only")

    def _key(self) -> tuple:
        return tuple(getattr(self, k) for k in self._fields if k != self._lazy)

    def __eq__(self, other):
        return self._key() == other._key() if type(other) is type(self) else NotImplemented

    __hash__ = None

    def __repr__(self) -> str:
        inner = ", ".join(f"{k}={getattr(self, k)!r}" for k in self._fields if k != self._lazy)
        return f"{type(self).__name__}({inner})"


class HomologyGroup(_Record):
    """``H_k ≅ Z^rank ⊕ Z/t_1 ⊕ ... ⊕ Z/t_s`` (or ``(Z/p)^rank``) with representative cycles.

    Every parameter is kept as the attribute of the same name; the record is read-only.

    Parameters
    ----------
    degree : int
        The degree ``k``.
    rank : int
        Betti number ``b_k``; over ``Z/p`` the dimension of ``H_k(X; Z/p)``.
    torsion : tuple of int
        Torsion coefficients ``t_1 | t_2 | ...`` (all > 1); ``()`` over ``Z/p``.
    generators : (n_k, rank + len(torsion)) int array, or a callable returning it
        Cycles: the free generators first, then the torsion generators (in the order of
        ``torsion``); over ``Z/p`` cycles modulo ``p`` with entries in ``[0, p)``.  Column ``j``
        is a chain over ``X.simplices(k)``.  :func:`homology` passes a callable: the basis is
        built on first access to ``generators`` (the groups need none).
    coefficients : str, default "Z"
        ``"Z"`` or ``"Z/p"``.

    Examples
    --------
    >>> from dhlb.examples import projective_plane
    >>> H1 = homology(projective_plane())[1]
    >>> str(H1), H1.rank, H1.torsion, H1.generators.shape
    ('Z/2', 0, (2,), (15, 1))
    >>> str(homology(projective_plane(), "Z/2")[1])
    'Z/2'
    """

    __slots__ = ("_v_coefficients", "_v_degree", "_v_generators", "_v_rank", "_v_torsion")
    _fields = ("degree", "rank", "torsion", "generators", "coefficients")
    _lazy = "generators"

    def __init__(self, degree: int, rank: int, torsion: tuple, generators=None, coefficients: str = "Z"):
        self._set(degree=degree, rank=rank, torsion=tuple(torsion), generators=generators, coefficients=coefficients)

    def __str__(self) -> str:
        if self.coefficients != "Z":
            f = self.coefficients
            return "0" if not self.rank else (f if self.rank == 1 else f"({f})^{self.rank}")
        return _group_str(self.rank, self.torsion)


class CohomologyGroup(_Record):
    """``H^k(X; G)`` described via universal coefficients, with representative cocycles.

    Every parameter is kept as the attribute of the same name; the record is read-only.

    Parameters
    ----------
    degree : int
        The degree ``k``.
    coefficients : str
        ``"Z"``, ``"R"``, ``"Z/m"`` or ``"S1"``.
    rank : int
        Z: free rank ``b_k``; R: the dimension ``b_k``; S1: the torus dimension ``b_k``;
        Z/m: 0 (every factor is listed in ``torsion``).
    torsion : tuple of int
        Z: orders of the torsion part (``Ext(H_{k-1}, Z)``); Z/m: the orders of all cyclic
        factors (``Hom`` part first, then ``Ext`` part); S1: the orders of the finite part
        (``≅`` torsion of ``H_k``); R: ``()``.
    cocycles : (n_k, rank + len(torsion)) int or float array, or a callable returning it
        One cocycle per generator, over ``X.simplices(k)``: Z: int cocycles; R: float; Z/m: ints
        in ``[0, m)``; S1: float — first ``rank`` columns are integer cocycles ``ε_i`` (the torus
        is ``{θ·ε : θ ∈ (R/2πZ)^rank}``), then the finite part as angles in ``(−π, π]``.
        :func:`cohomology` passes a callable: the cocycles are built on first access.
    n_hom : int, default 0
        The first ``n_hom`` cocycles represent ``Hom(H_k, G)``, the others ``Ext(H_{k-1}, G)``.

    Examples
    --------
    >>> from dhlb.examples import projective_plane
    >>> X = projective_plane()
    >>> [str(h) for h in cohomology(X)], [str(h) for h in cohomology(X, "S1")]
    (['Z', '0', 'Z/2'], ['S¹', 'Z/2', '0'])
    """

    __slots__ = ("_v_cocycles", "_v_coefficients", "_v_degree", "_v_n_hom", "_v_rank", "_v_torsion")
    _fields = ("degree", "coefficients", "rank", "torsion", "cocycles", "n_hom")
    _lazy = "cocycles"

    def __init__(self, degree: int, coefficients: str, rank: int, torsion: tuple, cocycles, n_hom: int = 0):
        self._set(degree=degree, coefficients=coefficients, rank=rank, torsion=tuple(torsion), cocycles=cocycles,
                  n_hom=n_hom)

    def __str__(self) -> str:
        if self.coefficients == "R":
            return "R" if self.rank == 1 else ("0" if not self.rank else f"R^{self.rank}")
        if self.coefficients == "S1":
            torus = ("S¹" if self.rank == 1 else f"(S¹)^{self.rank}") if self.rank else ""
            fin = " ⊕ ".join(f"Z/{t}" for t in self.torsion)
            return " × ".join(p for p in (torus, fin) if p) or "0"
        return _group_str(self.rank, self.torsion)


def _is_prime(p: int) -> bool:
    """Deterministic Miller–Rabin for ``p < 3.3·10²⁴`` (the first 12 prime bases)."""
    if p < 2:
        return False
    bases = (2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37)
    if p in bases:
        return True
    if any(p % b == 0 for b in bases):
        return False
    d, r = p - 1, 0
    while d % 2 == 0:
        d, r = d // 2, r + 1
    for b in bases:
        x = pow(b, d, p)
        if x in (1, p - 1):
            continue
        for _ in range(r - 1):
            x = x * x % p
            if x == p - 1:
                break
        else:
            return False
    return True


def _check_prime(p, name: str) -> int:
    if isinstance(p, bool) or not isinstance(p, (int, np.integer)):
        raise InvalidParameterError(f"{name} must be a prime number (an int), got {p!r}.")
    p = int(p)
    if p >= 2**64 or not _is_prime(p):
        raise InvalidParameterError(f"{name} must be a prime below 2**64, got {p}; for a composite m the integer "
                                    "groups give H_k(X; Z/m) = H_k ⊗ Z/m ⊕ Tor(H_(k-1), Z/m).")
    return p


def _homology_field(coefficients) -> int | None:
    """``None`` for ``"Z"``, else the prime ``p`` of ``"Z/p"`` / ``("Z", p)``."""
    c = coefficients
    if isinstance(c, str) and c.strip().upper() == "Z":
        return None
    if isinstance(c, tuple) and len(c) == 2 and c[0] == "Z":
        return _check_prime(c[1], "the p of ('Z', p)")
    if isinstance(c, str) and c.strip().upper().startswith("Z/") and c.strip()[2:].isdigit():
        return _check_prime(int(c.strip()[2:]), f"the p of {c!r}")
    raise InvalidParameterError(f"homology coefficients must be 'Z', 'Z/p' or ('Z', p) with p prime, got "
                                f"{coefficients!r}; cohomology() also takes 'R', 'S1' and any 'Z/m'.")


def _groups(S: HomologyBases) -> list:
    """The homology groups of a reduced complex; their generators are built on first access."""
    coeff = "Z" if S.p is None else f"Z/{S.p}"
    return [HomologyGroup(k, S.rank(k), S.torsion(k), (lambda k=k: S.homology_generators(k)[2]), coeff)
            for k in range(S.n + 1)]


def homology_from_boundaries(boundaries: Sequence[Any], coefficients: str | tuple = "Z") -> list:
    """Homology of a chain complex given by its boundary matrices.

    Parameters
    ----------
    boundaries : list of sparse or dense integer matrices
        ``[∂_0, ∂_1, ..., ∂_n]`` with ``∂_0`` of shape ``(0, n_0)`` and ``∂_k`` of shape
        ``(n_{k-1}, n_k)`` (as ``[X.boundary(k) for k in range(X.dim + 1)]``).
    coefficients : "Z" or "Z/p" or ("Z", p), default "Z"
        Integers (ranks and torsion), or the field ``Z/p`` for a prime ``p`` (dimensions).

    Returns
    -------
    list of HomologyGroup
        ``H_0, ..., H_n``.

    Raises
    ------
    ShapeError
        ``boundaries`` is empty, ``∂_0`` does not have 0 rows, or the rows of ``∂_k`` do not
        match the columns of ``∂_{k-1}``.
    InvalidMatrixError
        A matrix has non-integer entries (or entries beyond int64), or ``∂_{k-1} ∂_k ≠ 0``.
    InvalidParameterError
        ``coefficients`` is none of the above (or ``p`` is not prime).

    Examples
    --------
    >>> import numpy as np, scipy.sparse as sp
    >>> d1 = sp.csr_matrix(np.array([[-1, -1, 0], [1, 0, -1], [0, 1, 1]]))
    >>> d2 = sp.csr_matrix(np.array([[1], [-1], [1]]))          # the filled triangle
    >>> H = homology_from_boundaries([sp.csr_matrix((0, 3)), d1, d2])
    >>> [str(h) for h in H], H[0].generators.shape
    (['Z', '0', '0'], (3, 1))
    """
    return _groups(HomologyBases(boundaries, _homology_field(coefficients)))


def _boundaries(X):
    return [X.boundary(k) for k in range(X.dim + 1)]


def _reduced(X, p: int | None = None) -> HomologyBases:
    """The reduced complex of ``X`` (a SimplicialComplex's own boundary matrices need no ``∂∂ = 0`` check)."""
    return HomologyBases(_boundaries(X), p, trusted=getattr(type(X), "_exact_boundaries", False) is True)


def homology(X: ComplexLike, coefficients: str | tuple = "Z") -> list:
    """Homology ``H_0(X), ..., H_dim(X)`` of a simplicial complex, with integer or ``Z/p`` coefficients.

    Returns a list of :class:`HomologyGroup` (rank, torsion, generator cycles over
    ``X.simplices(k)``).  The groups are computed without any basis: the complex is reduced by an
    acyclic matching (collapses and coreductions), then by sparse elimination of unit pivots,
    and an exact Smith form runs on the small rest.  The generator cycles are built (sparsely,
    then returned dense) only when ``generators`` is first read.

    Parameters
    ----------
    X : SimplicialComplex
        Any complex.
    coefficients : "Z" or "Z/p" or ("Z", p), default "Z"
        Integers, or the field ``Z/p`` for a prime ``p``: then ``rank`` is the dimension of
        ``H_k(X; Z/p)`` and the generators are cycles modulo ``p``.

    Returns
    -------
    list of HomologyGroup
        ``H_0, ..., H_dim``; ``H_k.generators`` is an ``(n_k, rank + len(torsion))`` int array
        of cycles over ``X.simplices(k)``.

    Raises
    ------
    InvalidParameterError
        ``coefficients`` is none of the above (or ``p`` is not prime).

    Examples
    --------
    >>> import dhlb
    >>> X = dhlb.SimplicialComplex([(0, 1), (1, 2), (0, 2)])      # a circle
    >>> [str(h) for h in homology(X)]
    ['Z', 'Z']
    >>> homology(X)[1].generators.ravel().tolist() in ([1, -1, 1], [-1, 1, -1])
    True
    >>> from dhlb.examples import projective_plane
    >>> [str(h) for h in homology(projective_plane(), "Z/2")], [str(h) for h in homology(projective_plane(), "Z/3")]
    (['Z/2', 'Z/2', 'Z/2'], ['Z/3', '0', '0'])
    """
    return _groups(_reduced(X, _homology_field(coefficients)))


def betti_numbers(X: ComplexLike, p: int | None = None) -> tuple:
    """Betti numbers ``(b_0, ..., b_dim)``: ranks of integral homology, or dimensions over ``Z/p``.

    Parameters
    ----------
    X : SimplicialComplex
        Any complex.
    p : int, optional
        A prime: the dimensions of ``H_k(X; Z/p)`` (by elimination modulo ``p``).  Torsion shows
        as the difference: ``dim H_k(X; Z/p) − b_k`` counts the torsion coefficients of ``H_k``
        and ``H_{k-1}`` divisible by ``p``.

    Returns
    -------
    tuple of int, length X.dim + 1
        ``b_k = rank H_k(X; Z)``, or ``dim H_k(X; Z/p)``.

    Raises
    ------
    InvalidParameterError
        ``p`` is not a prime.

    Examples
    --------
    >>> import dhlb
    >>> betti_numbers(dhlb.SimplicialComplex([(0, 1, 2), (0, 2, 3), (0, 1, 3), (1, 2, 3)]))  # S²
    (1, 0, 1)
    >>> from dhlb.examples import projective_plane
    >>> betti_numbers(projective_plane()), betti_numbers(projective_plane(), p=2)
    ((1, 0, 0), (1, 1, 1))
    """
    S = _reduced(X, None if p is None else _check_prime(p, "p"))
    return tuple(S.rank(k) for k in range(S.n + 1))


def _parse_coefficients(coefficients):
    c = coefficients
    if isinstance(c, str) and c.replace("¹", "1").upper() in ("Z", "R", "S1"):
        return c.replace("¹", "1").upper(), None
    if isinstance(c, tuple) and len(c) == 2 and c[0] == "Z":
        m = c[1]
        if isinstance(m, (int, np.integer)) and not isinstance(m, bool) and m >= 2:
            return "Z/m", int(m)
    if isinstance(c, str) and c.upper().startswith("Z/") and c[2:].isdigit() and int(c[2:]) >= 2:
        return "Z/m", int(c[2:])
    raise InvalidMatrixError(f"unknown coefficients {coefficients!r}; use 'Z', 'R', 'S1', ('Z', m) or "
                             "'Z/m' with m >= 2.")


def _cocycles(S: HomologyBases, k: int, kind: str, m: int | None) -> tuple:
    """``(cocycles, orders, n_hom)`` of ``H^k(G)`` by universal coefficients (module docstring, step 3)."""
    d = S.degree(k)
    b, nt = S.rank(k), len(d["tors"])
    eps = S.dual_cochains(k)  # (n_k, b + nt): free then torsion
    if kind == "Z":
        tau, ords = S.ext_cocycles(k)
        return to_int_array(np.concatenate([np.asarray(eps[:, :b], dtype=object), tau], axis=1)), tuple(ords), b
    if kind == "R":
        return eps[:, :b].astype(float), (), b
    if kind == "S1":
        cols = [eps[:, i].astype(float) for i in range(b)]
        for j, o in enumerate(d["orders"]):
            e = np.array([int(x) % o for x in eps[:, b + j]], dtype=np.int64)
            e = np.where(2 * e > o, e - o, e)  # representative in (−o/2, o/2] -> angle in (−π, π]
            cols.append(2 * np.pi * e / o)
        return (np.stack(cols, axis=1) if cols else np.zeros((S.sizes[k], 0))), d["orders"], b + nt
    cols, ords = [eps[:, i] for i in range(b)], [m] * b
    for j, o in enumerate(d["orders"]):
        g = gcd(o, m)
        if g > 1:
            cols.append((m // g) * eps[:, b + j])
            ords.append(g)
    n_hom = len(cols)
    tau, tords = S.ext_cocycles(k)
    for j, o in enumerate(tords):
        g = gcd(o, m)
        if g > 1:
            cols.append(tau[:, j])
            ords.append(g)
    coc = np.array([[int(x) % m for x in c] for c in cols], dtype=np.int64).T if cols else \
        np.zeros((S.sizes[k], 0), dtype=np.int64)
    return coc.reshape(S.sizes[k], len(cols)), tuple(ords), n_hom


def cohomology_from_boundaries(boundaries: Sequence[Any], coefficients: str | int = "Z") -> list:
    """Cohomology ``H^k(G)``, ``k = 0..n``, of a chain complex; see :func:`cohomology`.

    Parameters
    ----------
    boundaries : list of sparse or dense integer matrices
        ``[∂_0, ∂_1, ..., ∂_n]``, ``∂_k`` of shape ``(n_{k-1}, n_k)``, as for
        :func:`homology_from_boundaries`.
    coefficients : {"Z", "R", "S1"} or ("Z", m) or "Z/m", default "Z"
        The coefficient group ``G`` (``m >= 2``).

    Returns
    -------
    list of CohomologyGroup
        ``H^0, ..., H^n``; the cocycles of ``H^k`` are over the ``n_k`` columns of ``∂_k`` (built
        on first access).

    Raises
    ------
    InvalidMatrixError
        ``coefficients`` is none of the above; a matrix has non-integer entries, or
        ``∂_{k-1} ∂_k ≠ 0``.
    ShapeError
        The shapes of the boundary matrices do not fit together (see :func:`homology_from_boundaries`).

    Examples
    --------
    >>> import numpy as np, scipy.sparse as sp
    >>> d1 = sp.csr_matrix(np.array([[-1, -1, 0], [1, 0, -1], [0, 1, 1]]))
    >>> [str(h) for h in cohomology_from_boundaries([sp.csr_matrix((0, 3)), d1], "R")]
    ['R', 'R']
    """
    return _cohomology_groups(HomologyBases(boundaries), coefficients)


def _cohomology_groups(S: HomologyBases, coefficients) -> list:
    """The cohomology groups of a reduced complex; their cocycles are built on first access."""
    kind, m = _parse_coefficients(coefficients)
    out = []
    for k in range(S.n + 1):
        b, tors_k = S.rank(k), S.torsion(k)
        tors_below = S.torsion(k - 1) if k else ()
        if kind == "Z":
            rank, orders, n_hom = b, tors_below, b
        elif kind == "R":
            rank, orders, n_hom = b, (), b
        elif kind == "S1":
            rank, orders, n_hom = b, tors_k, b + len(tors_k)
        else:
            hom = [m] * b + [gcd(o, m) for o in tors_k if gcd(o, m) > 1]
            rank, orders, n_hom = 0, tuple(hom + [gcd(o, m) for o in tors_below if gcd(o, m) > 1]), len(hom)
        coeff = {"Z": "Z", "R": "R", "S1": "S1"}.get(kind, f"Z/{m}")
        out.append(CohomologyGroup(k, coeff, rank, tuple(orders), (lambda k=k: _cocycles(S, k, kind, m)[0]), n_hom))
    return out


def cohomology(X: ComplexLike, coefficients: str | int = "Z") -> list:
    """Cohomology ``H^k(X; G)``, ``k = 0..dim``, with representative cocycles (module docstring).

    Parameters
    ----------
    X : SimplicialComplex
        Any complex.
    coefficients : {"Z", "R", "S1"} or ("Z", m) or "Z/m", default "Z"
        The coefficient group ``G`` (``m >= 2``); S¹-valued cocycles are angles (``docs/conventions.md``).

    Returns
    -------
    list of CohomologyGroup
        ``H^0, ..., H^dim``; the cocycles of ``H^k`` are over ``X.simplices(k)``.

    Raises
    ------
    InvalidMatrixError
        ``coefficients`` is none of the above.

    Examples
    --------
    RP² (6 vertices): ``H^1(RP²; S¹) ≅ Z/2``, the flat bundle with holonomy π:

    >>> import dhlb, numpy as np
    >>> F = [(0,1,2),(0,2,3),(0,3,4),(0,4,5),(0,1,5),(1,2,4),(2,3,5),(1,3,4),(1,3,5),(2,4,5)]
    >>> X = dhlb.SimplicialComplex(F)
    >>> [str(h) for h in cohomology(X, "Z")], [str(h) for h in cohomology(X, ("Z", 2))]
    (['Z', '0', 'Z/2'], ['Z/2', 'Z/2', 'Z/2'])
    >>> H1 = cohomology(X, "S1")[1]
    >>> str(H1), H1.torsion
    ('Z/2', (2,))
    >>> z = homology(X)[1].generators[:, 0]                  # the generator of H_1 = Z/2
    >>> bool(np.isclose(abs(np.angle(np.exp(1j * (z @ H1.cocycles[:, 0])))), np.pi))
    True
    """
    _parse_coefficients(coefficients)  # bad coefficients fail before the work
    return _cohomology_groups(_reduced(X), coefficients)
