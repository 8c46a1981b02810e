"""The result of :func:`dhlb.fields.direction_field`: the field, its indices and how it was computed."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from dhlb._result import Result
from dhlb.fields.directions import FieldIndices, Singularities
from dhlb.fields.guidance import Guidance
from dhlb.mesh.surface import SurfaceMesh
from dhlb.mesh.tangent import TangentBundle

__all__ = ["DirectionField", "PrescribedField"]


@dataclass(frozen=True, eq=False)
class DirectionField(Result):
    """An n-direction field on a triangle mesh (compact vertex order of ``mesh``).

    Made by :func:`~dhlb.fields.direction_field`; every parameter is kept as the attribute of the
    same name.

    Parameters
    ----------
    n : int
        The symmetry (number of directions).
    s : float
        The energy parameter (−1 anti-holomorphic, 0 Dirichlet, +1 holomorphic).
    lam : float
        λ_t of the aligned problem (0 for the smoothest field).
    tangent : TangentBundle
        The tangent bundle (``.mesh``, ``.frames``, ``.bundle``).
    u : (N,) complex array
        The power representation in the vertex frames, ``uᴴ M u = 1``.
    directions : (N, n, 3) float array
        Unit 3D directions (zero rows where ``u = 0``).
    indices : FieldIndices
        Per face, in the mesh orientation; the Poincaré–Hopf terms; the singularities.
    energy : float
        ``uᴴ A_s u`` (twice the energy E_s of the M-normalized field).
    eigenvalue : float or None
        The smallest eigenvalue (the largest over components); None if aligned.
    t : float or None
        ``(1 + ‖ũ‖_M)⁻¹`` of the aligned problem (Eq. 6.6).
    guidance : Guidance or None
        The alignment data.
    component_eigenvalues : tuple of float
        One per connected component (smoothest field).
    solver : dict
        What the eigensolver reported: backend, iterations, residual, converged, factorizations,
        solves, the factorized shift σ (``A − σM``) and note.
    timings : dict
        Seconds per phase (setup, solve, indices, total).

    Examples
    --------
    >>> from dhlb.fields import direction_field
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
        return round(float(self.indices.poincare_hopf), 12) + 0.0   # + 0.0: no "-0" in reports

    @property
    def euler_characteristic(self) -> int:
        """χ of the mesh."""
        return int(self.mesh.euler_characteristic)

    def input_directions(self) -> np.ndarray:
        """``(len(V), n, 3)`` directions in the input vertex order (NaN for unreferenced vertices)."""
        return self.mesh.to_input(self.directions)

    def input_face_index(self) -> np.ndarray:
        """Index per row of the input F.

        0 for faces dropped by ``components="largest"`` or removed by a repair; a merged duplicate face
        gets the index of the copy kept (:meth:`dhlb.mesh.SurfaceMesh.to_input_faces`).
        """
        return self.mesh.to_input_faces(self.face_index).astype(np.int64)

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
            "repairs": [] if self.mesh.repair is None else self.mesh.repair.to_json(),
            "solver": self.solver, "timings": self.timings,
        }

    def summary_rows(self) -> list[tuple[str, object]]:
        """The headline numbers, as ``(label, value)`` pairs (the ``dhlb`` report and notebooks).

        Returns
        -------
        list of (str, object)
        """
        sing = self.singularities
        return [("n, s", f"{self.n}, {self.s:g}"), ("vertices, faces", f"{self.mesh.n_vertices}, {self.mesh.n_faces}"),
                ("Euler characteristic", self.euler_characteristic),
                ("singularities", f"{int((sing.index > 0).sum())} positive, {int((sing.index < 0).sum())} negative"),
                ("index sum (n χ)", self.index_sum),
                ("eigenvalue" if self.eigenvalue is not None else "energy",
                 f"{(self.eigenvalue if self.eigenvalue is not None else self.energy):.6g}"),
                ("time", f"{self.timings.get('total', float('nan')):.3g} s")]

    def __repr__(self) -> str:
        return (f"DirectionField(n={self.n}, s={self.s}, vertices={self.mesh.n_vertices}, "
                f"singularities={len(self.singularities.faces)}, index_sum={self.index_sum})")


@dataclass(frozen=True, eq=False, repr=False)
class PrescribedField(DirectionField):
    """A :class:`DirectionField` with prescribed singularities (:func:`dhlb.fields.prescribed_field`).

    Parameters
    ----------
    n, s, lam, tangent, u, directions, indices, energy, eigenvalue, t, guidance, component_eigenvalues, solver, timings
        As in :class:`DirectionField`.
    prescribed : (m,) int64 array
        The prescribed index per face of ``mesh.faces`` (mesh orientation).
    delta : (n_1,) float64 array
        The connection change δ per canonical edge of ``mesh.complex``.
    delta_norm : float
        ``sqrt(δᵀ W δ)`` in the norm of ``weights``.
    weights : str
        ``"cotan"`` (Hodge star ⋆₁) or ``"uniform"`` (plain ℓ²).
    edge_weights : (n_1,) float64 array
        The weights W of the norm δ is minimal in (after any reweighting).
    generators : (q, n_1) sparse int matrix
        The generators of H₁ (fundamental cycles, rows).
    holonomy : (q,) float64 array
        The rotation θ_c of the field relative to parallel transport along each generator.
    admissible_holonomy : (q,) float64 array
        The admissible θ_c are these plus 2πZ.
    flatness_defect : float
        The largest closing error of the tree transport (round-off).

    Examples
    --------
    >>> from dhlb.io import read_surface, example_path
    >>> from dhlb.fields import prescribed_field
    >>> res = prescribed_field(*read_surface(example_path("torus.obj")), n=1)   # no singularity at all
    >>> res.index_sum, len(res.singularities.faces), res.generators.shape[0], res.flatness_defect < 1e-12
    (0, 0, 2, True)
    """

    prescribed: np.ndarray = None
    delta: np.ndarray = None
    delta_norm: float = 0.0
    weights: str = "cotan"
    generators: object = None
    holonomy: np.ndarray = None
    admissible_holonomy: np.ndarray = None
    flatness_defect: float = 0.0
    edge_weights: np.ndarray = None

    @property
    def prescribed_singularities(self) -> dict:
        """``{input face row: k}`` of the prescription (after locating points and summing per face)."""
        f = np.nonzero(self.prescribed)[0]
        return {int(r): int(k) for r, k in zip(self.mesh.face_rows[f], self.prescribed[f])}

    def to_json(self) -> dict:
        """The summary of :meth:`DirectionField.to_json` plus the prescription and the correction."""
        out = super().to_json()
        out.update({
            "prescribed": [{"face": r, "index": k} for r, k in self.prescribed_singularities.items()],
            "delta_norm": self.delta_norm, "delta_max": float(np.max(np.abs(self.delta), initial=0.0)),
            "weights": self.weights, "holonomy": [float(x) for x in self.holonomy],
            "admissible_holonomy": [float(x) for x in self.admissible_holonomy],
            "flatness_defect": self.flatness_defect,
        })
        return out

    def __repr__(self) -> str:
        return (f"PrescribedField(n={self.n}, vertices={self.mesh.n_vertices}, "
                f"singularities={len(self.singularities.faces)}, index_sum={self.index_sum}, "
                f"delta_norm={self.delta_norm:.4g})")
