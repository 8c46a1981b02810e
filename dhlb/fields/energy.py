r"""The energies of n-direction fields (seed part 1, Eq. 4.1, 6.8; Appendices C and D.4), in weak form.

For a section ψ of the n-th tangent power ``L = TM^{⊗n}`` the Dirichlet energy splits into the
holomorphic and anti-holomorphic parts ``E_D = E_H + E_A`` (``E_H = ½∫|∂̄ψ|²``,
``E_A = ½∫|∂ψ|²``), and the family of energies is

.. math:: E_s = (1 + s) E_H + (1 − s) E_A = E_D − s (E_A − E_H),   s ∈ [−1, 1].

The Weitzenböck-type identity of Appendix C (derived again in ``proofs/derive_holomorphic_energy.py``,
in our conventions: hermitian products antilinear in the first slot, the surface oriented by its
faces) reads

.. math:: 2(E_A − E_H)(ψ) = ∫_M nK |ψ|^2 − ∮_{∂M} \operatorname{Im}⟨∇ψ, ψ⟩,

with ``nK`` the curvature density of L. On the piecewise-smooth sections of the engine it holds
*exactly* on every triangle (a flat triangle carrying a connection of constant curvature), so:

* ``A_D`` is the engine's Dirichlet matrix (Theorem 17, ``∫|∇ψ̃|² = ψᴴ A_D ψ = 2 E_D``);
* ``W`` is the engine's mass matrix with the per-face density ``n σ_t / |t|``
  (:attr:`TangentBundle.curvature_density`): ``ψᴴ W ψ = ∫ nK |ψ̃|²``;
* the boundary term of a face cancels on interior edges (both faces see the same section), and on
  a boundary edge traversed ``j → k`` by its face it is (in a parallel frame along the edge,
  ``ψ̃ = ((1−t) z_j + t r̄_jk z_k) e``)

  .. math:: −∫_{e_{jk}} \operatorname{Im}⟨∇ψ̃, ψ̃⟩ = \operatorname{Im}(\bar z_j\, \bar r_{jk}\, z_k),

  the Hermitian form ``B`` with ``B[j, k] = −(i/2) r̄_jk``, ``B[k, j] = (i/2) r_jk``. (The seed's
  Eq. 6.8 prints the boundary entry as ``ε_jk r̄_jk / 2``, without the factor ``i``: the
  imaginary part of a hermitian form is the Hermitian matrix ``(C − Cᴴ)/2i``.)

Hence ``2 E_s(ψ) = ψᴴ A_s ψ`` with

.. math:: A_s = A_D − s (W + B).

Each face contributes ``(1+s)∫|∂̄ψ̃|² + (1−s)∫|∂ψ̃|² ≥ 0``, so ``A_s`` is positive semidefinite for
every ``s ∈ [−1, 1]``; ``s = +1`` is the holomorphic energy, whose kernel are the holomorphic
sections (three on the round sphere for n = 1, the conformal vector fields). Flat check: for
ψ = z (a linear function on a planar mesh, trivial bundle) ``ψᴴ A_{+1} ψ = 0`` and for ψ = z̄
``ψᴴ A_{−1} ψ = 0``, exactly (``tests/test_surface_energy.py``).

Examples
--------
>>> import numpy as np
>>> from dhlb.mesh import tangent_bundle
>>> from dhlb.fields import energy_matrices
>>> V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.4, 0.6, 0]])
>>> tb = tangent_bundle(V, [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]], n=1)
>>> A, M = energy_matrices(tb, s=1.0)
>>> frame = tb.frames[:, 0, 0] + 1j * tb.frames[:, 0, 1]    # X_i as a complex number
>>> u = (V[:, 0] + 1j * V[:, 1]) / frame                   # the holomorphic field z ∂_z
>>> bool(abs(u.conj() @ (A @ u)) < 1e-14)                  # E_H(u) = 0
True
"""

from __future__ import annotations

import numbers
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from dhlb.errors import InvalidParameterError
from dhlb.fem.assembly import bundle_matrices, mass_matrix
from dhlb.mesh.coerce import as_tangent_bundle
from dhlb.mesh.surface import SurfaceMesh
from dhlb.mesh.tangent import TangentBundle

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["energy_matrices", "boundary_form", "check_s"]


def check_s(s) -> float:
    """Validate the energy parameter ``s ∈ [−1, 1]``."""
    if isinstance(s, bool) or not isinstance(s, numbers.Real) or not np.isfinite(s) or not -1.0 <= s <= 1.0:
        raise InvalidParameterError(f"s must be a real number in [-1, 1] (-1 anti-holomorphic, 0 Dirichlet, "
                                    f"+1 holomorphic), got {s!r}")
    return float(s)


