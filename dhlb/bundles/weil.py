"""Weil's theorem for discrete hermitian line bundles (seed part 3, §7).

* Theorem 7: the curvature of a hermitian line bundle is *integral*: ``∫_C Ω ∈ 2πZ`` for every
  integer 2-cycle C.  :func:`check_integrality` tests this on an integer basis of ker ∂₂.
* Theorem 8: every closed integral Ω is the curvature of some bundle.
  :func:`line_bundle_with_curvature` constructs one (:mod:`dhlb.bundles._mod2pi`: collapses of
  the complex plus a small Smith form) and keeps Ω exactly as given.
* Remark 7: bundles with curvature Ω, up to isomorphism, form a torsor over
  ``H¹(X; S¹) = Hom(H₁(X), S¹) ≅ (S¹)^{b₁} × ⊕ Z/d``.  :class:`BundlesWithCurvature` makes this
  explicit: free part = holonomy angles around the free generators of H₁, torsion part = one
  residue ``k mod d`` per torsion generator (holonomy ``h₀ + 2πk/d``, with ``h₀`` that of the base
  bundle; for flat bundles ``h₀ = 0``).

The integer 2-cycles tested and the test itself live in :mod:`dhlb.bundles.integrality`.

Examples
--------
>>> import numpy as np
>>> from dhlb.examples import projective_plane
>>> X = projective_plane()
>>> A, B = flat_line_bundles(X)                          # H¹(RP²; S¹) = Z/2
>>> A.is_isomorphic(B), bundles_with_curvature(X, np.zeros(X.n_simplices(2))).torsion_orders
(False, (2,))
"""

from __future__ import annotations

import itertools
from typing import TYPE_CHECKING

import numpy as np

from dhlb.bundles._mod2pi import solve_mod_2pi
from dhlb.bundles.hermitian import HermitianLineBundle, _real_vector
from dhlb.bundles.integrality import _check_closed, check_integrality, integer_cycle_basis
from dhlb.errors import CurvatureMismatchError, IntegralityError, InvalidConnectionError
from dhlb.forms.groups import wrap_angle

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from dhlb.topology.complex import SimplicialComplex

__all__ = [
    "integer_cycle_basis",
    "check_integrality",
    "line_bundle_with_curvature",
    "BundlesWithCurvature",
    "bundles_with_curvature",
    "flat_line_bundles",
]



def line_bundle_with_curvature(
    X: SimplicialComplex, Omega: ArrayLike, holonomy: ArrayLike | None = None, *, atol: float = 1e-8
) -> HermitianLineBundle:
    """A hermitian line bundle whose curvature is exactly ``Omega`` (Theorem 8).

    Parameters
    ----------
    X : SimplicialComplex
        A complex of dimension >= 2.
    Omega : (n_2,) float array_like
        Real, closed and integral; one value per row of ``X.simplices(2)``.
    holonomy : None or ``(free_angles, torsion)``
        Which bundle in the H¹(X; S¹)-torsor (see :class:`BundlesWithCurvature`); ``None``
        returns the base bundle of the construction. A dict with keys ``"free"`` and
        ``"torsion"`` is accepted too.
    atol : float, default 1e-8
        Tolerance of the closedness and integrality tests.

    Returns
    -------
    HermitianLineBundle
        A bundle whose ``curvature`` is ``Omega`` (the same values, not recomputed).

    Raises
    ------
    NotClosedError
        ``dΩ ≠ 0`` on a tetrahedron (named).
    IntegralityError
        Ω is not integral; ``.cycle`` is a violating integer 2-cycle, ``.defect`` its defect.
    InvalidConnectionError
        ``Omega`` is not a real vector of length ``n_2``; ``holonomy`` has the wrong number of
        free angles or torsion residues.
    NonFiniteError
        ``Omega`` contains NaN or infinity.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.examples import torus
    >>> X = torus()
    >>> Om = np.full(X.n_simplices(2), 2 * np.pi * 3 / X.n_simplices(2)) * X.orientation()
    >>> L = line_bundle_with_curvature(X, Om)
    >>> L.degree(), bool(np.array_equal(L.curvature, Om))
    (3, True)
    """
    Om = _real_vector(Omega, X.n_simplices(2), "Ω")
    _check_closed(X, Om, atol)
    if holonomy is not None:
        return BundlesWithCurvature(X, Om, atol=atol).bundle(*_split_holonomy(holonomy))
    check_integrality(X, Om, atol=atol)
    sol = solve_mod_2pi(X, Om)
    if not sol.consistent:  # pragma: no cover - excluded by check_integrality
        raise IntegralityError(
            f"Ω is not integral (residual {sol.defect:.3g} in the deferred equations)", defect=sol.defect
        )
    return HermitianLineBundle.from_angles(X, sol.omega(), Om, atol=atol)


