r"""Global mass and Dirichlet matrices of a hermitian line bundle with curvature (Theorems 15, 17).

The piecewise-linear sections of the associated bundle (seed part 3, §11) give, for a discrete
hermitian line bundle ``L`` with curvature Ω over a Euclidean simplicial manifold of any
dimension n, the hermitian product ``<<ψ, φ>> = ψᴴ M φ`` (Theorem 15) and the Dirichlet product
``E(ψ) = ψᴴ A ψ = ∫ |∇ψ̃|²`` (Theorem 17), both as complex Hermitian sparse matrices on the
vertices, in the conventions of ``docs/conventions.md``: antilinear in the first slot, a single
edge contributes ``|z_j − r_ij z_i|²``, eigenproblem ``A u = λ M u``.

Assembly: the bundle and the geometry are validated when built (``HermitianLineBundle``,
``EuclideanComplex``); here only that they live on the same pure complex.  The per-simplex data
(volumes, Gram matrices only when the Dirichlet matrix is asked for, curvature on the local
triangles, connection on the local edges) go to the element kernel of the dimension
(:func:`dhlb.fem.kernels.element_kernel`), which returns the compact local entries of the
requested matrices; they are summed per global edge and vertex into one CSR pattern, the vertex
adjacency of the complex, shared by the mass and the Dirichlet matrix.

With Ω = 0 and the trivial connection the matrices are exactly the P1 mass matrix and the P1
stiffness matrix (the cotangent Laplacian for n = 2).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from dhlb.errors import NonFiniteError, ShapeError
from dhlb.fem.kernels import KERNELS, element_kernel
from dhlb.fem.kernels_closed import split_entries

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from dhlb.bundles.hermitian import HermitianLineBundle
    from dhlb.geometry.euclidean import EuclideanComplex

__all__ = ["mass_matrix", "dirichlet_matrix", "bundle_matrices", "lumped_mass"]


def _check_pair(bundle, geometry):
    X = bundle.X
    G = geometry.complex
    if G is not X and G != X:
        raise ShapeError(
            "the bundle and the geometry live on different complexes; build both on the same SimplicialComplex"
        )
    if not X.is_pure:
        raise ShapeError("the finite elements need a pure complex (every simplex a face of a top simplex)")
    return X


def _entries(bundle, geometry, *, mass: bool, dirichlet: bool):
    """``(X, LocalEntries)`` of the top simplices from the element kernel of their dimension.

    The off-diagonal entries come as ``(2, C(n+1, 2), m)`` float arrays, real then imaginary parts.
    """
    X = _check_pair(bundle, geometry)
    n = X.dim
    vol = geometry.volumes(n)
    omega = bundle.curvature[geometry.top_faces(2)] if n >= 2 else np.zeros((vol.size, 0))
    gram = geometry.barycentric_gradient_gram if dirichlet else None
    kernel = element_kernel(n)
    if kernel is KERNELS.get(n) and n in (2, 3):
        return X, split_entries(n, gram, vol, omega, bundle.connection, mass=mass, dirichlet=dirichlet,
                                rows=geometry.top_faces(1))
    out = kernel(gram, vol, omega, bundle.connection[geometry.top_faces(1)], mass=mass, dirichlet=dirichlet)
    return X, tuple(np.stack([x.real, x.imag]) if i % 2 == 0 and x is not None else x for i, x in enumerate(out))


class _Pattern:
    """The scatter indices of a complex: per local entry its canonical edge or vertex, and the CSR pattern."""

    def __init__(self, X, geometry):
        self.X = X
        self.adj = X.vertex_adjacency
        self.edges = geometry.top_faces(1).T.ravel()           # (local edge, simplex), the layout of `off`
        self.vertices = X.simplices(X.dim).T.ravel()
        n1 = X.n_simplices(1)
        self.n1 = n1
        big = self.adj.indices.size >= 2**31 or X.n_vertices >= 2**31
        self.index_type = np.int64 if big else np.int32

    def scatter(self, off: np.ndarray, diag: np.ndarray) -> sp.csr_matrix:
        """Sum compact local entries (layout of :mod:`dhlb.fem.kernels`) into the vertex-adjacency CSR pattern.

        ``off[:, p, s]`` (real, imaginary part of ``K_s[b, a]``) is summed per canonical edge ``(v_a < v_b)``
        into the lower entry ``K[v_b, v_a]`` (the upper one is its conjugate), ``diag`` per vertex.
        """
        adj, N = self.adj, self.X.n_vertices
        re = np.bincount(self.edges, weights=off[0].ravel(), minlength=self.n1)
        im = np.bincount(self.edges, weights=off[1].ravel(), minlength=self.n1)
        data = np.empty(adj.indices.size, complex)
        d_re, d_im = data.real, data.imag
        d_re[adj.lower] = re
        d_im[adj.lower] = im
        d_re[adj.upper] = re
        d_im[adj.upper] = np.negative(im, out=im)
        d_re[adj.diagonal] = np.bincount(self.vertices, weights=diag.ravel(), minlength=N)
        d_im[adj.diagonal] = 0.0
        A = sp.csr_matrix((data, adj.indices.astype(self.index_type), adj.indptr.astype(self.index_type)),
                          shape=(N, N))
        A.has_sorted_indices = True
        return A


def _weights(weights, m: int) -> np.ndarray:
    w = np.asarray(weights, dtype=float)
    if w.ndim == 0:
        w = np.full(m, float(w))
    if w.shape != (m,):
        raise ShapeError(f"weights must be one value per top simplex ({m}), got shape {w.shape}")
    if not np.all(np.isfinite(w)):
        bad = int(np.argmax(~np.isfinite(w)))
        raise NonFiniteError(f"weights[{bad}] = {w[bad]} is not finite")
    return w


def mass_matrix(
    bundle: HermitianLineBundle, geometry: EuclideanComplex, *, lumped: bool = False, weights: ArrayLike | None = None
) -> sp.csr_matrix:
    """The mass matrix ``M`` of Theorem 15: ``<<ψ, φ>> = ψᴴ M φ``.

    Parameters
    ----------
    bundle : HermitianLineBundle
        Connection and curvature on the complex ``geometry.complex``.
    geometry : EuclideanComplex
        The metric (points or edge lengths) of a pure n-dimensional complex.
    lumped : bool
        Return the diagonal lumped mass ``M_ii = Σ_{σ ∋ i} vol(σ)/(n+1)`` (bundle independent).
    weights : float or (n_top,) array, optional
        A density per top simplex: the matrix of ``∫ w |ψ̃|²`` (e.g. a curvature density).

    Returns
    -------
    scipy.sparse.csr_matrix, complex, Hermitian positive (semi)definite

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb import EuclideanComplex, HermitianLineBundle
    >>> from dhlb.examples import cube_nd
    >>> X, P = cube_nd(2, 2, return_points=True)
    >>> M = mass_matrix(HermitianLineBundle.trivial(X), EuclideanComplex(X, points=P))
    >>> round(float(M.sum().real), 12)   # ∫ 1 = area
    1.0
    """
    if lumped:
        _check_pair(bundle, geometry)
        w = None if weights is None else _weights(weights, geometry.complex.n_simplices(geometry.dim))
        return sp.diags(_lumped(geometry, w).astype(complex), format="csr")
    X, (off, diag, _, _) = _entries(bundle, geometry, mass=True, dirichlet=False)
    if weights is not None:
        w = _weights(weights, diag.shape[1])
        off, diag = off * w, diag * w
    return _Pattern(X, geometry).scatter(off, diag)


def dirichlet_matrix(bundle: HermitianLineBundle, geometry: EuclideanComplex) -> sp.csr_matrix:
    """The Dirichlet matrix ``A`` of Theorem 17: ``∫ |∇ψ̃|² = ψᴴ A ψ`` (the generalised cotangent Laplacian).

    Parameters
    ----------
    bundle : HermitianLineBundle
        Connection and curvature on the complex ``geometry.complex``.
    geometry : EuclideanComplex
        The metric (points or edge lengths) of a pure n-dimensional complex.

    Returns
    -------
    A : (X.n_vertices, X.n_vertices) complex scipy.sparse.csr_matrix
        Hermitian positive semidefinite, on the vertex-adjacency pattern of the complex.

    Raises
    ------
    ShapeError
        When the bundle and the geometry live on different complexes, or the complex is not pure.

    Examples
    --------
    >>> from dhlb import EuclideanComplex, HermitianLineBundle
    >>> from dhlb.examples import cube_nd
    >>> X, P = cube_nd(2, 3, return_points=True)
    >>> geo = EuclideanComplex(X, points=P)
    >>> A = dirichlet_matrix(HermitianLineBundle.trivial(X), geo)
    >>> bool(abs(A - geo.stiffness_matrix()).max() < 1e-14)   # Ω = 0: the cotangent Laplacian
    True
    """
    X, (_, _, off, diag) = _entries(bundle, geometry, mass=False, dirichlet=True)
    return _Pattern(X, geometry).scatter(off, diag)


def bundle_matrices(
    bundle: HermitianLineBundle, geometry: EuclideanComplex, *, lumped: bool = False
) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """``(A, M)``: Dirichlet and mass matrix in one pass (the moments are shared).

    Parameters
    ----------
    bundle : HermitianLineBundle
        Connection and curvature on the complex ``geometry.complex``.
    geometry : EuclideanComplex
        The metric (points or edge lengths) of a pure n-dimensional complex.
    lumped : bool, optional
        Return the diagonal lumped mass (as :func:`mass_matrix` with ``lumped=True``) as ``M``.

    Returns
    -------
    A : (X.n_vertices, X.n_vertices) complex scipy.sparse.csr_matrix
        The Dirichlet matrix, as :func:`dirichlet_matrix`.
    M : (X.n_vertices, X.n_vertices) complex scipy.sparse.csr_matrix
        The mass matrix, as :func:`mass_matrix`.

    Raises
    ------
    ShapeError
        When the bundle and the geometry live on different complexes, or the complex is not pure.

    Examples
    --------
    >>> from dhlb import EuclideanComplex, HermitianLineBundle
    >>> from dhlb.examples import cube_nd
    >>> X, P = cube_nd(3, 2, return_points=True)
    >>> A, M = bundle_matrices(HermitianLineBundle.trivial(X), EuclideanComplex(X, points=P))
    >>> A.shape == M.shape == (27, 27)
    True
    """
    X, (m_off, m_diag, a_off, a_diag) = _entries(bundle, geometry, mass=not lumped, dirichlet=True)
    pattern = _Pattern(X, geometry)
    A = pattern.scatter(a_off, a_diag)
    return A, (mass_matrix(bundle, geometry, lumped=True) if lumped else pattern.scatter(m_off, m_diag))


def lumped_mass(geometry: EuclideanComplex) -> np.ndarray:
    """The lumped mass ``Σ_{σ ∋ i} vol(σ)/(n+1)`` per vertex, as a vector.

    Parameters
    ----------
    geometry : EuclideanComplex
        The metric of an n-dimensional complex; its top simplices are the n-simplices.

    Returns
    -------
    (X.n_vertices,) float array
        The lumped mass of each vertex (0 for a vertex of no n-simplex).

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> from dhlb.geometry import EuclideanComplex
    >>> G = EuclideanComplex(SimplicialComplex([(0, 1, 2)]), [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    >>> lumped_mass(G).round(6).tolist()
    [0.166667, 0.166667, 0.166667]
    """
    return _lumped(geometry, None)


def _lumped(geometry, weights) -> np.ndarray:
    X = geometry.complex
    n = X.dim
    w = geometry.volumes(n) if weights is None else geometry.volumes(n) * weights
    return np.bincount(X.simplices(n).ravel(), weights=np.repeat(w / (n + 1), n + 1), minlength=X.n_vertices)
