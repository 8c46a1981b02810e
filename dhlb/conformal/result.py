"""What :func:`~dhlb.conformal.conformal_deformation` returns.

:class:`ConformalResult` (deformed points, φ, distortion).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from dhlb._result import Result
from dhlb.mesh.tet import TetMesh

if TYPE_CHECKING:
    from typing import Any


__all__ = ["ConformalResult"]


@dataclass(frozen=True, eq=False)
class ConformalResult(Result):
    """What :func:`conformal_deformation` computed.

    Parameters
    ----------
    points : (N, 3) float64
        The deformed vertices ``f`` (compact vertex order of ``mesh.complex``; equal to the input
        row order unless the input had unused vertices).
    phi : (N, 4) float64
        The unit quaternion ``φ = ψ/|ψ|`` per vertex (w, x, y, z); ``df(X) ≈ e^u φ̄ X φ``.
    eigenvalue : float
        ``λ₁ = ψᴴAψ / ψᴴMψ``, the connection energy of ψ (0 iff the discrete connection has a
        parallel section).
    distortion : (m,) float64
        Per tet (rows of ``mesh.tets``): ``σ_max/σ_min`` of the deformation gradient (1: conformal).
    scale_error : (m,) float64
        Per tet: ``log(mean σ) − u`` with ``u`` the mean of its vertex values.
    u : (N,) float64
        The target log conformal factor at the vertices.
    statistics : dict
        Counts, the solver report, ``inverted_tets`` (``det F <= 0``), distortion / scale-error
        summaries, ``max_edge_angle`` (largest ``|½ g × e|``, the rotation angle of a transport).
    timings : dict
        Seconds per phase: ``mesh``, ``factor``, ``bundle``, ``solve``, ``map``, ``quality``, ``total``.
    mesh : TetMesh
    bundle : VectorBundle
        The complex rank-2 bundle (:func:`quaternion_bundle`).
    edge_gradient : (n_1, 3) float64
        The value of grad u used on every canonical edge.

    Examples
    --------
    >>> from dhlb.conformal import conformal_deformation
    >>> from dhlb.mesh import box_tet_mesh
    >>> res = conformal_deformation(box_tet_mesh(2), None, 0.5)            # u = 1/2: scale by e^{1/2}
    >>> bool(abs(res.distortion.max() - 1) < 1e-9), sorted(res.to_json())[:4]
    (True, ['distortion', 'eigenvalue', 'phi', 'points'])
    """

    points: np.ndarray
    phi: np.ndarray
    eigenvalue: float
    distortion: np.ndarray
    scale_error: np.ndarray
    u: np.ndarray
    statistics: dict
    timings: dict
    mesh: TetMesh = field(repr=False)
    bundle: Any = field(repr=False)
    edge_gradient: np.ndarray = field(repr=False)

    def __repr__(self) -> str:
        s = self.statistics
        return (f"ConformalResult({s['n_vertices']} vertices, {s['n_tets']} tets, λ₁ = {self.eigenvalue:.4g}, "
                f"distortion mean {s['distortion_mean']:.4g} max {s['distortion_max']:.4g}, "
                f"{self.timings['total']:.3g} s)")

    def summary_rows(self) -> list[tuple[str, object]]:
        """The headline numbers, as ``(label, value)`` pairs (the ``dhlb`` report and notebooks).

        Returns
        -------
        list of (str, object)
        """
        s = self.statistics
        return [("vertices, tetrahedra", f"{s['n_vertices']}, {s['n_tets']}"), ("λ₁", f"{self.eigenvalue:.6g}"),
                ("distortion mean, max", f"{s['distortion_mean']:.4g}, {s['distortion_max']:.4g}"),
                ("inverted tets", s["inverted_tets"]), ("time", f"{self.timings.get('total', float('nan')):.3g} s")]

    def to_json(self) -> dict:
        """A JSON-ready dict of the result.

        Keys ``points``, ``tets``, ``phi``, ``u``, ``distortion``, ``scale_error``, ``eigenvalue``,
        ``statistics``, ``timings``.

        Examples
        --------
        >>> import json
        >>> from dhlb.conformal import conformal_deformation
        >>> from dhlb.mesh import box_tet_mesh
        >>> d = conformal_deformation(box_tet_mesh(1), None, 0.0).to_json()
        >>> len(d["points"]), len(d["tets"]), len(json.dumps(d)) > 100
        (8, 6, True)
        """
        return {
            "points": self.points.tolist(),
            "tets": self.mesh.tets.tolist(),
            "phi": self.phi.tolist(),
            "u": self.u.tolist(),
            "distortion": self.distortion.tolist(),
            "scale_error": self.scale_error.tolist(),
            "eigenvalue": float(self.eigenvalue),
            "statistics": self.statistics,
            "timings": dict(self.timings),
        }
