"""What :func:`~dhlb.vortex.vortex_filaments` returns.

:class:`VortexResult` (filaments, section, bundle, linking numbers).
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from dhlb._deprecation import warn_moved
from dhlb._result import Result
from dhlb.mesh.tet import TetMesh

if TYPE_CHECKING:
    from typing import Any


__all__ = ["VortexResult"]


@dataclass(frozen=True, eq=False)
class VortexResult(Result):
    """What :func:`vortex_filaments` found.

    Parameters
    ----------
    filaments : list of Filament
        Oriented polylines (``.points`` (m, 3), ``.closed``, ``.faces``): closed loops, and chains
        from boundary to boundary.  A filament runs so that the flow circulates right-handedly
        about it (like the input curve of a :class:`~dhlb.vortex.FilamentField` with ``Γ > 0``).
    psi : (N,) complex128
        The section in the frames of :attr:`bundle` (compact vertex order of ``mesh.complex``),
        with unit L² norm ``ψᴴ M ψ = 1``.
    eigenvalue : float
        Its Dirichlet energy ``ψᴴ A ψ`` (the smallest eigenvalue).
    linking_numbers : (c, c) int64
        Gauss linking numbers among the closed filaments (zero diagonal); row ``a`` belongs to
        ``filaments[linking_index[a]]``.
    linking_index : (c,) int64
        Positions in :attr:`filaments` of the closed filaments.
    statistics : dict
        ``n_vertices``, ``n_edges``, ``n_triangles``, ``n_tets``, ``hbar``, ``max_flux`` (max
        ``|Ω|`` over triangles), ``n_unresolved_faces`` (``|Ω| > π``), ``n_crossed_faces``,
        ``tets_by_crossed_faces`` (``{"0": …, "2": …}``; 3 or 4 mean a tetrahedron crossed
        twice), ``n_filaments``, ``n_closed``, ``n_open``, ``ambiguous_tets``, ``tie_edges``,
        ``clamped_faces``, ``degenerate_faces`` (counts, see :class:`~dhlb.vortex.FilamentSet`),
        ``linking_defect`` (largest distance of a Gauss integral from its integer), and
        ``solver`` (``backend``, ``iterations``, ``converged``, ``residual``, ``shift``).
    timings : dict
        Seconds per phase: ``mesh``, ``omega``, ``assembly``, ``solve``, ``extraction``, ``total``.
    mesh : TetMesh
    bundle : HermitianLineBundle
        ``r = exp(iω/ħ)``, ``Ω = dω/ħ``.
    filament_set : FilamentSet
        The full extraction result (index form, ambiguous tetrahedra, ties, clamped faces).
    matrices : tuple (A, M)
        The Dirichlet and mass matrices (complex Hermitian CSR).

    Examples
    --------
    >>> from dhlb.mesh import box_tet_mesh
    >>> from dhlb.vortex import uniform_flow, vortex_filaments
    >>> res = vortex_filaments(box_tet_mesh(4), None, uniform_flow([0.3, 0.0, 0.0]), hbar=1.0)   # a gradient
    >>> len(res.filaments), bool(abs(res.eigenvalue) < 1e-10), res.statistics["n_tets"], res.linking_numbers.shape
    (0, True, 384, (0, 0))
    """

    filaments: list
    psi: np.ndarray
    eigenvalue: float
    linking_numbers: np.ndarray
    linking_index: np.ndarray
    statistics: dict
    timings: dict
    mesh: TetMesh = field(repr=False)
    bundle: object = field(repr=False)
    filament_set: object = field(repr=False)
    matrices: tuple = field(repr=False)

    def __repr__(self) -> str:
        s = self.statistics
        return (f"VortexResult({s['n_filaments']} filaments ({s['n_closed']} closed, {s['n_open']} open) on "
                f"{s['n_tets']} tets, ħ = {s['hbar']:.4g}, λ = {self.eigenvalue:.6g}, "
                f"{self.timings['total']:.3g} s)")

    def summary_rows(self) -> list[tuple[str, object]]:
        """The headline numbers, as ``(label, value)`` pairs (the ``dhlb`` report and notebooks).

        Returns
        -------
        list of (str, object)
        """
        s = self.statistics
        return [("filaments", f"{s['n_filaments']} ({s['n_closed']} closed, {s['n_open']} open)"),
                ("vertices, tetrahedra", f"{s['n_vertices']}, {s['n_tets']}"), ("eigenvalue", f"{self.eigenvalue:.6g}"),
                ("time", f"{self.timings.get('total', float('nan')):.3g} s")]

    def to_json(self, **kwargs: Any) -> dict:
        """A JSON-ready summary.

        Parameters
        ----------
        **kwargs
            Deprecated: ``to_json(indent=...)`` returned a string in dhlb 0.1; with keyword arguments it
            still returns ``json.dumps(self.to_json(), **kwargs)`` and warns.

        Returns
        -------
        dict
            Keys ``filaments`` (``[{"points": [[x, y, z], …], "closed": bool}]``), ``linking_numbers``,
            ``linking_index``, ``timings``, ``eigenvalue``, ``statistics``.
        """
        if kwargs:
            warn_moved("VortexResult.to_json(**kwargs) returning a str", "json.dumps(result.to_json(), **kwargs)")
            return json.dumps(self.to_json(), **kwargs)
        return {
            "filaments": [{"points": f.points.tolist(), "closed": bool(f.closed)} for f in self.filaments],
            "linking_numbers": self.linking_numbers.tolist(),
            "linking_index": self.linking_index.tolist(),
            "timings": dict(self.timings),
            "eigenvalue": float(self.eigenvalue),
            "statistics": self.statistics,
        }

    def to_dict(self) -> dict:
        """Deprecated alias of :meth:`to_json` (every result's ``to_json`` returns a dict).

        Returns
        -------
        dict
            :meth:`to_json`.
        """
        warn_moved("VortexResult.to_dict()", "VortexResult.to_json()")
        return self.to_json()
