r"""Global mass and Dirichlet matrices of a hermitian line bundle with curvature (Theorems 15, 17).

The piecewise-linear sections of the associated bundle (seed part 3, §11) give, for a discrete
hermitian line bundle ``L`` with curvature Ω over a Euclidean simplicial manifold of any
dimension n, the hermitian product ``<<ψ, φ>> = ψᴴ M φ`` (Theorem 15) and the Dirichlet product
``E(ψ) = ψᴴ A ψ = ∫ |∇ψ̃|²`` (Theorem 17), both as complex Hermitian sparse matrices on the
vertices, in the conventions of ``docs/conventions.md``: antilinear in the first slot, a single
edge contributes ``|z_j − r_ij z_i|²``, eigenproblem ``A u = λ M u``.

Assembly is vectorized over the top simplices: per simplex the local matrices of
:mod:`dhlb.fem.integrals` (local vertex order = sorted row, global frames through the
connection on the local edges) are scattered into one COO matrix.

With Ω = 0 and the trivial connection the matrices are exactly the P1 mass matrix and the P1
stiffness matrix (the cotangent Laplacian for n = 2).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from dhlb.errors import NonFiniteError, ShapeError
from dhlb.fem._fast_local import fast_local_entries, fast_local_matrices
from dhlb.fem._local_matrices import local_mass_matrices, local_matrices
from dhlb.topology.structure import subfaces

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


def _local_data(bundle, geometry):
    """Per top simplex: vertex rows, volumes, local curvature, local connection."""
    X = _check_pair(bundle, geometry)
    n = X.dim
    rows = X.simplices(n)
    vol = np.asarray(geometry.volumes(n), dtype=float)
    if n >= 2:
        omega = np.asarray(bundle.curvature, dtype=float)[subfaces(X, n, 2)]
    else:
        omega = np.zeros((rows.shape[0], 0))
    r = np.asarray(bundle.connection, dtype=complex)[subfaces(X, n, 1)]
    return X, rows, vol, omega, r


def _scatter(X, local: np.ndarray) -> sp.csr_matrix:
    """Sum ``local[s, b, a]`` into ``K[v_b, v_a]`` (``v = X.simplices(n)[s]``) on the vertex-adjacency pattern."""
    pos = X.top_entry_positions.ravel()
    local = local.reshape(-1)
    return _csr(X, [pos], [local.real], [local.imag])


def _scatter_entries(X, off: np.ndarray, diag: np.ndarray) -> sp.csr_matrix:
    """As :func:`_scatter` for Hermitian local matrices in a compact layout.

    The layout is that of :func:`dhlb.fem._fast_local.fast_local_entries` (``off[p] = K_s[b, a]``
    for local edge ``p = (a, b)``, shape ``(n_edges_local, n_top)``; ``diag`` ``(n + 1, n_top)``).
    The entries are summed per canonical edge ``e = (v_a < v_b)`` (the lower entry ``K[v_b, v_a]``;
    the upper one is its conjugate) and per vertex, then placed on the adjacency pattern.
    """
    n = X.dim
    adj = X.vertex_adjacency
    edges = subfaces(X, n, 1).T.ravel()  # (E, m) layout, like `off`
    off = off.ravel()
    n1 = X.n_simplices(1)
    low = np.bincount(edges, weights=off.real, minlength=n1).astype(complex)
    if np.iscomplexobj(off):
        low.imag = np.bincount(edges, weights=off.imag, minlength=n1)
    data = np.empty(adj.indices.size, complex)
    data[adj.lower] = low
    data[adj.upper] = low.conj()
    data[adj.diagonal] = np.bincount(X.simplices(n).T.ravel(), weights=diag.ravel(), minlength=X.n_vertices)
    return sp.csr_matrix((data, adj.indices.copy(), adj.indptr.copy()), shape=(X.n_vertices, X.n_vertices))


def _csr(X, positions, real_parts, imag_parts) -> sp.csr_matrix:
    adj = X.vertex_adjacency
    nnz = adj.indices.size
    pos = np.concatenate(positions)
    re = np.concatenate(real_parts)
    data = np.bincount(pos, weights=re, minlength=nnz).astype(complex)
    im = [(p, w) for p, w in zip(positions, imag_parts) if w is not None]
    if im:
        data.imag = np.bincount(
            np.concatenate([p for p, _ in im]), weights=np.concatenate([w for _, w in im]), minlength=nnz
        )
    return sp.csr_matrix((data, adj.indices.copy(), adj.indptr.copy()), shape=(X.n_vertices, X.n_vertices))


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
    X, rows, vol, omega, r = _local_data(bundle, geometry)
    n = X.dim
    if lumped:
        w = vol if weights is None else vol * _weights(weights, vol.size)
        diag = np.bincount(rows.ravel(), weights=np.repeat(w / (n + 1), n + 1), minlength=X.n_vertices)
        return sp.diags(diag.astype(complex), format="csr")
    if n in (2, 3):
        gram = np.asarray(geometry.barycentric_gradient_gram, dtype=float)
        local = fast_local_matrices(gram, vol, omega, r)[0]
    else:
        local = local_mass_matrices(vol, omega, r, dim=n)
    if weights is not None:
        local = local * _weights(weights, vol.size)[:, None, None]
    return _scatter(X, local)


def dirichlet_matrix(bundle: HermitianLineBundle, geometry: EuclideanComplex) -> sp.csr_matrix:
    """The Dirichlet matrix ``A`` of Theorem 17: ``∫ |∇ψ̃|² = ψᴴ A ψ`` (the generalised cotangent Laplacian).

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb import EuclideanComplex, HermitianLineBundle
    >>> from dhlb.examples import cube_nd
    >>> X, P = cube_nd(2, 3, return_points=True)
    >>> geo = EuclideanComplex(X, points=P)
    >>> A = dirichlet_matrix(HermitianLineBundle.trivial(X), geo)
    >>> bool(abs(A - geo.stiffness_matrix()).max() < 1e-14)   # Ω = 0: the cotangent Laplacian
    True
    """
    X, _rows, vol, omega, r = _local_data(bundle, geometry)
    gram = np.asarray(geometry.barycentric_gradient_gram, dtype=float)
    return _scatter(X, fast_local_matrices(gram, vol, omega, r)[1])


def bundle_matrices(
    bundle: HermitianLineBundle, geometry: EuclideanComplex, *, lumped: bool = False
) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """``(A, M)``: Dirichlet and mass matrix in one pass (the moments are shared).

    Examples
    --------
    >>> from dhlb import EuclideanComplex, HermitianLineBundle
    >>> from dhlb.examples import cube_nd
    >>> X, P = cube_nd(3, 2, return_points=True)
    >>> A, M = bundle_matrices(HermitianLineBundle.trivial(X), EuclideanComplex(X, points=P))
    >>> A.shape == M.shape == (27, 27)
    True
    """
    X, _rows, vol, omega, r = _local_data(bundle, geometry)
    gram = np.asarray(geometry.barycentric_gradient_gram, dtype=float)
    if X.dim in (2, 3):
        m_off, m_diag, a_off, a_diag = fast_local_entries(gram, vol, omega, r)
        A = _scatter_entries(X, a_off, a_diag)
        M = _scatter_entries(X, m_off, m_diag)
    else:
        Ml, Al = local_matrices(gram, vol, omega, r)
        A, M = _scatter(X, Al), _scatter(X, Ml)
    return (A, mass_matrix(bundle, geometry, lumped=True)) if lumped else (A, M)


def lumped_mass(geometry: EuclideanComplex) -> np.ndarray:
    """The lumped mass ``Σ_{σ ∋ i} vol(σ)/(n+1)`` per vertex, as a vector.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> from dhlb.geometry import EuclideanComplex
    >>> G = EuclideanComplex(SimplicialComplex([(0, 1, 2)]), [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    >>> lumped_mass(G).round(6).tolist()
    [0.166667, 0.166667, 0.166667]
    """
    X = geometry.complex
    n = X.dim
    vol = np.asarray(geometry.volumes(n), dtype=float)
    return np.bincount(X.simplices(n).ravel(), weights=np.repeat(vol / (n + 1), n + 1), minlength=X.n_vertices)