def _split_holonomy(holonomy):
    if isinstance(holonomy, dict):
        return holonomy.get("free"), holonomy.get("torsion")
    free, torsion = holonomy
    return free, torsion


class BundlesWithCurvature:
    """All hermitian line bundles with curvature Ω up to isomorphism: a torsor over H¹(X; S¹).

    Parameters
    ----------
    X : SimplicialComplex
        A complex of dimension >= 2.
    Omega : (n_2,) float array_like
        Real, closed and integral; one value per row of ``X.simplices(2)``.
    atol : float, default 1e-8
        Tolerance of the closedness and integrality tests and of :meth:`coordinates`.

    Raises
    ------
    NotClosedError
        ``dΩ ≠ 0`` on a tetrahedron.
    IntegralityError
        Ω is not integral.
    InvalidConnectionError
        ``Omega`` is not a real vector of length ``n_2``.
    NonFiniteError
        ``Omega`` contains NaN or infinity.

    Attributes
    ----------
    base : HermitianLineBundle
        The bundle of :func:`line_bundle_with_curvature`.
    b1 : int
        Dimension of the torus part (first Betti number).
    torsion_orders : tuple of int
        Orders ``d`` of the torsion generators of H₁(X; Z).
    generators : (n_1, b1 + t) int
        H₁ generators (free first, then torsion), from :func:`dhlb.topology.homology.homology`.
    cocycles : (n_1, b1 + t) float
        Their dual S¹ cocycles (from :func:`dhlb.topology.homology.cohomology` with ``"S1"``).

    Examples
    --------
    >>> from dhlb.examples import projective_plane
    >>> X = projective_plane()
    >>> F = BundlesWithCurvature(X, np.zeros(X.n_simplices(2)))
    >>> L = F.bundle(torsion=[1])                                   # holonomy π on the generator of H₁
    >>> F.torsion_orders, F.coordinates(L)[1], L.is_isomorphic(F.base)
    ((2,), (1,), False)
    """

    def __init__(self, X: SimplicialComplex, Omega: ArrayLike, *, atol: float = 1e-8):
        from dhlb.topology.homology import cohomology, homology

        self.X = X
        self.atol = atol
        self.base = line_bundle_with_curvature(X, Omega, atol=atol)
        H1 = homology(X)[1] if X.dim >= 1 else None
        C1 = cohomology(X, "S1")[1] if X.dim >= 1 else None
        n1 = X.n_simplices(1)
        self.b1 = H1.rank if H1 else 0
        self.torsion_orders = tuple(int(t) for t in H1.torsion) if H1 else ()
        self.generators = np.asarray(H1.generators, dtype=np.int64) if H1 else np.zeros((n1, 0), np.int64)
        self.cocycles = np.asarray(C1.cocycles, dtype=np.float64) if C1 else np.zeros((n1, 0))
        self._h0 = np.array([self.base.holonomy(g) for g in self.generators.T])
        self._pair_free = self.generators[:, : self.b1].T @ self.cocycles[:, : self.b1]

    def __repr__(self) -> str:
        return f"BundlesWithCurvature(b1={self.b1}, torsion_orders={self.torsion_orders})"

    def bundle(self, free_angles: ArrayLike | None = None, torsion: ArrayLike | None = None) -> HermitianLineBundle:
        """The bundle with the given holonomy around the generators of H_1.

        Its holonomy is ``free_angles[i]`` around free generator i and ``h₀ + 2π torsion[j] / d_j``
        around torsion generator j.
        """
        b, t = self.b1, len(self.torsion_orders)
        theta = np.zeros(b) if free_angles is None else np.asarray(free_angles, dtype=np.float64).reshape(-1)
        k = np.zeros(t, np.int64) if torsion is None else np.asarray(torsion, dtype=np.int64).reshape(-1)
        if theta.size != b or k.size != t:
            raise InvalidConnectionError(
                f"holonomy needs {b} free angles and {t} torsion residues, got {theta.size} and {k.size}"
            )
        # the free cocycles are dual to the free generators (pairing = identity); solve anyway
        x = np.linalg.solve(self._pair_free, theta - self._h0[:b]) if b else np.zeros(0)
        shift = self.cocycles[:, :b] @ x + self.cocycles[:, b:] @ k
        return HermitianLineBundle.from_angles(
            self.X, self.base.connection_angles + shift, self.base.curvature, atol=self.atol
        )

    def coordinates(self, L: HermitianLineBundle) -> tuple[np.ndarray, tuple]:
        """``(free_angles, torsion)`` of a bundle with the same curvature (inverse of :meth:`bundle`)."""
        if not np.allclose(L.curvature, self.base.curvature, rtol=0, atol=self.atol * 10):
            raise CurvatureMismatchError("the bundle has a different curvature; it is not in this family")
        h = np.array([L.holonomy(g) for g in self.generators.T])
        b = self.b1
        d = np.array(self.torsion_orders, dtype=np.float64)
        k = np.round(wrap_angle(h[b:] - self._h0[b:]) * d / (2 * np.pi)).astype(np.int64)
        k %= np.maximum(d, 1).astype(np.int64)
        return wrap_angle(h[:b]), tuple(int(x) for x in k)

    def enumerate_torsion(self, free_angles: ArrayLike | None = None) -> list:
        """One bundle per torsion residue vector (``Π d`` of them) with the given free angles."""
        ranges = [range(d) for d in self.torsion_orders]
        return [self.bundle(free_angles, ks) for ks in itertools.product(*ranges)]


