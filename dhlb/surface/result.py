"""The result of :func:`dhlb.surface.direction_field`: the field, its indices and how it was computed."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from dhlb.surface.directions import FieldIndices, Singularities
from dhlb.surface.guidance import Guidance
from dhlb.surface.mesh import SurfaceMesh
from dhlb.surface.tangent import TangentBundle

__all__ = ["DirectionField"]


@dataclass(frozen=True, eq=False)
class DirectionField:
    """An n-direction field on a triangle mesh (compact vertex order of ``mesh``).

    Attributes
    ----------
    n, s, lam : the symmetry, the energy parameter and λ_t of the aligned problem
    tangent : TangentBundle (``.mesh``, ``.frames``, ``.bundle``)
    u : (N,) complex, power representation in the vertex frames, ``uᴴ M u = 1``
    directions : (N, n, 3) unit 3D directions (zero rows where ``u = 0``)
    indices : FieldIndices (per face, mesh orientation; Poincaré–Hopf terms; singularities)
    energy : float, ``uᴴ A_s u`` (twice the energy E_s of the M-normalized field)
    eigenvalue : float or None, smallest eigenvalue (the largest over components); None if aligned
    t : float or None, ``(1 + ‖ũ‖_M)⁻¹`` of the aligned problem (Eq. 6.6)
    guidance : Guidance or None
    component_eigenvalues : tuple of float, one per connected component (smoothest field)
    solver : dict, backend, iterations, residual, converged
    timings : dict, seconds per phase (setup, solve, indices, total)

    Examples
    --------
    >>> from dhlb.surface import direction_field
    >>> V = [[0, 0, 1], [0, 0, -1], [1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0]]
    >>> F = [[0, 2, 4], [0, 4, 3], [0, 3, 5], [0, 5, 2], [1, 4, 2], [1, 3, 4], [1, 5, 3], [1, 2, 5]]
    >>> res = direction_field(V, F, n=1)
    >>> res.n, res.u.shape, res.directions.shape, res.indices.total
    (1, (6,), (6, 1, 3), 2)
    """

    n: int
    s: float
    lam: float
    tangent: TangentBundle
    u: np.ndarray
    directions: np.ndarray
    indices: FieldIndices
    energy: float
    eigenvalue: float | None
    t: float | None
    guidance: Guidance | None
    component_eigenvalues: tuple = ()
    solver: dict = field(default_factory=dict)
    timings: dict = field(default_factory=dict)

    @property
    def mesh(self) -> SurfaceMesh:
        """The validated mesh (compact vertex numbering)."""
        return self.tangent.mesh

    @property
    def frames(self) -> np.ndarray:
        """(N, 2, 3) orthonormal tangent frames ``(X_i, J X_i)``."""
        return self.tangent.frames

    @property
    def singularities(self) -> Singularities:
        """Faces with nonzero index: faces, input_faces, index, barycentric, points."""
        return self.indices.singularities

    @property
    def face_index(self) -> np.ndarray:
        """(m,) int index per face of ``mesh.faces`` (mesh orientation)."""
        return self.indices.face_index

    @property
    def index_sum(self) -> int:
        """Σ of the face indices (``n χ`` on a closed mesh)."""
        return int(self.indices.total)

    @property
    def poincare_hopf(self) -> float:
        """``(Σ_t Ω_t + boundary rotation)/2π`` (rounded to 12 digits); equals ``index_sum``."""
        return round(float(self.indices.poincare_hopf), 12)

    @property
    def euler_characteristic(self) -> int:
        """χ of the mesh."""
        return int(self.mesh.euler_characteristic)

    def input_directions(self) -> np.ndarray:
        """``(len(V), n, 3)`` directions in the input vertex order (NaN for unreferenced vertices)."""
        return self.mesh.to_input(self.directions)

    def input_face_index(self) -> np.ndarray:
        """Index per row of the input F (0 for faces dropped by ``components="largest"``)."""
        out = np.zeros(int(self.mesh.face_rows.max(initial=-1)) + 1, np.int64)
        out[self.mesh.face_rows] = self.face_index
        return out

    def to_json(self) -> dict:
        """A JSON-ready summary (face numbers are rows of the input F)."""
        sing = self.singularities
        return {
            "n": self.n, "s": self.s, "lambda": self.lam,
            "n_vertices": int(self.mesh.n_vertices), "n_faces": int(self.mesh.n_faces),
            "euler_characteristic": self.euler_characteristic,
            "index_sum": self.index_sum, "poincare_hopf": self.poincare_hopf,
            "singularities": [{"face": int(f), "index": int(i), "position": [float(c) for c in p]}
                              for f, i, p in zip(sing.input_faces, sing.index, sing.points)],
            "eigenvalue": self.eigenvalue, "energy": self.energy, "t": self.t,
            "alignment": None if self.guidance is None else self.guidance.kind,
            "solver": self.solver, "timings": self.timings,
        }

    def __repr__(self) -> str:
        return (f"DirectionField(n={self.n}, s={self.s}, vertices={self.mesh.n_vertices}, "
                f"singularities={len(self.singularities.faces)}, index_sum={self.index_sum})")
