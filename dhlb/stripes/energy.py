"""The stripe energy as a generalized eigenproblem ``A x = λ M x`` (seed part 2, §3.2–§4.2, Alg. 7/8).

Two discretizations of the energy ``∫ |(d − iω)ψ|²`` of conjugate-symmetric functions:

* ``"cotan"`` (the seed's): the cotangent connection Laplacian
  (:func:`dhlb.fem.connection_laplacian`) of the real rank-2 O(2) bundle
  :attr:`StripeForm.bundle` — transports ``R(ω̂)`` or ``C R(ω̂)`` — with the weights of branch
  triangles removed (``simplex_weights = 0`` there, §3.2), and the lumped mass ``B = diag(A_i/3)``
  (Alg. 8). Up to the factor 2 of Eq. 3.5 this is the seed's matrix of §4.1.
* ``"fem"``: the curvature-corrected finite elements of the engine (:func:`dhlb.fem.bundle_matrices`,
  Theorems 15/17) of the line bundle ``e^{iω̃}`` with curvature ``Ω = dω̃`` on the double cover
  K̃ of the regular faces, restricted to conjugate-symmetric functions
  (:meth:`DoubleCover.restrict`, halved: ψ̃ has twice the energy of ψ). The mass is the
  consistent bundle mass unless ``lumped=True``.

**Complex form.** When every ``s_ij = +1`` (always for ``n = 1``; for line fields that happen to
be consistently oriented) the real 2N × 2N problem is the realification of the complex N × N
problem of the line bundle ``e^{iω̂}`` on the base (:attr:`StripeForm.line_bundle`): the same
eigenvalues, ``x = (Re ψ, Im ψ)`` interleaved. It is solved in that form (half the unknowns).

Vertices all of whose faces are branch triangles would have no energy at all (a spurious zero
eigenvalue): in the cotan energy those faces keep their weight (with a warning); the fem energy
raises :class:`~dhlb.errors.InvalidParameterError`.
"""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from dhlb.bundles.hermitian import HermitianLineBundle
from dhlb.errors import DhlbWarning, InvalidParameterError
from dhlb.fem.assembly import bundle_matrices
from dhlb.fem.connection import connection_laplacian, connection_mass
from dhlb.geometry.euclidean import EuclideanComplex
from dhlb.topology.complex import SimplicialComplex

if TYPE_CHECKING:
    from dhlb.stripes.oneform import StripeForm

__all__ = ["ENERGIES", "stripe_matrices"]

ENERGIES = ("cotan", "fem")


def _isolated(form) -> np.ndarray:
    """Vertices with no regular (non-branch) face."""
    mesh = form.mesh
    reg = np.bincount(mesh.faces[~form.is_branch].ravel(), minlength=mesh.n_vertices)
    return reg == 0


def _vertex(form, v) -> str:
    return f"vertex {int(form.mesh.vertex_rows[v])}"


def _cotan(form, lumped: bool, branch_weight: float, complex_form: bool):
    mesh = form.mesh
    geo = form.tangent.geometry
    face_w = np.where(form.is_branch, float(branch_weight), 1.0)
    iso = _isolated(form)
    if branch_weight == 0 and np.any(iso):
        keep = np.any(iso[mesh.faces], axis=1) & form.is_branch
        face_w[keep] = 1.0
        warnings.warn(f"{int(iso.sum())} vertices (first: {_vertex(form, int(np.argmax(iso)))}) lie only in branch "
                      f"triangles; their {int(keep.sum())} branch triangles keep their weight in the energy (else "
                      "those vertices would be unconstrained). The direction field is very rough there",
                      DhlbWarning, stacklevel=3)
    sw = np.empty(mesh.n_faces)
    sw[mesh.triangle_of_face] = face_w
    # the transports as arrays: no bundle object (with its checks) is built for the energy
    if complex_form:
        eta = np.exp(1j * form.omega)     # the connection of form.line_bundle
        return connection_laplacian(eta, geo, simplex_weights=sw), connection_mass(geo, 1, lumped=lumped)
    return connection_laplacian(form.transports, geo, simplex_weights=sw), connection_mass(geo, 2, lumped=lumped)


def _fem(form, lumped: bool, complex_form: bool):
    if complex_form:
        return bundle_matrices(form.line_bundle, form.tangent.geometry, lumped=lumped)
    iso = _isolated(form)
    if np.any(iso):
        raise InvalidParameterError(
            f"{int(iso.sum())} vertices (first: {_vertex(form, int(np.argmax(iso)))}) lie only in branch triangles, "
            "which have no lift to the double cover: the fem energy leaves them unconstrained. Use energy='cotan' "
            "or a smoother direction field")
    dc = form.double_cover
    N = dc.n_base_vertices
    lifts = dc.face_lifts[~form.is_branch]
    tris = np.sort(np.concatenate([lifts, np.where(lifts >= N, lifts - N, lifts + N)]), axis=1)
    Xr = SimplicialComplex(tris)  # pure: the lifted regular faces on the cover vertices 0 .. 2N-1
    Xt = dc.complex
    r = dc.bundle.connection[Xt.index(1, Xr.vertex_labels[Xr.simplices(1)])]
    Om = dc.bundle.curvature[Xt.index(2, Xr.vertex_labels[Xr.simplices(2)])]
    L = HermitianLineBundle(Xr, r, Om)
    A, M = bundle_matrices(L, _cover_geometry(Xr, dc, form.mesh), lumped=lumped)
    return 0.5 * dc.restrict(A), 0.5 * dc.restrict(M)


