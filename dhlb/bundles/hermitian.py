"""Discrete hermitian line bundles with curvature (seed part 3, §7–§8; Definition 8).

Conventions (``docs/conventions.md``): one unit complex ``r_ij`` per canonical edge ``i < j``
with ``η_ij(X_i) = r_ij X_j``; a section ``ψ_i = z_i X_i`` is parallel along ``ij`` iff
``z_j = r_ij z_i``.  The curvature is one real ``Ω`` per canonical triangle ``i < j < k`` with
``exp(iΩ_ijk) = r_ij r_jk r_ki`` and ``dΩ = 0``.

Examples
--------
>>> import numpy as np
>>> from dhlb import SimplicialComplex
>>> from dhlb.bundles import HermitianLineBundle
>>> X = SimplicialComplex([(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)])   # a 2-sphere
>>> L = HermitianLineBundle(X, np.ones(6), [0, 0, 0, 2 * np.pi])
>>> L.degree()            # the fundamental cycle is [1, -1, 1, -1]
-1
>>> L.index_form(np.ones(4)).tolist()
[0, 0, 0, 1]
"""

from __future__ import annotations

from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np

from dhlb.bundles import _sections
from dhlb.bundles._hermitian_checks import checked_connection, checked_curvature, from_cochain
from dhlb.bundles._hermitian_checks import real_vector as _real_vector  # also imported by weil.py
from dhlb.bundles.integrality import check_integrality
from dhlb.bundles.vector_bundle import VectorBundle
from dhlb.errors import IntegralityError, InvalidConnectionError, NonManifoldError, NonOrientableError, NotClosedError
from dhlb.forms.groups import wrap_angle
from dhlb.topology import graph
from dhlb.topology._incidence import coboundary_values as coboundary
from dhlb.topology._names import simplex_name

if TYPE_CHECKING:
    from typing import Any

    from numpy.typing import ArrayLike

    from dhlb.forms.chain import Chain
    from dhlb.forms.cochain import Cochain
    from dhlb.topology.complex import SimplicialComplex

__all__ = ["HermitianLineBundle"]