def bundles_with_curvature(X: SimplicialComplex, Omega: ArrayLike, *, atol: float = 1e-8) -> BundlesWithCurvature:
    """The H¹(X; S¹)-parametrized family of bundles with curvature Ω (Remark 7).

    Parameters
    ----------
    X : SimplicialComplex
        A complex of dimension >= 2.
    Omega : (n_2,) float array_like
        Real, closed and integral; one value per row of ``X.simplices(2)``.
    atol : float, default 1e-8
        Tolerance of the closedness and integrality tests.

    Returns
    -------
    BundlesWithCurvature
        The family, with its base bundle and the coordinates of H¹(X; S¹).

    Raises
    ------
    NotClosedError
        ``dΩ ≠ 0`` on a tetrahedron.
    IntegralityError
        Ω is not integral.
    InvalidConnectionError
        ``Omega`` is not a real vector of length ``n_2``.

    Examples
    --------
    >>> from dhlb.examples import torus
    >>> X = torus()
    >>> F = bundles_with_curvature(X, np.zeros(X.n_simplices(2)))
    >>> F.b1, F.torsion_orders, F.base.degree()
    (2, (), 0)
    """
    return BundlesWithCurvature(X, Omega, atol=atol)


def flat_line_bundles(X: SimplicialComplex, free_angles: ArrayLike | None = None, *, atol: float = 1e-8) -> list:
    """The flat hermitian line bundles with the given free holonomies, one per torsion class.

    Over RP² there are exactly two (holonomy 0 and π); over the torus the list has one
    element for each choice of the two free angles.

    Parameters
    ----------
    X : SimplicialComplex
        A complex of dimension >= 2.
    free_angles : (b1,) float array_like, optional
        The holonomy around each free generator of H₁(X; Z) (default: all 0).
    atol : float, default 1e-8
        Tolerance of the construction.

    Returns
    -------
    list of HermitianLineBundle
        One flat bundle per torsion residue vector: ``Π d`` of them, ``d`` the torsion orders
        of H₁(X; Z).

    Raises
    ------
    InvalidConnectionError
        ``free_angles`` does not have ``b1`` entries.

    Examples
    --------
    >>> from dhlb.examples import projective_plane, torus
    >>> len(flat_line_bundles(projective_plane())), len(flat_line_bundles(torus(), [np.pi / 2, 0.0]))
    (2, 1)
    """
    return BundlesWithCurvature(X, np.zeros(X.n_simplices(2)), atol=atol).enumerate_torsion(free_angles)
