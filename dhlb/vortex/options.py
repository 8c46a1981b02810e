"""The method knobs of :func:`~dhlb.vortex.vortex_filaments`, as one frozen value.

Examples
--------
>>> from dhlb.vortex import VortexOptions
>>> VortexOptions(order=4).replace(placement="vertex")
VortexOptions(order=4, placement='vertex', orientation='fix')
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

from dhlb._deprecation import check_choice, check_integer
from dhlb.vortex.velocity import DEFAULT_ORDER, MAX_ORDER

__all__ = ["DEFAULT_TOL", "VortexOptions"]

DEFAULT_TOL = 1e-9
"""Default backward-error tolerance of the eigen solve (see :func:`dhlb.fem.smallest_eigenpairs`)."""

PLACEMENTS = ("balanced", "vertex")
"""The values of :attr:`VortexOptions.placement` (:func:`~dhlb.vortex.face_zeros`)."""
ORIENTATIONS = ("fix", "require")
"""The values of :attr:`VortexOptions.orientation` (:func:`~dhlb.mesh.check_tet_mesh`)."""


@dataclass(frozen=True)
class VortexOptions:
    """How :func:`~dhlb.vortex.vortex_filaments` integrates and extracts (solver: :class:`~dhlb.linalg.SolverOptions`).

    Parameters
    ----------
    order : int in 1 .. 64
        Gauss–Legendre nodes per edge for a callable velocity (exact for polynomials of degree
        ``2·order − 1`` along the edge; at most 64: :func:`~dhlb.vortex.velocity.gauss_legendre` builds an
        ``order × order`` matrix). A Python or numpy integer, not a bool.
    placement : {"balanced", "vertex"}
        Local gauge in which the zero on a crossed triangle is interpolated
        (:func:`~dhlb.vortex.face_zeros`).
    orientation : {"fix", "require"}
        Passed to :func:`~dhlb.mesh.check_tet_mesh`: fix negatively oriented tetrahedra, or raise.

    Raises
    ------
    InvalidParameterError
        Bad ``order`` (an integer in 1 .. 64), ``placement`` or ``orientation``. Checked at construction,
        and again by :meth:`replace`.

    Examples
    --------
    >>> VortexOptions(placement="middle")
    Traceback (most recent call last):
    ...
    dhlb.errors.InvalidParameterError: VortexOptions.placement must be one of 'balanced', 'vertex', got 'middle'
    """

    order: int = DEFAULT_ORDER
    placement: str = "balanced"
    orientation: str = "fix"

    _EXAMPLE = "order=6"   # the example of a right call (dhlb._deprecation.check_option_group)

    def __post_init__(self) -> None:
        check_integer(self.order, "VortexOptions.order", 1, MAX_ORDER, why="Gauss-Legendre nodes per edge")
        check_choice(self.placement, "VortexOptions.placement", PLACEMENTS)
        check_choice(self.orientation, "VortexOptions.orientation", ORIENTATIONS)

    def replace(self, **changes: Any) -> VortexOptions:
        """A copy with some fields changed (:func:`dataclasses.replace`; validated again).

        Parameters
        ----------
        **changes
            Field names and their new values.

        Returns
        -------
        VortexOptions

        Examples
        --------
        >>> VortexOptions().replace(order=2).order
        2
        """
        return dataclasses.replace(self, **changes)
