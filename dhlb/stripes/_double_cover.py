"""The double cover K̃ of a line field's non-branch part as data: :class:`DoubleCover` (seed part 2, §3.3–§4.2).

Built by :attr:`dhlb.stripes.StripeForm.double_cover` (see :mod:`dhlb.stripes.oneform` for the
construction); re-exported from :mod:`dhlb.stripes.oneform` and :mod:`dhlb.stripes`. The class
holds the cover complex, its hermitian line bundle ``e^{iω̃}`` and the real-linear embedding of
conjugate-symmetric functions ``ψ̃ = (ψ, ψ̄)``, through which Hermitian forms on K̃ restrict to
the real 2N × 2N eigenproblem.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from dhlb.bundles.hermitian import HermitianLineBundle
from dhlb.errors import ShapeError
from dhlb.topology.complex import SimplicialComplex

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["DoubleCover"]


@dataclass(frozen=True)
class DoubleCover:
    """The double cover K̃ of the non-branch part and its hermitian line bundle (§3.3).

    Vertex ``i`` of the base is covered by ``i`` (sheet 1, the field ``X_i``) and ``N + i``
    (sheet 2, ``−X_i``). ``face_lifts[f]`` is the sheet-1 lift ``(p, q, r)`` of ``mesh.faces[f]``
    walked from its first corner (for a branch face the walk ends on ``τ(p) = p ± N``, and the
    face has no lift in K̃).

    The conjugate-symmetric functions are the real subspace ``ψ̃ = P x`` of :meth:`embedding`
    (``x`` interleaved ``(Re ψ_0, Im ψ_0, Re ψ_1, …)``); a Hermitian form H on K̃ restricts to the
    real symmetric ``Re(Pᴴ H P)`` (:meth:`restrict`), e.g. a Dirichlet and a mass matrix of
    ``bundle`` over the geometry ``points`` give the real 2N × 2N eigenproblem of §4.1–§4.2.

    Made by :attr:`dhlb.stripes.StripeForm.double_cover`; every parameter is kept as the attribute
    of the same name.

    Parameters
    ----------
    complex : SimplicialComplex
        On the vertices ``0 .. 2N−1`` (regular faces lifted twice, all edges).
    bundle : HermitianLineBundle
        Connection ``e^{iω̃}`` and curvature ``dω̃``.
    n_base_vertices : int
        ``N``, the number of vertices of the base mesh.
    face_lifts : (m, 3) int array
        The sheet-1 lift of each face of ``mesh.faces`` (see above).
    points : (2N, 3) float array
        The position of each cover vertex (that of the vertex below it).

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import validate_surface
    >>> from dhlb.stripes import stripe_form, texture_coordinates
    >>> V = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]
    >>> mesh = validate_surface(V, [[0, 1, 2], [1, 3, 2]])
    >>> form = stripe_form(mesh, np.tile([1.0, 0, 0], (4, 1)), frequency=0.25)
    >>> dc = form.double_cover
    >>> dc.n_base_vertices, dc.complex.n_simplices(0), dc.lift([1j, 1, 2, 3]).tolist()[3:5]
    (4, 8, [(3+0j), -1j])
    """

    complex: SimplicialComplex
    bundle: HermitianLineBundle
    n_base_vertices: int
    face_lifts: np.ndarray
    points: np.ndarray

    def lift(self, psi: ArrayLike) -> np.ndarray:
        """The conjugate-symmetric lift ``ψ̃ = (ψ, ψ̄)`` of one complex value per base vertex."""
        z = np.asarray(psi, np.complex128).reshape(-1)
        if z.size != self.n_base_vertices:
            raise ShapeError(f"psi needs one value per base vertex ({self.n_base_vertices}), got {z.size}")
        return np.concatenate([z, np.conj(z)])

    def embedding(self) -> sp.csr_matrix:
        """The real-linear map ``P`` (2N × 2N, complex) with ``P x = lift(x[0::2] + 1j x[1::2])``."""
        N = self.n_base_vertices
        v = np.arange(N)
        rows = np.concatenate([v, v, v + N, v + N])
        cols = np.concatenate([2 * v, 2 * v + 1, 2 * v, 2 * v + 1])
        vals = np.concatenate([np.ones(N), np.full(N, 1j), np.ones(N), np.full(N, -1j)])
        return sp.csr_matrix((vals, (rows, cols)), shape=(2 * N, 2 * N))

    def restrict(self, matrix: sp.spmatrix) -> sp.csr_matrix:
        """``Re(Pᴴ H P)``: a Hermitian form on the cover restricted to conjugate-symmetric functions (real, 2N × 2N)."""
        H = sp.csr_matrix(matrix)
        n = 2 * self.n_base_vertices
        if H.shape != (n, n):
            raise ShapeError(f"the matrix must be {n} x {n} (one row per vertex of the double cover), got {H.shape}")
        P = self.embedding()
        return sp.csr_matrix((P.conj().T @ H @ P).real)