def _cover_geometry(Xr: SimplicialComplex, dc, mesh) -> EuclideanComplex:
    """The metric of the double cover: that of the points, or the base mesh's intrinsic lengths (mollified).

    A cover vertex ``v`` or ``v + N`` lies over the base vertex ``v``; a cover edge has the length of the
    base edge under it.
    """
    if mesh.edge_lengths is None:
        return EuclideanComplex(Xr, points=dc.points)
    N = dc.n_base_vertices
    E = np.sort(Xr.vertex_labels[Xr.simplices(1)] % N, axis=1)
    base = mesh.complex.index(1, mesh.complex.vertex_labels[E])
    return EuclideanComplex(Xr, edge_lengths=mesh.edge_lengths[base])


def stripe_matrices(
    form: StripeForm,
    energy: str = "cotan",
    *,
    lumped: bool | None = None,
    branch_weight: float = 0.0,
    complex_form: bool | None = None,
) -> tuple[sp.csr_matrix, sp.csr_matrix, bool]:
    """``(A, M, is_complex)`` of the stripe eigenproblem of a :class:`~dhlb.stripes.StripeForm`.

    Parameters
    ----------
    form : StripeForm
        The stripe form (:func:`~dhlb.stripes.stripe_form`).
    energy : {"cotan", "fem"}, optional
        The discretization (see the module docstring).
    lumped : bool, optional
        Lumped (diagonal) mass; default True for "cotan" (Alg. 8), False for "fem".
    branch_weight : float >= 0, optional
        Factor of the branch triangles' contribution to the cotan weights (0: removed, as in the seed).
    complex_form : bool, optional
        Solve the complex N × N problem (needs every ``s_ij = +1``); default: whenever possible.

    Returns
    -------
    A : scipy.sparse.csr_matrix
        The energy: complex N × N (``is_complex``) or real 2N × 2N with unknowns ``(Re ψ_i, Im ψ_i)``
        interleaved.
    M : scipy.sparse.csr_matrix
        The mass matrix, of the same shape and kind.
    is_complex : bool
        Whether the problem is in the complex form.

    Raises
    ------
    InvalidParameterError
        An unknown ``energy``; ``branch_weight`` not a finite number >= 0; ``complex_form=True``
        for a field that is not consistently oriented; or (``"fem"``, real form) a vertex that lies
        only in branch triangles.

    Warns
    -----
    DhlbWarning
        (``"cotan"``) Vertices that lie only in branch triangles: those triangles keep their weight.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import validate_surface
    >>> from dhlb.stripes import stripe_form
    >>> from dhlb.stripes.energy import stripe_matrices
    >>> mesh = validate_surface([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], [[0, 1, 2], [1, 3, 2]])
    >>> form = stripe_form(mesh, np.tile([1.0, 0, 0], (4, 1)), frequency=0.25)
    >>> A, M, cplx = stripe_matrices(form)
    >>> A.shape, cplx
    ((4, 4), True)
    >>> psi = np.exp(0.5j * np.pi * mesh.points[:, 0])          # the exact plane wave has zero energy
    >>> abs(complex(psi.conj() @ A @ psi)) < 1e-14
    True
    """
    if energy not in ENERGIES:
        raise InvalidParameterError(f"energy must be one of {ENERGIES}, got {energy!r}")
    try:
        bw = float(branch_weight)
    except (TypeError, ValueError):
        raise InvalidParameterError(f"branch_weight must be a number >= 0, got {branch_weight!r}") from None
    if not (np.isfinite(bw) and bw >= 0):
        raise InvalidParameterError(f"branch_weight must be a finite number >= 0, got {branch_weight!r}")
    oriented = bool(np.all(form.edge_sign > 0))
    if complex_form is None:
        complex_form = oriented
    elif complex_form and not oriented:
        e = int(np.argmax(form.edge_sign < 0))
        E = form.mesh.complex.simplices(1)[e]
        raise InvalidParameterError(
            "complex_form=True needs a consistently oriented field, but the representatives are opposite along "
            f"edge ({int(form.mesh.vertex_rows[E[0]])}, {int(form.mesh.vertex_rows[E[1]])}); use the real form")
    lumped = (energy == "cotan") if lumped is None else bool(lumped)
    if energy == "cotan":
        A, M = _cotan(form, lumped, bw, bool(complex_form))
    else:
        A, M = _fem(form, lumped, bool(complex_form))
    return sp.csr_matrix(A), sp.csr_matrix(M), bool(complex_form)
