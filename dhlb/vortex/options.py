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

from dhlb.errors import InvalidParameterError
from dhlb.vortex.velocity import DEFAULT_ORDER, gauss_legendre

__all__ = ["VortexOptions"]


@dataclass(frozen=True)
class VortexOptions:
    """How :func:`~dhlb.vortex.vortex_filaments` integrates and extracts (solver: :class:`~dhlb.linalg.SolverOptions`).

    Parameters
    ----------
    order : int >= 1
        Gauss–Legendre nodes per edge for a callable velocity (exact for polynomials of degree
        ``2·order − 1`` along the edge; at most 64).
    placement : {"balanced", "vertex"}
        Local gauge in which the zero on a crossed triangle is interpolated
        (:func:`~dhlb.vortex.face_zeros`).
    orientation : {"fix", "require"}
        Passed to :func:`~dhlb.mesh.check_tet_mesh`: fix negatively oriented tetrahedra, or raise.

    Raises
    ------
    InvalidParameterError
        Bad ``order`` (1 .. 64), ``placement`` or ``orientation``.

    Examples
    --------
    >>> VortexOptions(placement="middle")
    Traceback (most recent call last):
    ...
    dhlb.errors.InvalidParameterError: placement must be one of 'balanced', 'vertex', got 'middle'
    """

    order: int = DEFAULT_ORDER
    placement: str = "balanced"
    orientation: str = "fix"

    def __post_init__(self) -> None:
        gauss_legendre(self.order)  # integer in 1 .. MAX_ORDER
        for name, value, allowed in (("placement", self.placement, ("balanced", "vertex")),
                                     ("orientation", self.orientation, ("fix", "require"))):
            if not isinstance(value, str) or value not in allowed:
                raise InvalidParameterError(f"{name} must be one of {', '.join(map(repr, allowed))}, got {value!r}")

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
