r"""Cotangent connection Laplacians of vector bundles (the discrete energy ``Σ w_ij |v_j − η_ij v_i|²``).

For a bundle of rank k over a pure n-dimensional Euclidean simplicial complex (a
:class:`~dhlb.bundles.VectorBundle` over R or C, with ``η_ij`` per canonical edge ``i < j``
meaning ``v_j = η_ij v_i`` for a parallel section, or a
:class:`~dhlb.bundles.HermitianLineBundle`, ``η_ij = r_ij``) the **connection Laplacian** is the
matrix of the quadratic form

.. math:: E(v) = \sum_{i<j} w_{ij}\, |v_j - \eta_{ij} v_i|^2 = v^H A v ,

on sections ``v`` stored interleaved, ``v[i·k + a]`` = component a at vertex i. The edge
weights are the P1 (cotangent) weights ``w_ij = −Σ_σ s_σ c^σ_ij`` with the local stiffness
``c^σ_ij = vol(σ) ⟨∇λ_i, ∇λ_j⟩`` of each top simplex σ ∋ i, j (Theorem 16; for triangles
``w_ij = (cot β_ij + cot β_ji)/2``) and optional factors ``s_σ`` per top simplex (e.g. 0 for the
branch triangles of a stripe pattern, seed part 2, §3.2). Expanding the square:

* off-diagonal blocks ``A[j, i] = −w_ij η_ij`` and ``A[i, j] = −w_ij η_ijᴴ`` (for ``k = 1``
  exactly the entries of ``docs/conventions.md``);
* diagonal blocks ``A[i, i] = Σ_{j>i} w_ij η_ijᴴ η_ij + Σ_{j<i} w_ji I``. If every transport is
  orthogonal / unitary this is ``(Σ_σ s_σ c^σ_ii) I``, and then the whole matrix is computed edge by
  edge from the weighted P1 stiffness ``K`` (the sums of :meth:`EuclideanComplex.stiffness_matrix`):
  ``K_ii I`` and ``K_ij η`` (so that the trivial bundle of rank 1 gives exactly the stiffness matrix).

Unlike :func:`dhlb.fem.dirichlet_matrix` (the curvature-corrected finite elements of a line
bundle) this is the plain "discrete connection" energy: exact for flat bundles, and the energy
of the stripe-pattern and direction-field papers. A is Hermitian (real symmetric for real
bundles) and positive semidefinite if all ``s_σ >= 0`` and the weights ``w_ij`` are (e.g. a
Delaunay triangulation); in general only the trivial-bundle part is guaranteed PSD.

Examples
--------
>>> import numpy as np
>>> from dhlb import SimplicialComplex
>>> from dhlb.bundles import VectorBundle
>>> from dhlb.geometry import EuclideanComplex
>>> from dhlb.fem import connection_laplacian
>>> X = SimplicialComplex([(0, 1, 2), (1, 2, 3)])
>>> geo = EuclideanComplex(X, points=[[0, 0], [1, 0], [0, 1], [1, 1]])
>>> A = connection_laplacian(VectorBundle.trivial(X, 1), geo)
>>> bool((A != geo.stiffness_matrix()).nnz == 0)
True
>>> R = np.array([[0.0, -1.0], [1.0, 0.0]])                   # quarter turn on every edge
>>> A2 = connection_laplacian(VectorBundle(X, np.tile(R, (5, 1, 1)), metric=True), geo)
>>> A2.shape, bool(abs(A2 - A2.T).max() == 0), round(float(np.linalg.eigvalsh(A2.toarray()).min()), 12)
((8, 8), True, 0.0)
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from dhlb._coerce import check_int
from dhlb.errors import InvalidParameterError, NonFiniteError, ShapeError
from dhlb.topology import _keys
from dhlb.topology.structure import subfaces

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from dhlb.bundles.hermitian import HermitianLineBundle
    from dhlb.bundles.vector_bundle import VectorBundle
    from dhlb.geometry.euclidean import EuclideanComplex

__all__ = ["TET_PSD_TOL", "connection_laplacian", "connection_mass", "cotan_edge_weights", "tet_connection_laplacian"]

TET_PSD_TOL = 1e-6
"""A tet's plain connection energy is kept while its smallest eigenvalue is ``>= −TET_PSD_TOL ·`` its trace.