class HermitianLineBundle:
    """A hermitian line bundle with connection ``r`` and curvature ``Ω``.

    Parameters
    ----------
    X : SimplicialComplex
    connection : (n_1,) complex128, unit modulus, one per canonical edge (or an S¹/C* 1-form
        :class:`dhlb.forms.Cochain`)
    curvature : (n_2,) real, one per canonical triangle (or a real 2-form ``Cochain``)
    atol : float
        Tolerance for ``|r| = 1``, ``exp(iΩ) = holonomy`` (mod 2π, relative to ``max(1, |Ω|)``)
        and ``dΩ = 0``.

    Raises
    ------
    InvalidConnectionError
        wrong length or a non-unit ``r`` (names the edge).
    CurvatureMismatchError
        ``exp(iΩ_t) ≠ r_ij r_jk r_ki`` (names the triangle and the mismatch).
    NotClosedError
        ``dΩ ≠ 0`` on a tetrahedron (names it).

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)])
    >>> L = HermitianLineBundle(X, np.ones(6), [0, 0, 0, 2 * np.pi])
    >>> L.degree(), L.is_isomorphic(HermitianLineBundle.trivial(X)), L.tensor(L.dual()).degree()
    (-1, False, 0)
    """

    def __init__(self, X: SimplicialComplex, connection: ArrayLike, curvature: ArrayLike, *, atol: float = 1e-8):
        self._X = X
        self._atol = float(atol)
        connection, curvature = from_cochain(connection, 1), from_cochain(curvature, 2)
        r = checked_connection(X, connection, atol)
        Om = checked_curvature(X, r, curvature, atol)
        r.setflags(write=False)
        Om.setflags(write=False)
        self._r = r
        self._Om = Om

    # ------------------------------------------------------------------ construction
    @classmethod
    def _from_checked(cls, X: SimplicialComplex, connection: np.ndarray, curvature: np.ndarray,
                      *, atol: float = 1e-8) -> HermitianLineBundle:
        """Unchecked construction from data consistent by construction (e.g. a mesh's tangent bundle).

        ``connection`` is a finite complex ``(n_1,)`` array of modulus 1 up to rounding (normalized here as
        by the checked constructor), ``curvature`` a finite real ``(n_2,)`` array matching its holonomy.
        """
        self = cls.__new__(cls)
        self._X = X
        self._atol = float(atol)
        r = np.asarray(connection, np.complex128).reshape(-1)
        r = r / np.abs(r)
        Om = np.array(curvature, np.float64).reshape(-1)
        r.setflags(write=False)
        Om.setflags(write=False)
        self._r, self._Om = r, Om
        return self

    @classmethod
    def from_angles(
        cls, X: SimplicialComplex, angles: ArrayLike, curvature: ArrayLike, **kw: Any
    ) -> HermitianLineBundle:
        """From connection angles ``ω_ij`` (``r = exp(iω)``)."""
        w = _real_vector(angles, X.n_simplices(1), "the connection angles")
        return cls(X, np.exp(1j * w), curvature, **kw)

    @classmethod
    def trivial(cls, X: SimplicialComplex, **kw: Any) -> HermitianLineBundle:
        """The product bundle: ``r = 1``, ``Ω = 0``."""
        return cls(X, np.ones(X.n_simplices(1)), np.zeros(X.n_simplices(2)), **kw)

    # ------------------------------------------------------------------ data
    @property
    def X(self) -> SimplicialComplex:
        """The base simplicial complex."""
        return self._X

    @property
    def connection(self) -> np.ndarray:
        """``(n_1,)`` unit complex ``r_ij`` per canonical edge (read-only)."""
        return self._r

    @property
    def curvature(self) -> np.ndarray:
        """``(n_2,)`` real curvature Ω per canonical triangle (read-only)."""
        return self._Om

    @property
    def atol(self) -> float:
        """The absolute tolerance of the unit-modulus and curvature checks."""
        return self._atol

    @cached_property
    def connection_angles(self) -> np.ndarray:
        """The S¹-valued connection form ``ω = angle(r)`` in (−π, π]."""
        return wrap_angle(np.angle(self._r))

    def connection_form(self) -> Cochain:
        """The connection form ω as an S¹-valued :class:`dhlb.forms.Cochain`."""
        from dhlb.forms import Cochain

        return Cochain(self._X, 1, self.connection_angles, "S1")

    def curvature_form(self) -> Cochain:
        """The curvature Ω as a real :class:`dhlb.forms.Cochain`."""
        from dhlb.forms import Cochain

        return Cochain(self._X, 2, self._Om, "R")

    def holonomy_angles(self) -> np.ndarray:
        """``(dω)`` wrapped to (−π, π]: the angle of ``r_ij r_jk r_ki`` per triangle."""
        return wrap_angle(coboundary(self._X, 1, self.connection_angles)[0])

    def vector_bundle(self) -> VectorBundle:
        """The rank-1 complex hermitian :class:`VectorBundle` with transports ``r``."""
        return VectorBundle(self._X, self._r, "C", metric=True, atol=self._atol)

    def __repr__(self) -> str:
        return f"HermitianLineBundle(X={self._X!r})"

    # ------------------------------------------------------------------ operations
    def gauge(self, g: ArrayLike) -> HermitianLineBundle:
        """New frames ``X'_i = g_i X_i`` (``g`` unit complex per vertex): ``r'_ij = conj(g_j) r_ij g_i``."""
        g = np.asarray(g, dtype=np.complex128).reshape(-1)
        if g.size != self._X.n_vertices or np.any(np.abs(np.abs(g) - 1) > self._atol):
            raise InvalidConnectionError(
                f"a gauge transformation is one unit complex number per vertex ({self._X.n_vertices})"
            )
        E = self._X.simplices(1)
        return HermitianLineBundle(self._X, np.conj(g[E[:, 1]]) * self._r * g[E[:, 0]], self._Om, atol=self._atol)

    def _check_same(self, other) -> None:
        if not isinstance(other, HermitianLineBundle) or (other.X is not self._X and other.X != self._X):
            raise InvalidConnectionError("both line bundles must live over the same complex")

    def tensor(self, other: HermitianLineBundle) -> HermitianLineBundle:
        """``L ⊗ L'``: connections multiply, curvatures add."""
        self._check_same(other)
        return HermitianLineBundle(self._X, self._r * other._r, self._Om + other._Om, atol=self._atol)

    __mul__ = tensor

    def dual(self) -> HermitianLineBundle:
        """``L*``: conjugate connection, curvature ``−Ω``."""
        return HermitianLineBundle(self._X, np.conj(self._r), -self._Om, atol=self._atol)

    def power(self, n: int) -> HermitianLineBundle:
        """``L^{⊗n}`` for an integer ``n`` (negative: powers of the dual)."""
        n = int(n)
        return HermitianLineBundle(self._X, self._r**n, n * self._Om, atol=self._atol)

    # ------------------------------------------------------------------ classification
    @cached_property
    def _forest(self) -> graph.SpanningForest:
        return graph.spanning_forest(self._X)

    def class_angles(self) -> np.ndarray:
        """The class in Hom(ker ∂₁, S¹): holonomy angle around each fundamental cycle of the BFS forest."""
        T = self._forest
        w = self.connection_angles
        child = np.nonzero(T.parent >= 0)[0]
        step = np.zeros(self._X.n_vertices)
        step[child] = np.where(T.parent[child] < child, 1.0, -1.0) * w[T.parent_edge[child]]
        phi = graph.tree_accumulate(T, step, np.add, 0.0)
        E = self._X.simplices(1)[T.nontree]
        return wrap_angle(phi[E[:, 0]] + w[T.nontree] - phi[E[:, 1]])

    def holonomy(self, cycle: ArrayLike | Chain) -> float:
        """Holonomy angle ``Σ c_e ω_e`` (mod 2π) around an integer 1-cycle ``c``.

        Raises
        ------
        NotClosedError
            if ``c`` is not a cycle (names a vertex of its boundary).
        """
        c = self._chain(cycle, 1)
        return float(wrap_angle(c @ self.connection_angles))

    def find_isomorphism(self, other: HermitianLineBundle) -> np.ndarray | None:
        """Unit ``g`` per vertex with ``other = self.gauge(g)``, or None (needs equal curvature)."""
        self._check_same(other)
        tol = self._atol * max(1.0, float(np.max(np.abs(self._Om), initial=0)))
        if not np.allclose(self._Om, other._Om, rtol=0, atol=tol):
            return None
        d = wrap_angle(self.class_angles() - other.class_angles())
        if np.any(np.abs(d) > self._atol * 100):
            return None
        # gauge: r'_ij = conj(g_j) r_ij g_i  <=>  g_j = g_i r_ij / r'_ij along the tree
        T = self._forest
        child = np.nonzero(T.parent >= 0)[0]
        ratio = self.connection_angles - other.connection_angles
        step = np.zeros(self._X.n_vertices)
        step[child] = np.where(T.parent[child] < child, 1.0, -1.0) * ratio[T.parent_edge[child]]
        return np.exp(1j * graph.tree_accumulate(T, step, np.add, 0.0))

    def is_isomorphic(self, other: HermitianLineBundle) -> bool:
        """Isomorphic as bundles with curvature: equal Ω and equal class in Hom(ker ∂₁, S¹)."""
        return self.find_isomorphism(other) is not None

    # ------------------------------------------------------------------ curvature integrals
    def _chain(self, chain, k: int) -> np.ndarray:
        if hasattr(chain, "coefficients") and hasattr(chain, "k"):  # a dhlb.forms.Chain
            if chain.k != k:
                raise NotClosedError(f"expected a {k}-chain, got a {chain.k}-chain")
            chain = chain.coefficients
        c = np.asarray(chain)
        n = self._X.n_simplices(k)
        if c.ndim != 1 or c.size != n or not (np.issubdtype(c.dtype, np.integer) or np.all(c == np.round(c))):
            raise NotClosedError(f"a {k}-cycle is an integer vector of length n_{k} = {n}")
        c = c.astype(np.int64)
        b = self._X.boundary(k) @ c
        if np.any(b != 0):
            s = int(np.nonzero(b)[0][0])
            where = f"vertex {int(self._X.vertex_labels[s])}" if k == 1 else simplex_name(self._X, k - 1, s)
            raise NotClosedError(f"the {k}-chain is not a cycle: its boundary has coefficient {int(b[s])} on {where}")
        return c

    def integrate_curvature(self, cycle: ArrayLike | Chain) -> float:
        """``∫_C Ω = Σ C_t Ω_t`` over an integral 2-cycle ``C`` (checked: ``∂C = 0``)."""
        return float(self._chain(cycle, 2) @ self._Om)

    def fundamental_cycle(self, orientation: ArrayLike | None = None) -> np.ndarray:
        """The fundamental 2-cycle ``Σ_t o_t t`` of the closed oriented surface X.

        Parameters
        ----------
        orientation : (n_2,) array of ±1, optional
            The orientation per canonical triangle (e.g. the orientation of a mesh's faces:
            ``X.orientation_of(F)`` reordered to the rows of ``X.simplices(2)``). Default:
            ``X.orientation()`` (+1 on the first triangle of each component).

        Raises
        ------
        NonManifoldError
            X is not a closed surface (names an edge with one triangle).
        NonOrientableError
            X is not orientable, or ``orientation`` is not a consistent orientation.
        """
        X = self._X
        if X.dim != 2:
            raise NonManifoldError(f"the degree is defined over closed oriented surfaces; X has dimension {X.dim}")
        cnt = np.bincount(X.faces(2).ravel(), minlength=X.n_simplices(1))
        if np.any(cnt == 1):
            e = int(np.argmax(cnt == 1))
            raise NonManifoldError(
                f"the degree needs a closed surface, but edge {simplex_name(X, 1, e)} lies in one triangle only"
            )
        if orientation is None:
            return np.asarray(X.orientation(), dtype=np.int64)
        o = np.asarray(orientation)
        if o.shape != (X.n_simplices(2),) or not np.all(np.abs(o) == 1):
            raise NonOrientableError(f"orientation must be one ±1 per triangle ({X.n_simplices(2)} values)")
        o = o.astype(np.int64)
        bad = np.nonzero(X.boundary(2) @ o)[0]
        if bad.size:
            raise NonOrientableError(
                f"the given orientation is not consistent at edge {simplex_name(X, 1, int(bad[0]))}"
            )
        return o

    def degree(self, orientation: ArrayLike | None = None) -> int:
        """``deg L = (1/2π) Σ_t o_t Ω_t`` over a closed oriented surface.

        Parameters
        ----------
        orientation : (n_2,) array of ±1, optional
            See :meth:`fundamental_cycle`; the default ``X.orientation()`` may be opposite to
            the orientation a mesh's face order means (the degree then changes sign).

        Raises
        ------
        NonManifoldError
            X is not a closed surface (names an edge with one triangle).
        NonOrientableError
            X is not orientable.
        """
        o = self.fundamental_cycle(orientation)
        total = float(o @ self._Om) / (2 * np.pi)
        deg = int(np.round(total))
        if abs(total - deg) > 1e-6 * max(1.0, float(np.abs(self._Om).sum()) / (2 * np.pi)):
            raise IntegralityError(f"∫Ω/2π = {total:.9g} is not an integer", cycle=o, defect=2 * np.pi * (total - deg))
        return deg

    def check_integrality(self) -> np.ndarray:
        """Theorem 7: periods ``∫_C Ω / 2π`` over an integer basis of 2-cycles (see :func:`check_integrality`)."""
        return check_integrality(self._X, self._Om, atol=self._atol)

    # ------------------------------------------------------------------ sections and indices
    def rotation_form(self, section: ArrayLike) -> np.ndarray:
        """Rotation form ξ of a nowhere-vanishing section (see :func:`dhlb.bundles.index.rotation_form`)."""
        return _sections.rotation_angles(self._X.simplices(1), _sections.checked_section(self._X, section),
                                         self.connection)

    def index_form(self, section: ArrayLike) -> np.ndarray:
        """Index form ``(dξ + Ω)/2π`` as int64 per triangle (see :func:`dhlb.bundles.index.index_form`)."""
        return _sections.index_values(self._X, self.rotation_form(section), self.curvature)
