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

from dataclasses import dataclass, field
from math import gcd
from typing import TYPE_CHECKING

import numpy as np

from dhlb.errors import InvalidMatrixError
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


@dataclass(frozen=True)
class HomologyGroup:
    """``H_k ≅ Z^rank ⊕ Z/t_1 ⊕ ... ⊕ Z/t_s`` with representative cycles.

    Every parameter is kept as the attribute of the same name.

    Parameters
    ----------
    degree : int
        The degree ``k``.
    rank : int
        Betti number ``b_k``.
    torsion : tuple of int
        Torsion coefficients ``t_1 | t_2 | ...`` (all > 1).
    generators : (n_k, rank + len(torsion)) int array
        Integer cycles: the free generators first, then the torsion generators (in the order of
        ``torsion``).  Column ``j`` is a chain over ``X.simplices(k)``.

    Examples
    --------
    >>> from dhlb.examples import projective_plane
    >>> H1 = homology(projective_plane())[1]
    >>> str(H1), H1.rank, H1.torsion, H1.generators.shape
    ('Z/2', 0, (2,), (15, 1))
    """

    degree: int
    rank: int
    torsion: tuple
    generators: np.ndarray = field(repr=False, compare=False)

    def __str__(self) -> str:
        return _group_str(self.rank, self.torsion)


@dataclass(frozen=True)
class CohomologyGroup:
    """``H^k(X; G)`` described via universal coefficients, with representative cocycles.

    Every parameter is kept as the attribute of the same name.

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
    cocycles : (n_k, rank + len(torsion)) int or float array
        One cocycle per generator, over ``X.simplices(k)``: Z: int cocycles; R: float; Z/m: ints
        in ``[0, m)``; S1: float — first ``rank`` columns are integer cocycles ``ε_i`` (the torus
        is ``{θ·ε : θ ∈ (R/2πZ)^rank}``), then the finite part as angles in ``(−π, π]``.
    n_hom : int, default 0
        The first ``n_hom`` cocycles represent ``Hom(H_k, G)``, the others ``Ext(H_{k-1}, G)``.

    Examples
    --------
    >>> from dhlb.examples import projective_plane
    >>> X = projective_plane()
    >>> [str(h) for h in cohomology(X)], [str(h) for h in cohomology(X, "S1")]
    (['Z', '0', 'Z/2'], ['S¹', 'Z/2', '0'])
    """

    degree: int
    coefficients: str
    rank: int
    torsion: tuple
    cocycles: np.ndarray = field(repr=False, compare=False)
    n_hom: int = 0

    def __str__(self) -> str:
        if self.coefficients == "R":
            return "R" if self.rank == 1 else ("0" if not self.rank else f"R^{self.rank}")
        if self.coefficients == "S1":
            torus = ("S¹" if self.rank == 1 else f"(S¹)^{self.rank}") if self.rank else ""
            fin = " ⊕ ".join(f"Z/{t}" for t in self.torsion)
            return " × ".join(p for p in (torus, fin) if p) or "0"
        return _group_str(self.rank, self.torsion)


def homology_from_boundaries(boundaries: Sequence[Any]) -> list:
    """Integral homology of a chain complex given by its boundary matrices.

    Parameters
    ----------
    boundaries : list of sparse or dense integer matrices
        ``[∂_0, ∂_1, ..., ∂_n]`` with ``∂_0`` of shape ``(0, n_0)`` and ``∂_k`` of shape
        ``(n_{k-1}, n_k)`` (as ``[X.boundary(k) for k in range(X.dim + 1)]``).

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

    Examples
    --------
    >>> import numpy as np, scipy.sparse as sp
    >>> d1 = sp.csr_matrix(np.array([[-1, -1, 0], [1, 0, -1], [0, 1, 1]]))
    >>> d2 = sp.csr_matrix(np.array([[1], [-1], [1]]))          # the filled triangle
    >>> H = homology_from_boundaries([sp.csr_matrix((0, 3)), d1, d2])
    >>> [str(h) for h in H], H[0].generators.shape
    (['Z', '0', '0'], (3, 1))
    """
    S = HomologyBases(boundaries)
    return [HomologyGroup(k, *S.homology_generators(k)) for k in range(S.n + 1)]


def _boundaries(X):
    return [X.boundary(k) for k in range(X.dim + 1)]


def homology(X: ComplexLike) -> list:
    """Integral homology ``H_0(X), ..., H_dim(X)`` of a simplicial complex.

    Returns a list of :class:`HomologyGroup` (rank, torsion, integer generator cycles over
    ``X.simplices(k)``).  Large complexes are fine: boundary matrices are reduced by sparse ±1
    pivoting before an exact Smith form on the small residual.

    Parameters
    ----------
    X : SimplicialComplex
        Any complex.

    Returns
    -------
    list of HomologyGroup
        ``H_0, ..., H_dim``; ``H_k.generators`` is an ``(n_k, rank + len(torsion))`` int array
        of cycles over ``X.simplices(k)``.

    Examples
    --------
    >>> import dhlb
    >>> X = dhlb.SimplicialComplex([(0, 1), (1, 2), (0, 2)])      # a circle
    >>> [str(h) for h in homology(X)]
    ['Z', 'Z']
    >>> homology(X)[1].generators.ravel().tolist() in ([1, -1, 1], [-1, 1, -1])
    True
    """
    return homology_from_boundaries(_boundaries(X))


def betti_numbers(X: ComplexLike) -> tuple:
    """Betti numbers ``(b_0, ..., b_dim)`` (ranks of integral homology).

    Parameters
    ----------
    X : SimplicialComplex
        Any complex.

    Returns
    -------
    tuple of int, length X.dim + 1
        ``b_k = rank H_k(X; Z)``.

    Examples
    --------
    >>> import dhlb
    >>> betti_numbers(dhlb.SimplicialComplex([(0, 1, 2), (0, 2, 3), (0, 1, 3), (1, 2, 3)]))  # S²
    (1, 0, 1)
    """
    return tuple(h.rank for h in homology(X))


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
        ``H^0, ..., H^n``; the cocycles of ``H^k`` are over the ``n_k`` columns of ``∂_k``.

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
    kind, m = _parse_coefficients(coefficients)
    S = HomologyBases(boundaries)
    out = []
    for k in range(S.n + 1):
        d = S.deg[k]
        b, nt = len(d["free"]), len(d["tors"])
        eps = S.dual_cochains(k)  # (n_k, b + nt) object
        if kind == "Z":
            tau, ords = S.ext_cocycles(k)
            coc = to_int_array(np.concatenate([eps[:, :b], tau], axis=1))
            out.append(CohomologyGroup(k, "Z", b, tuple(ords), coc, b))
        elif kind == "R":
            out.append(CohomologyGroup(k, "R", b, (), eps[:, :b].astype(float), b))
        elif kind == "S1":
            cols = [eps[:, i].astype(float) for i in range(b)]
            for j, o in enumerate(d["orders"]):
                e = np.array([int(x) % o for x in eps[:, b + j]], dtype=np.int64)
                e = np.where(2 * e > o, e - o, e)  # representative in (−o/2, o/2] -> angle in (−π, π]
                cols.append(2 * np.pi * e / o)
            coc = np.stack(cols, axis=1) if cols else np.zeros((S.sizes[k], 0))
            out.append(CohomologyGroup(k, "S1", b, d["orders"], coc, b + nt))
        else:
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
            out.append(CohomologyGroup(k, f"Z/{m}", 0, tuple(ords), coc.reshape(S.sizes[k], len(cols)), n_hom))
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
    return cohomology_from_boundaries(_boundaries(X), coefficients)
