"""What :func:`~dhlb.stripes.stripe_pattern` returns.

:class:`StripePattern` (texture, section, zeros and branch faces).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from dhlb._result import Result
from dhlb.mesh.surface import SurfaceMesh
from dhlb.stripes.oneform import StripeForm
from dhlb.stripes.section import (
    SectionIteration,
)
from dhlb.stripes.texture import StripeTexture

if TYPE_CHECKING:

    from numpy.typing import ArrayLike

__all__ = ["StripePattern"]


@dataclass
class StripePattern(Result):
    """Result of :func:`stripe_pattern`.

    Parameters
    ----------
    form : StripeForm
        Directions, frequencies, ω̂, the signs ``s_ij``, branch triangles, the bundles.
    psi : (N,) complex128
        The section (compact vertices; for line fields the value on the sheet of ``X_i``): unit modulus
        per vertex for ``section="unit"``, ``M``-normalized for ``"eigenvector"`` and ``"power"``.
    texture : StripeTexture
        Per-corner α, zero indices, branch data; ``texture.evaluate(faces, bary)`` anywhere.
    eigenvalue : float
        The smallest eigenvalue ``λ₁`` of the relaxed problem (0 for an exactly integrable field).
    section : str
        ``"unit"``, ``"eigenvector"`` or ``"power"`` (see :func:`stripe_pattern`).
    unit_energy : float
        The seed's energy of the unit function ``φ = ψ/|ψ|``: ``ρ(φ) = φᴴAφ / φᴴMφ >= λ₁``.
    iteration : SectionIteration or None
        Steps after the eigen solve (``"unit"``, ``"power"``): iterations, the unit energy of every
        iterate, which one was kept (:class:`~dhlb.stripes.section.SectionIteration`).
    energy : str
        ``"cotan"`` or ``"fem"``.
    solver : dict
        ``backend``, ``iterations``, ``residual`` (backward error), ``converged``, ``shift``,
        ``block_size``, ``unknowns``, ``complex`` (solved as the complex N × N problem),
        ``indefinite``, ``factorizations`` and ``solves`` (right-hand sides) of the eigensolver,
        ``section_solves`` (right-hand sides of the section iteration) and ``section_factorizations``
        (0 when it reused the eigensolver's factorization).
    timings : dict
        Seconds: ``setup`` (mesh, form, matrices), ``solve`` (eigenpair and section iteration),
        ``section`` (the iteration alone), ``texture``, ``total``.
    orthogonal : StripePattern or None
        The pattern of the directions turned by 90° (``orthogonal=True``).

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.stripes import stripe_pattern
    >>> V, F = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], [[0, 1, 2], [1, 3, 2]]
    >>> res = stripe_pattern(V, F, np.tile([1.0, 0, 0], (4, 1)), frequency=0.25)    # stripes across x
    >>> res.n, res.psi.shape, bool(abs(res.eigenvalue) < 1e-9), res.zero_faces.size, res.energy
    (1, (4,), True, 0, 'cotan')
    """

    form: StripeForm
    psi: np.ndarray
    texture: StripeTexture
    eigenvalue: float
    energy: str
    solver: dict
    timings: dict
    orthogonal: StripePattern | None = field(default=None, repr=False)
    section: str = "eigenvector"
    unit_energy: float = float("nan")
    iteration: SectionIteration | None = field(default=None, repr=False)

    @property
    def mesh(self) -> SurfaceMesh:
        """The validated surface mesh."""
        return self.form.mesh

    @property
    def n(self) -> int:
        """1 for a vector field, 2 for a line field."""
        return self.form.n

    @property
    def corner_alpha(self) -> np.ndarray:
        """``(m, 3)`` α per face corner (linear part; see :class:`StripeTexture`)."""
        return self.texture.corner_alpha

    @property
    def zero_faces(self) -> np.ndarray:
        """Faces (rows of ``mesh.faces``) containing a zero of ψ."""
        return self.texture.zero_faces

    @property
    def zero_index(self) -> np.ndarray:
        """``(m,)`` index of every face (mesh orientation; 0 on branch faces)."""
        return self.texture.zero_index

    @property
    def branch_faces(self) -> np.ndarray:
        """Branch triangles (rows of ``mesh.faces``)."""
        return self.texture.branch_faces

    def evaluate(self, faces: ArrayLike, bary: ArrayLike) -> np.ndarray:
        """α at barycentric points of faces (see :meth:`StripeTexture.evaluate`)."""
        return self.texture.evaluate(faces, bary)

    def to_json(self) -> dict:
        """A JSON-ready summary: singular faces as input rows of F, eigenvalue, solver, timings."""
        mesh = self.mesh
        zf = self.zero_faces
        f = self.form.frequency
        out = {
            "n": int(self.n),
            "energy": self.energy,
            "n_vertices": int(mesh.n_vertices),
            "n_faces": int(mesh.n_faces),
            "frequency": {"min": float(f.min()), "max": float(f.max()), "mean": float(f.mean())},
            "eigenvalue": float(self.eigenvalue),
            "section": self.section,
            "unit_energy": float(self.unit_energy),
            "iteration": None if self.iteration is None else self.iteration.to_json(),
            "zero_faces": [{"face": int(r), "index": int(i), "position": p}
                           for r, i, p in zip(mesh.face_rows[zf], self.zero_index[zf],
                                              self.texture.zero_points.tolist())],
            "branch_faces": [int(r) for r in mesh.face_rows[self.branch_faces]],
            "index_sum": int(self.zero_index.sum()),
            "repairs": [] if mesh.repair is None else mesh.repair.to_json(),
            "solver": dict(self.solver),
            "timings": {k: float(v) for k, v in self.timings.items()},
        }
        if self.orthogonal is not None:
            out["orthogonal"] = self.orthogonal.to_json()
        return out

    def summary_rows(self) -> list[tuple[str, object]]:
        """The headline numbers, as ``(label, value)`` pairs (the ``dhlb`` report and notebooks).

        Returns
        -------
        list of (str, object)
        """
        f = self.form.frequency
        return [("n", self.n), ("vertices, faces", f"{self.mesh.n_vertices}, {self.mesh.n_faces}"),
                ("frequency", f"{float(f.min()):.4g} – {float(f.max()):.4g}"),
                ("zeros (index sum)", f"{self.zero_faces.size} ({int(self.zero_index.sum())})"),
                ("branch faces", self.branch_faces.size), ("section", self.section),
                ("eigenvalue, unit energy", f"{self.eigenvalue:.6g}, {self.unit_energy:.6g}"),
                ("time", f"{self.timings.get('total', float('nan')):.3g} s")]

    def __repr__(self) -> str:
        return (f"StripePattern(n={self.n}, energy={self.energy!r}, zeros={self.zero_faces.size}, "
                f"branch_faces={self.branch_faces.size}, section={self.section!r}, eigenvalue={self.eigenvalue:.6g}, "
                f"unit_energy={self.unit_energy:.6g}, {self.mesh!r})")