def boundary_form(tb: TangentBundle) -> sp.csr_matrix:
    """The Hermitian form ``B`` of the boundary term: ``ψᴴ B ψ = −∮_{∂M} Im⟨∇ψ̃, ψ̃⟩``.

    One term ``Im(z̄_j r̄_jk z_k)`` per boundary edge traversed ``j → k`` by its face (``r_jk`` the
    transport of the half-edge: ``r_jk = conj(r_kj)`` for ``j > k``). Zero on a closed mesh.

    Parameters
    ----------
    tb : TangentBundle
        The n-th tangent power bundle of the mesh.

    Returns
    -------
    B : (N, N) scipy.sparse.csr_matrix
        Complex Hermitian, compact vertex order; nonzero only between the ends of boundary edges.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import tangent_bundle
    >>> from dhlb.fields.energy import boundary_form
    >>> tb = tangent_bundle([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    >>> frame = tb.frames[:, 0, 0] + 1j * tb.frames[:, 0, 1]
    >>> u = np.array([0, 1, 1j]) / frame    # the field z ∂_z on the flat triangle
    >>> round(float((u.conj() @ (boundary_form(tb) @ u)).real), 12)    # −∮ Im⟨∇u, u⟩ = 2·area
    1.0
    """
    m = tb.mesh
    N = m.n_vertices
    bd = m.boundary_halfedges
    if bd.size == 0:
        return sp.csr_matrix((N, N), dtype=np.complex128)
    j, k = bd[:, 0], bd[:, 1]
    c = -0.5j * tb.half_edge_transport(j, k).conj()                      # B[j, k]; B[k, j] = conj(c)
    rows = np.concatenate([j, k])
    cols = np.concatenate([k, j])
    return sp.csr_matrix((np.concatenate([c, c.conj()]), (rows, cols)), shape=(N, N))


def _tangent(V, F, n, reorient, components, repair="none") -> TangentBundle:
    """:func:`dhlb.mesh.as_tangent_bundle`, positional (kept for dhlb.fields.field and dhlb.fields.prescribed)."""
    return as_tangent_bundle(V, F, n, reorient=reorient, components=components, repair=repair, caller="dhlb.fields")


def energy_matrices(
    V: ArrayLike | SurfaceMesh,
    F: ArrayLike | None = None,
    n: int | None = None,
    s: float = 0.0,
    *,
    lumped: bool = False,
    reorient: bool = False,
    components: str = "all",
) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """``(A_s, M)``: the energy ``2 E_s = ψᴴ A_s ψ`` of n-direction fields and the mass matrix.

    Parameters
    ----------
    V : (n, 3) float array, SurfaceMesh or TangentBundle
        Vertex positions, or a validated mesh or tangent bundle (then ``F`` must be None).
    F : (m, 3) int array, optional
        Triangles as rows of ``V``; required when ``V`` is an array.
    n : int >= 1, optional
        The symmetry order (default: that of a TangentBundle ``V``, else 1).
    s : float in [−1, 1], optional
        −1 anti-holomorphic, 0 Dirichlet, +1 holomorphic energy.
    lumped : bool, optional
        Return the lumped (diagonal) mass matrix.
    reorient : bool, optional
        Passed to :func:`~dhlb.mesh.validate_surface` (mesh arrays only).
    components : {"all", "largest"}, optional
        Passed to :func:`~dhlb.mesh.validate_surface` (mesh arrays only).

    Returns
    -------
    A : (N, N) scipy.sparse.csr_matrix
        Complex Hermitian positive semidefinite, compact vertex order.
    M : (N, N) scipy.sparse.csr_matrix
        Complex Hermitian positive definite.

    Raises
    ------
    InvalidParameterError
        ``s`` is not a real number in [−1, 1]; ``n`` is not an integer >= 1; both a
        TangentBundle and ``F`` are given, or mesh arrays without ``F``.
    DhlbError
        The errors of :func:`~dhlb.mesh.validate_surface` on bad mesh arrays.

    Examples
    --------
    >>> from dhlb.io import read_surface, example_path
    >>> from dhlb.fields import energy_matrices
    >>> A, M = energy_matrices(*read_surface(example_path("torus.obj")), n=4, s=-1.0)
    >>> A.shape == M.shape, bool(abs(A - A.getH()).max() < 1e-12)
    (True, True)
    """
    s = check_s(s)
    tb = _tangent(V, F, n, reorient, components)
    A, M = bundle_matrices(tb.bundle, tb.geometry, lumped=lumped)
    if s != 0.0:
        W = mass_matrix(tb.bundle, tb.geometry, weights=tb.curvature_density)
        A = (A - s * (W + boundary_form(tb))).tocsr()
    return A, M
