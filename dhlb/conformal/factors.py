r"""Target log conformal factors ``u: R³ → R`` with their gradients.

A :class:`ConformalFactor` is a callable ``u(x)`` on ``(m, 3)`` points with an exact
``gradient(x)`` (used for the edge values of ``grad u`` in the connection) and the list of its
singular points (which must lie outside the mesh).  Two families:

* :func:`point_charge_factor`: ``u(x) = Σ_k q_k / |x − a_k|``, the Coulomb potential of point
  charges (the seed's Figure 5); harmonic, not a Möbius factor, so the deformation is only
  close to conformal;
* :func:`mobius_factor`: ``u(x) = log(R² / |x − a|²)``, the factor of the inversion in the
  sphere ``(a, R)``; its connection is flat and the deformation is a Möbius transformation.

Gradients are derived in ``proofs/derive_conformal_quaternion.py`` (parts 4 and 7).

Examples
--------
>>> import numpy as np
>>> u = point_charge_factor([[0.0, 0.0, 2.0, 1.0]])        # charge 1 at (0, 0, 2)
>>> float(u(np.zeros((1, 3)))[0]), u.gradient(np.zeros((1, 3))).tolist()
(0.5, [[0.0, 0.0, 0.25]])
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from dhlb._coerce import as_points
from dhlb.errors import InvalidParameterError, NonFiniteError, ShapeError

if TYPE_CHECKING:
    from collections.abc import Callable

    from numpy.typing import ArrayLike

__all__ = ["ConformalFactor", "mobius_factor", "point_charge_factor"]


class ConformalFactor:
    """A log conformal factor ``u`` with its gradient and singular points.

    Parameters
    ----------
    value : callable
        ``u`` itself, mapping ``(m, 3)`` points to ``(m,)`` values.
    gradient : callable
        ``grad u``, mapping ``(m, 3)`` points to ``(m, 3)`` vectors.
    singularities : (s, 3) float array, optional
        Points where ``u`` is singular; :func:`~dhlb.conformal.conformal_deformation` refuses a
        mesh that contains one of them.
    name : str, optional
        A short description (used in reports).
    labels : list of str, optional
        One name per singular point (e.g. ``"charge #0 (q = 1)"``).
    charges : (k, 4) float array, optional
        For the potential of point charges, their rows ``(x, y, z, q)`` (kept as the attribute
        ``charges``, else None; scaling the factor scales the ``q``).

    Examples
    --------
    >>> import numpy as np
    >>> u = ConformalFactor(lambda x: x[:, 0] ** 2, lambda x: np.c_[2 * x[:, 0], 0 * x[:, :2]], name="x^2")
    >>> v = 0.5 * u                                            # scaling keeps the gradient exact
    >>> float(v(np.array([[2.0, 0, 0]]))[0]), v.gradient(np.array([[2.0, 0, 0]])).tolist(), v.name
    (2.0, [[2.0, 0.0, 0.0]], '0.5 * x^2')
    """

    def __init__(self, value: Callable, gradient: Callable, *, singularities: ArrayLike | None = None,
                 name: str = "u", labels: list[str] | None = None, charges: ArrayLike | None = None):
        self._value = value
        self._gradient = gradient
        S = np.zeros((0, 3)) if singularities is None else np.asarray(singularities, dtype=np.float64).reshape(-1, 3)
        self.singularities = S
        self.labels = list(labels) if labels is not None else [f"singular point #{k}" for k in range(S.shape[0])]
        self.name = name
        self.charges = None if charges is None else np.asarray(charges, dtype=np.float64).reshape(-1, 4)

    def __call__(self, x: ArrayLike) -> np.ndarray:
        """Values ``u(x)`` at ``(m, 3)`` points."""
        return np.asarray(self._value(as_points(x, "points", finite=False)), dtype=np.float64)

    def gradient(self, x: ArrayLike) -> np.ndarray:
        """``grad u`` at ``(m, 3)`` points, shape ``(m, 3)``.

        Examples
        --------
        >>> mobius_factor((0.0, 0.0, 0.0), 1.0).gradient([[2.0, 0.0, 0.0]]).tolist()   # −2 r/|r|²
        [[-1.0, -0.0, -0.0]]
        """
        return np.asarray(self._gradient(as_points(x, "points", finite=False)), dtype=np.float64)

    def __mul__(self, s: float) -> ConformalFactor:
        if not (np.isscalar(s) and np.isfinite(s)):
            raise InvalidParameterError(f"a conformal factor can only be scaled by a finite number, got {s!r}")
        s = float(s)
        C = None if self.charges is None else self.charges * [1.0, 1.0, 1.0, s]
        return ConformalFactor(lambda x: s * self._value(x), lambda x: s * self._gradient(x),
                               singularities=self.singularities, name=f"{s:g} * {self.name}", labels=self.labels,
                               charges=C)

    __rmul__ = __mul__

    def __repr__(self) -> str:
        return f"ConformalFactor({self.name!r}, {self.singularities.shape[0]} singular points)"


def _charges(charges) -> np.ndarray:
    try:
        C = np.asarray(charges, dtype=np.float64)
    except (TypeError, ValueError):
        raise ShapeError("charges must be rows (x, y, z, q)") from None
    if C.ndim == 1 and C.size == 4:
        C = C[None, :]
    if C.ndim != 2 or C.shape[1] != 4 or C.shape[0] == 0:
        raise ShapeError(f"charges must be a non-empty array of rows (x, y, z, q), shape (k, 4); got {C.shape}")
    bad = ~np.isfinite(C).all(axis=1)
    if np.any(bad):
        k = int(np.argmax(bad))
        raise NonFiniteError(f"charge #{k} = {C[k].tolist()} is not finite")
    return C


def point_charge_factor(charges: ArrayLike) -> ConformalFactor:
    """``u(x) = Σ_k q_k / |x − a_k|``: the potential of point charges ``q_k`` at ``a_k``.

    Parameters
    ----------
    charges : (k, 4) float array
        One row ``(x, y, z, q)`` per charge: its position ``a_k`` and charge ``q_k`` (one row may be
        given as 4 numbers).

    Returns
    -------
    ConformalFactor
        With ``grad u = −Σ q_k (x − a_k)/|x − a_k|³`` and the charges as singular points.

    Raises
    ------
    ShapeError, NonFiniteError
        Not rows of four numbers; a NaN/inf entry (the charge is named).

    Examples
    --------
    >>> import numpy as np
    >>> u = point_charge_factor([[0, 0, 3, 1.5], [0, 0, -3, -1.5]])   # a dipole
    >>> float(u([[0.0, 0.0, 0.0]])[0]), u.labels[1]
    (0.0, 'charge #1 (q = -1.5) at (0, 0, -3)')
    """
    C = _charges(charges)
    A, q = C[:, :3], C[:, 3]

    def value(x):
        r = np.linalg.norm(x[:, None, :] - A[None], axis=2)
        return (q[None] / r).sum(axis=1)

    def gradient(x):
        d = x[:, None, :] - A[None]
        r = np.linalg.norm(d, axis=2)
        return -np.einsum("mk,mkc->mc", q[None] / r**3, d)

    labels = [f"charge #{k} (q = {q[k]:g}) at ({A[k, 0]:g}, {A[k, 1]:g}, {A[k, 2]:g})" for k in range(len(q))]
    return ConformalFactor(value, gradient, singularities=A, name=f"{len(q)} point charges", labels=labels,
                           charges=C)


def mobius_factor(center: ArrayLike, radius: float = 1.0) -> ConformalFactor:
    """``u(x) = log(R² / |x − a|²)``: the conformal factor of the inversion in the sphere ``(a, R)``.

    ``grad u = −2 (x − a)/|x − a|²``; the orientation-preserving Möbius map with this factor is
    ``x ↦ S(a + R² (x − a)/|x − a|²)`` for any reflection ``S``.

    Parameters
    ----------
    center : 3 floats
        The center ``a`` of the sphere (the singular point of ``u``).
    radius : float > 0, optional
        The radius ``R`` of the sphere (``u = 0`` on it).

    Returns
    -------
    ConformalFactor
        With ``grad u = −2 (x − a)/|x − a|²`` and the center as its singular point.

    Raises
    ------
    InvalidParameterError
        ``center`` is not 3 finite numbers, or ``radius`` is not a finite number > 0.

    Examples
    --------
    >>> u = mobius_factor((3.0, 0.0, 0.0), 2.0)
    >>> float(u([[1.0, 0.0, 0.0]])[0])                          # log(4/4)
    0.0
    """
    a = np.asarray(center, dtype=np.float64)
    if a.shape != (3,) or not np.all(np.isfinite(a)):
        raise InvalidParameterError(f"center must be 3 finite numbers, got {center!r}")
    if not (np.isscalar(radius) and np.isfinite(radius) and radius > 0):
        raise InvalidParameterError(f"radius must be a finite number > 0, got {radius!r}")
    R2 = float(radius) ** 2

    def value(x):
        return np.log(R2 / ((x - a) ** 2).sum(axis=1))

    def gradient(x):
        d = x - a
        return -2.0 * d / (d**2).sum(axis=1)[:, None]

    return ConformalFactor(value, gradient, singularities=a[None], name=f"Möbius (inversion in the sphere "
                           f"({a[0]:g}, {a[1]:g}, {a[2]:g}), R = {float(radius):g})",
                           labels=[f"the centre ({a[0]:g}, {a[1]:g}, {a[2]:g}) of the inversion"])
