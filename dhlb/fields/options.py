"""The method knobs of :func:`~dhlb.fields.direction_field` and :func:`~dhlb.fields.prescribed_field`.

Examples
--------
>>> from dhlb.fields import FieldOptions
>>> FieldOptions(lumped=True).replace(reorient=True)
FieldOptions(lumped=True, reorient=True, components='all', progress=False, repair='safe')
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

from dhlb._deprecation import check_choice, check_flag

__all__ = ["FieldOptions"]

COMPONENTS = ("all", "largest")
"""The values of ``components`` (:func:`dhlb.mesh.validate_surface`)."""


@dataclass(frozen=True)
class FieldOptions:
    """How a direction field is computed (the solver's own knobs are :class:`dhlb.linalg.SolverOptions`).

    Parameters
    ----------
    lumped : bool
        Use the lumped (diagonal) mass matrix instead of the consistent one of Theorem 15 (the
        seed's choice). For strongly aligned fields (λ_t ≪ 0) the consistent mass makes
        ``(A − λ_t M)⁻¹ M`` oscillate (M is not an M-matrix): spurious ±1 pairs appear near
        the guidance; the lumped mass avoids them. Not used by :func:`~dhlb.fields.prescribed_field`.
        Every flag of this class is ``True`` or ``False`` (a numpy bool counts; a truthy string such as
        ``"no"`` does not).
    reorient : bool
        Passed to :func:`dhlb.mesh.validate_surface`: fix inconsistently oriented faces.
    components : {"all", "largest"}
        Passed to :func:`dhlb.mesh.validate_surface`: keep every connected component, or only the largest.
    progress : bool
        Report the phases (setup, eigen solve, indices) on stderr with tqdm when the run is expected
        to take more than about two seconds (``pip install 'dhlb[progress]'``); the CLI passes
        ``not --quiet``. Not used by :func:`~dhlb.fields.prescribed_field`.
    repair : str or RepairOptions
        Which defects of the input mesh are repaired (:mod:`dhlb.mesh.repair`): ``"safe"`` (default:
        split non-manifold vertices and edges, merge duplicate faces, remove doubled sheets, drop faces
        repeating a vertex, reorient, mollify zero-area faces; each repair made is one
        :class:`~dhlb.errors.MeshRepairWarning`), ``"none"`` (every defect is an error), ``"all"``, or a
        comma-separated list (``"safe,merge-vertices"``). A mesh without defects is never changed.
        :func:`~dhlb.fields.distributed_direction_field` does not repair (repair the mesh first with
        :func:`dhlb.mesh.repair_surface`).

    Raises
    ------
    InvalidParameterError
        ``lumped``, ``reorient`` or ``progress`` not a bool (``True``/``False``, numpy bools included);
        ``components`` not ``"all"`` or ``"largest"``; an unknown ``repair``. Checked at construction,
        and again by :meth:`replace`.

    Examples
    --------
    >>> from dhlb.fields import FieldOptions, direction_field
    >>> from dhlb.io import read_surface, example_path
    >>> res = direction_field(*read_surface(example_path("torus.obj")), n=4, align="curvature", lam=-10.0,
    ...                       options=FieldOptions(lumped=True))
    >>> res.index_sum
    0
    """

    lumped: bool = False
    reorient: bool = False
    components: str = "all"
    progress: bool = False
    repair: Any = "safe"

    _EXAMPLE = "lumped=True"   # the example of a right call (dhlb._deprecation.check_option_group)

    def __post_init__(self) -> None:
        from dhlb.mesh.repair import RepairOptions

        for name in ("lumped", "reorient", "progress"):
            check_flag(getattr(self, name), f"FieldOptions.{name}")
        check_choice(self.components, "FieldOptions.components", COMPONENTS)
        RepairOptions.parse(self.repair)   # an unknown repair is an error here, not at the first mesh

    def replace(self, **changes: Any) -> FieldOptions:
        """A copy with some fields changed (:func:`dataclasses.replace`; validated again).

        Parameters
        ----------
        **changes
            Field names and their new values.

        Returns
        -------
        FieldOptions

        Examples
        --------
        >>> FieldOptions().replace(progress=True).progress
        True
        """
        return dataclasses.replace(self, **changes)