Measured with a Möbius factor (a flat connection, where the plain energy is consistent): at most
7.3e-7 on ``ball_tet_mesh(4)``, 1.6e-8 on ``ball_tet_mesh(8)`` (it vanishes under refinement); with
the default charge 2.5e-7 on ``hand-tet.mesh`` and 4.4e-3 on the slivers of ``bunny-tet.mesh``, whose
plain energy has 4 eigenvalues below −9·10⁵ (:func:`tet_connection_laplacian`).
"""


def _check_geometry(X, geometry):
    G = getattr(geometry, "complex", None)
    if G is None or not hasattr(geometry, "cotan_weights"):
        raise TypeError(f"geometry must be a dhlb.geometry.EuclideanComplex, got {type(geometry).__name__}")
    if G is not X and G != X:
        raise ShapeError("the bundle and the geometry live on different complexes; build both on the same "
                         "SimplicialComplex")
    if not X.is_pure:
        raise ShapeError("the connection Laplacian needs a pure complex (every simplex a face of a top simplex)")


def _simplex_weights(weights, X) -> np.ndarray:
    m = X.n_simplices(X.dim)
    if weights is None:
        return np.ones(m)
    try:
        w = np.asarray(weights, dtype=np.float64)
    except (TypeError, ValueError):
        raise ShapeError(f"simplex_weights must be one number per top simplex ({m})") from None
    if w.ndim == 0:
        w = np.full(m, float(w))
    if w.shape != (m,):
        raise ShapeError(f"simplex_weights must be one number per top simplex ({m}), got shape {w.shape}")
    bad = ~np.isfinite(w)
    if np.any(bad):
        s = int(np.argmax(bad))
        raise NonFiniteError(f"simplex_weights[{s}] = {w[s]} (top simplex {X.simplices(X.dim)[s].tolist()}) is "
                             "not finite")
    bad = w < 0
    if np.any(bad):
        s = int(np.argmax(bad))
        raise InvalidParameterError(f"simplex_weights[{s}] = {w[s]} (top simplex {X.simplices(X.dim)[s].tolist()}) "
                                    "is negative; the factors must be >= 0 (0 removes the simplex from the energy)")
    return w


def _transports(bundle, geometry) -> tuple[np.ndarray, bool, object]:
    """``(n_1, k, k)`` transports (float or complex), whether they are all orthogonal / unitary, and the complex."""
    if isinstance(bundle, np.ndarray):
        X = getattr(geometry, "complex", None)
        if X is None:
            _check_geometry(X, geometry)   # raises the TypeError
        T = bundle.reshape(-1, 1, 1) if bundle.ndim == 1 else bundle
        n1 = X.n_simplices(1)
        if T.ndim != 3 or T.shape[0] != n1 or T.shape[1] != T.shape[2] or T.shape[1] == 0:
            raise ShapeError(f"transports must have shape (n_1, k, k) or (n_1,) with n_1 = {n1} edges of "
                             f"geometry.complex, got shape {bundle.shape}")
        if not np.all(np.isfinite(T)):
            e = int(np.argmax(~np.isfinite(T.reshape(n1, -1)).all(axis=1)))
            raise NonFiniteError(f"the transport of edge {X.simplices(1)[e].tolist()} (row {e}) is not finite")
        T = T.astype(np.complex128 if np.iscomplexobj(T) else np.float64, copy=False)
        return T, _is_orthogonal(T), X
    if hasattr(bundle, "connection") and hasattr(bundle, "curvature") and not hasattr(bundle, "transports"):
        return np.asarray(bundle.connection, np.complex128).reshape(-1, 1, 1), True, bundle.X
    if not hasattr(bundle, "transports"):
        raise TypeError(f"bundle must be a VectorBundle, a HermitianLineBundle or an array of transports, got "
                        f"{type(bundle).__name__}")
    field = bundle.field
    if field not in ("R", "C"):
        raise InvalidParameterError(f"the connection Laplacian needs a bundle over R or C, got the field {field!r}")
    T = np.asarray(bundle.transports, np.float64 if field == "R" else np.complex128)
    return T, bool(bundle.metric) or _is_orthogonal(T), bundle.X


def _is_orthogonal(T: np.ndarray) -> bool:
    """All ``ηᴴη = I`` to 16 ulp (entry by entry of the Gram matrices: k² vector sums, no small matmuls)."""
    k = T.shape[1]
    Tc = T.conj()
    return all(bool(np.all(np.abs(np.sum(Tc[:, :, a] * T[:, :, c], axis=1) - (a == c)) <= 16 * np.finfo(float).eps))
               for a in range(k) for c in range(k))


def cotan_edge_weights(geometry: EuclideanComplex, *, simplex_weights: ArrayLike | None = None) -> np.ndarray:
    """The weights ``w_ij = −Σ_σ s_σ c^σ_ij`` per canonical edge (rows of ``complex.simplices(1)``).

    For triangle meshes ``w_ij = (cot β_ij + cot β_ji)/2`` (one term on boundary edges); the
    weighted graph Laplacian with these weights is the P1 stiffness matrix.

    Parameters
    ----------
    geometry : EuclideanComplex
        The metric of a complex of any dimension n; its top simplices are the n-simplices.
    simplex_weights : float or (n_top,) float array, optional
        A factor ``s_σ >= 0`` per top simplex (default 1; 0 removes the simplex).

    Returns
    -------
    w : (n_edges,) float array
        The weight of each canonical edge, in the row order of ``geometry.complex.simplices(1)``
        (all 0 for a 0-dimensional complex).

    Raises
    ------
    ShapeError
        When ``simplex_weights`` is not one number per top simplex.
    NonFiniteError, InvalidParameterError
        NaN/inf or negative ``simplex_weights`` (naming the top simplex).

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> from dhlb.geometry import EuclideanComplex
    >>> geo = EuclideanComplex(SimplicialComplex([(0, 1, 2)]), points=[[0, 0], [1, 0], [0, 1]])
    >>> cotan_edge_weights(geo).round(12).tolist()      # edges (0,1) (0,2) (1,2); cot 90° = 0, cot 45° = 1
    [0.5, 0.5, 0.0]
    """
    X = geometry.complex
    sw = _simplex_weights(simplex_weights, X)
    n = X.dim
    if n == 0:
        return np.zeros(X.n_simplices(1))
    c = np.asarray(geometry.cotan_weights, dtype=np.float64)
    pairs = _keys.combination_columns(n + 1, 2)
    loc = -c[:, pairs[:, 0], pairs[:, 1]] * sw[:, None]
    return np.bincount(subfaces(X, n, 1).ravel(), weights=loc.ravel(), minlength=X.n_simplices(1))


def connection_laplacian(
    bundle: VectorBundle | HermitianLineBundle, geometry: EuclideanComplex, *, simplex_weights: ArrayLike | None = None
) -> sp.csr_matrix:
    """The cotangent connection Laplacian ``A`` with ``vᴴ A v = Σ_{i<j} w_ij |v_j − η_ij v_i|²``.

    Parameters
    ----------
    bundle : VectorBundle (field ``"R"`` or ``"C"``, rank k), HermitianLineBundle (k = 1), or (n_1, k, k) / (n_1,) array
        Transports ``η_ij`` per canonical edge of ``geometry.complex``; an array (float or complex) is
        taken as they are, without building a bundle (the row order of ``geometry.complex.simplices(1)``).
    geometry : EuclideanComplex
        The metric of a pure complex of any dimension n >= 1 (the same complex as the bundle).
    simplex_weights : float or (n_top,) array of numbers >= 0, optional
        A factor ``s_σ`` per top simplex scaling its contribution to every edge weight
        (default 1; 0 removes the simplex, e.g. the branch triangles of a stripe pattern).

    Returns
    -------
    scipy.sparse.csr_matrix, shape (N k, N k)
        Float64 for real bundles, complex128 otherwise; section index ``i·k + a``.

    Raises
    ------
    ShapeError
        Bundle and geometry on different complexes, a non-pure complex, bad ``simplex_weights`` shape,
        an array of transports of the wrong shape.
    NonFiniteError, InvalidParameterError
        NaN/inf or negative ``simplex_weights`` (naming the top simplex), NaN/inf transports (naming the
        edge); a bundle over a finite field.
    TypeError
        ``bundle`` is neither a VectorBundle, a HermitianLineBundle nor an array, or ``geometry`` is not
        an EuclideanComplex.

    Examples
    --------
    A line bundle on a flat square, ``r = e^{iνΔx}``: the plane wave ``e^{iνx}`` has zero energy.

    >>> import numpy as np
    >>> from dhlb import SimplicialComplex, HermitianLineBundle
    >>> from dhlb.geometry import EuclideanComplex
    >>> X = SimplicialComplex([(0, 1, 2), (1, 2, 3)])
    >>> P = np.array([[0, 0], [1, 0], [0, 1], [1, 1]], float)
    >>> E = X.simplices(1)
    >>> dx = P[E[:, 1], 0] - P[E[:, 0], 0]
    >>> L = HermitianLineBundle(X, np.exp(0.7j * dx), np.zeros(2))
    >>> A = connection_laplacian(L, EuclideanComplex(X, points=P))
    >>> psi = np.exp(0.7j * P[:, 0])
    >>> abs(complex(psi.conj() @ A @ psi)) < 1e-14
    True
    >>> bool(abs(connection_laplacian(L.connection, EuclideanComplex(X, points=P)) - A).max() == 0)   # the array
    True
    """
    T, orthogonal, X = _transports(bundle, geometry)
    _check_geometry(X, geometry)
    sw = _simplex_weights(simplex_weights, X)
    k = T.shape[1]
    N = X.n_vertices
    n = X.dim
    if n == 0 or X.n_simplices(1) == 0:
        return sp.csr_matrix((N * k, N * k), dtype=T.dtype)
    c = np.asarray(geometry.cotan_weights, dtype=np.float64) * sw[:, None, None]  # c_ab = −w contribution
    if not orthogonal:
        return _general_laplacian(X, T, c)
    # the weighted P1 stiffness K (the sums of EuclideanComplex.stiffness_matrix), then K_ij ↦ K_ij η per edge
    S = X.simplices(n)
    rows = np.broadcast_to(S[:, :, None], c.shape).ravel()
    cols = np.broadcast_to(S[:, None, :], c.shape).ravel()
    K = sp.coo_matrix((c.ravel(), (rows, cols)), shape=(N, N)).tocsr()   # canonical: sorted, explicit zeros kept
    indptr, idx, val = K.indptr, K.indices, K.data
    row = np.repeat(np.arange(N, dtype=idx.dtype), np.diff(indptr))
    upper, lower = idx > row, idx < row
    # K has exactly the edges of the pure complex off the diagonal and the diagonal: the pattern of
    # X.vertex_adjacency, which names the two entries of each canonical edge
    adj = X.vertex_adjacency
    edge = np.zeros(K.nnz, np.int64)
    edge[adj.upper] = edge[adj.lower] = np.arange(X.n_simplices(1))
    if k == 1:
        eta = T[edge, 0, 0]
        return sp.csr_matrix((val * np.where(upper, eta.conj(), np.where(lower, eta, 1.0)), idx, indptr), shape=(N, N))
    return _expand_blocks(K, row, upper, lower, T, edge)


def _expand_blocks(K, row, upper, lower, T, edge) -> sp.csr_matrix:
    """The csr matrix with the blocks ``K_ii I`` (diagonal only, no stored zeros), ``K_ij ηᴴ`` (i < j), ``K_ij η``."""
    N, k = K.shape[0], T.shape[1]
    indptr, idx, val = K.indptr, K.indices, K.data
    eta = T[edge]
    blocks = np.where(upper[:, None, None], np.swapaxes(eta, 1, 2).conj(), eta)
    diag = ~(upper | lower)
    blocks[diag] = np.eye(k)
    B = sp.bsr_matrix((val[:, None, None] * blocks, idx, indptr), shape=(N * k, N * k)).tocsr()
    # drop the off-diagonal entries of the diagonal blocks: k − 1 per row, at known places (each row of K
    # has its diagonal entry, the complex being pure; row i k + a of B lists the blocks of row i of K in order)
    t = np.flatnonzero(diag)
    i = row[t].astype(np.int64)
    ak = np.arange(k)
    start = B.indptr[(i * k)[:, None] + ak] + (k * (t - indptr[i]))[:, None]
    drop = (start[:, :, None] + ak)[:, ~np.eye(k, dtype=bool)]
    keep = np.ones(B.nnz, bool)
    keep[drop.ravel()] = False
    ptr = B.indptr - (k - 1) * np.arange(N * k + 1, dtype=B.indptr.dtype)
    return sp.csr_matrix((B.data[keep], B.indices[keep], ptr), shape=(N * k, N * k))


def _general_laplacian(X, T: np.ndarray, c: np.ndarray) -> sp.csr_matrix:
    """The connection Laplacian of non-orthogonal transports, simplex by simplex (diagonal blocks ``Σ w ηᴴη``)."""
    k, N, n = T.shape[1], X.n_vertices, X.dim
    S = X.simplices(n)
    L = np.zeros((S.shape[0], n + 1, n + 1, k, k), dtype=T.dtype)
    eye = np.eye(k)
    edges = subfaces(X, n, 1)
    for p, (a, b) in enumerate(_keys.combination_columns(n + 1, 2).tolist()):
        eta = T[edges[:, p]]
        cab = c[:, a, b, None, None]
        L[:, a, b] = cab * np.swapaxes(eta, 1, 2).conj()  # A[i, j] = −w ηᴴ   (i = v_a < j = v_b)
        L[:, b, a] = cab * eta  # A[j, i] = −w η
        L[:, a, a] -= cab * np.einsum("sba,sbc->sac", eta.conj(), eta)
        L[:, b, b] -= cab * eye
    off = np.arange(k)
    rows = np.broadcast_to(S[:, :, None, None, None] * k + off[:, None], L.shape)
    cols = np.broadcast_to(S[:, None, :, None, None] * k + off[None, :], L.shape)
    return sp.coo_matrix((L.ravel(), (rows.ravel(), cols.ravel())), shape=(N * k, N * k)).tocsr()


def connection_mass(geometry: EuclideanComplex, rank: int = 1, *, lumped: bool = True) -> sp.csr_matrix:
    """The mass matrix of rank-k sections, ``M ⊗ I_k`` (lumped: ``Σ_{σ ∋ i} vol(σ)/(n+1)`` on the diagonal).

    Parameters
    ----------
    geometry : EuclideanComplex
        The metric of the complex.
    rank : int >= 1
        The rank k of the bundle (number of components per vertex).
    lumped : bool
        Diagonal lumped mass (default) or the consistent P1 mass of each component.

    Returns
    -------
    (N k, N k) float scipy.sparse.csr_matrix
        ``N = geometry.complex.n_vertices``; section index ``i·k + a`` as in :func:`connection_laplacian`.

    Raises
    ------
    InvalidParameterError
        When ``rank`` is not an integer >= 1.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> from dhlb.geometry import EuclideanComplex
    >>> geo = EuclideanComplex(SimplicialComplex([(0, 1, 2)]), points=[[0, 0], [3, 0], [0, 2]])
    >>> connection_mass(geo, 2).diagonal().tolist()
    [1.0, 1.0, 1.0, 1.0, 1.0, 1.0]
    """
    rank = check_int(rank, "rank", 1)
    M = geometry.mass_matrix(lumped=bool(lumped))
    if rank == 1:
        return sp.csr_matrix(M)
    if lumped:
        return sp.csr_matrix(sp.diags(np.repeat(M.diagonal(), rank), format="csr"))
    return sp.csr_matrix(sp.kron(M, sp.identity(rank), format="csr"))


def tet_connection_laplacian(bundle: VectorBundle, geometry: EuclideanComplex) -> sp.csr_matrix:
    r"""The connection energy of a metric bundle on a tet mesh, assembled tet by tet; no tet term is indefinite.

    The plain energy ``Σ_ij w_ij |ψ_j − η_ij ψ_i|²`` (:func:`dhlb.fem.connection_laplacian`) is a
    sum over tets of ``A_T = Σ_{ab ⊂ T} w^T_ab |ψ_b − η_ab ψ_a|²``.  ``A_T`` is a unitary conjugate
    of the P1 stiffness of ``T`` (positive semidefinite whatever the signs of its cotan weights)
    only when the transports around ``T`` compose to the identity.  With a curved connection and
    negative weights (obtuse dihedral angles, slivers) it can be indefinite: the plain energy of
    ``bunny-tet.mesh`` under the default charge has 4 eigenvalues below −9·10⁵, with eigenvectors
    on a few slivers, and its least-energy section vanishes.  A tet whose ``A_T`` has an
    eigenvalue below ``−TET_PSD_TOL · tr A_T`` (:data:`TET_PSD_TOL`) is therefore read in the
    gauge of one of its vertices ``k``: the value at ``a`` is carried to ``k`` along the edge
    ``ak``, so the term ``ab`` uses the path ``a → k → b`` (``η_kb η_ak``; the edge ``ab`` itself
    when ``k ∈ {a, b}``), and the four choices of ``k`` are averaged.  Each gauged term is the
    scalar P1 stiffness of ``T`` conjugated by a unitary, hence PSD; the diagonal is unchanged and
    the off-diagonal block of the edge ``ab`` in ``T`` becomes
    ``−w^T_ab ¼ (2 η_ab + Σ_{k ∉ {a,b}} η_kb η_ak)``.  Path and edge transports differ by the
    holonomy of a triangle, ``1 + O(F h²)``; every other tet keeps its plain term, so that on
    meshes without such tets the result is :func:`dhlb.fem.connection_laplacian`
    (``proofs/derive_conformal_tet_energy.py``). Used by :func:`dhlb.conformal.conformal_deformation`.

    Parameters
    ----------
    bundle : VectorBundle
        A metric (unitary or orthogonal transports) bundle of rank k over a pure 3-dimensional complex.
    geometry : EuclideanComplex
        Its metric (the cotan weights of each tet).

    Returns
    -------
    scipy.sparse.csr_matrix, shape (N k, N k)
        Section index ``i·k + a``, like :func:`dhlb.fem.connection_laplacian`.

    Raises
    ------
    ShapeError
        The complex is not 3-dimensional, or bundle and geometry live on different complexes.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import box_tet_mesh
    >>> from dhlb.conformal import quaternion_bundle
    >>> from dhlb.fem import connection_laplacian
    >>> from dhlb.geometry import EuclideanComplex
    >>> mesh = box_tet_mesh(2)
    >>> geo = EuclideanComplex(mesh.complex, points=mesh.points)
    >>> flat = quaternion_bundle(mesh, np.zeros((mesh.complex.n_simplices(1), 3)))     # trivial: the plain energy
    >>> bool(abs(tet_connection_laplacian(flat, geo) - connection_laplacian(flat, geo)).max() < 1e-14)
    True
    >>> steep = quaternion_bundle(mesh, np.tile([30.0, 0, 0], (mesh.complex.n_simplices(1), 1)))
    >>> A = tet_connection_laplacian(steep, geo)
    >>> bool(np.linalg.eigvalsh(A.toarray()).min() > -1e-12)
    True
    """
    X = bundle.X
    c = np.asarray(geometry.cotan_weights, dtype=np.float64)     # c_ab = −w^T_ab, c_aa = Σ w^T
    if X.dim != 3 or geometry.complex.n_vertices != X.n_vertices or c.shape != (X.n_simplices(3), 4, 4):
        raise ShapeError(f"tet_connection_laplacian needs a bundle and a geometry on the same tet complex (bundle: "
                         f"dimension {X.dim}, {X.n_vertices} vertices; cotan weights of shape {c.shape})")
    A = connection_laplacian(bundle, geometry)                   # the plain terms; then repair the few bad tets
    eta = np.asarray(bundle.transports)
    k = eta.shape[1]
    pairs = _keys.combination_columns(4, 2).tolist()
    ia, ib = [a for a, _ in pairs], [b for _, b in pairs]
    # only a tet with a negative weight can be indefinite (else A_T = Σ w |ψ_b − η ψ_a|² is a sum of squares)
    cand = np.flatnonzero(np.any(c[:, ia, ib] > 0, axis=1))
    if cand.size == 0:
        return A
    S, c, edges = X.simplices(3)[cand], c[cand], subfaces(X, 3, 1)[cand]
    m, N = cand.size, X.n_vertices
    tau = np.zeros((m, 4, 4, k, k), dtype=eta.dtype)             # tau[:, a, b]: a → b
    for p, (a, b) in enumerate(pairs):
        t = eta[edges[:, p]]
        tau[:, a, b], tau[:, b, a] = t, np.swapaxes(t, 1, 2).conj()
    L = np.zeros((m, 4, 4, k, k), dtype=eta.dtype)              # A_T of the candidates, as connection_laplacian
    for a in range(4):
        L[:, a, a] = c[:, a, a, None, None] * np.eye(k)
    for a, b in pairs:
        blk = c[:, a, b, None, None] * tau[:, a, b]
        L[:, b, a], L[:, a, b] = blk, np.swapaxes(blk, 1, 2).conj()
    dense = np.swapaxes(L, 2, 3).reshape(m, 4 * k, 4 * k)
    low = np.linalg.eigvalsh(dense)[:, 0] < -TET_PSD_TOL * np.trace(dense, axis1=1, axis2=2).real  # O(m) small eigs
    if not np.any(low):
        return A
    D = np.zeros((int(low.sum()), 4, 4, k, k), dtype=eta.dtype)  # gauged minus plain off-diagonal blocks
    for a, b in pairs:
        avg = 2.0 * tau[low, a, b]
        for j in range(4):
            if j not in (a, b):
                avg = avg + tau[low, j, b] @ tau[low, a, j]
        blk = c[low, a, b, None, None] * (0.25 * avg) - L[low, b, a]
        D[:, b, a], D[:, a, b] = blk, np.swapaxes(blk, 1, 2).conj()
    off = np.arange(k)
    rows = np.broadcast_to(S[low][:, :, None, None, None] * k + off[:, None], D.shape)
    cols = np.broadcast_to(S[low][:, None, :, None, None] * k + off[None, :], D.shape)
    return (A + sp.coo_matrix((D.ravel(), (rows.ravel(), cols.ravel())), shape=(N * k, N * k))).tocsr()
