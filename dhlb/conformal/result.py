"""What :func:`~dhlb.conformal.conformal_deformation` returns.

:class:`ConformalResult` (deformed points, φ, distortion).
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from dhlb.errors import (
    InvalidParameterError,
)
from dhlb.mesh.tet import TetMesh

if TYPE_CHECKING:
    from typing import Any


__all__ = ["ConformalResult"]


@dataclass(frozen=True, eq=False)
class ConformalResult:
    """What :func:`conformal_deformation` computed.

    Attributes
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

    def save(self, path: str | os.PathLike[str]) -> list[str]:
        """Write the result: ``.json`` (:meth:`to_json`), ``.mesh``/``.msh``/``.vtk`` (tets), ``.vtu`` or ``.npz``.

        ``.vtu`` (needs meshio, ``dhlb[meshio]``) holds the deformed tets with ``phi``, ``u`` and
        ``input_points`` per vertex and ``distortion``, ``scale_error`` per tet, for ParaView.

        Parameters
        ----------
        path : str or path-like
            The extension chooses the format.

        Returns
        -------
        list of str
            The paths written.

        Examples
        --------
        >>> import os, tempfile
        >>> from dhlb.io import read_volume
        >>> from dhlb.conformal import conformal_deformation
        >>> from dhlb.mesh import box_tet_mesh
        >>> res = conformal_deformation(box_tet_mesh(1), None, 0.0)
        >>> with tempfile.TemporaryDirectory() as d:
        ...     paths = res.save(os.path.join(d, "f.vtk"))
        ...     print(read_volume(paths[0])[1].shape)
        (6, 4)
        """
        from dhlb._files import atomic_write

        out = os.fspath(path)
        ext = os.path.splitext(out)[1].lower()
        if ext == ".json":
            with atomic_write(out, "w") as fh:
                json.dump(self.to_json(), fh)
        elif ext == ".npz":
            with atomic_write(out, "wb") as fh:
                np.savez(fh, points=self.points, tets=self.mesh.tets, phi=self.phi, u=self.u,
                         distortion=self.distortion, scale_error=self.scale_error, eigenvalue=self.eigenvalue)
        elif ext in (".mesh", ".msh", ".vtk"):
            from dhlb.io import write_volume

            write_volume(out, self.points, self.mesh.tets)
        elif ext == ".vtu":  # ParaView: the deformed tets with φ, u and the input points; distortion per tet
            from dhlb.io.meshio_bridge import write_vtu_volume

            write_vtu_volume(out, self.points, self.mesh.tets,
                             point_data={"phi": self.phi, "u": self.u, "input_points": self.mesh.points},
                             cell_data={"distortion": self.distortion, "scale_error": self.scale_error},
                             field_data={"eigenvalue": [float(self.eigenvalue)]})
        else:
            raise InvalidParameterError(f"cannot save a conformal deformation as {ext or 'a file without extension'!r}"
                                        f" ({out}); use .json, .npz, .mesh, .msh, .vtk or .vtu (ParaView, meshio)")
        return [out]
