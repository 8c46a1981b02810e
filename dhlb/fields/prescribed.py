"""n-direction fields with prescribed singularities: the dualised *trivial connections* of Crane et al.

The seed (part 1, conclusion; part 2, Fig. 5) edits a field by changing the connection of the
n-th power tangent bundle (:mod:`dhlb.mesh.tangent`) by the smallest amount ``δ`` (one angle per
edge) that makes it **flat** away from chosen faces, with holonomy ``2π k_f`` around face ``f``, and
**trivial** around every generator of H₁ up to a chosen rotation; the field is then a parallel
section of the new connection ``r_ij e^{iδ_ij}``.

Conditions (mesh orientation, ``docs/conventions.md``): per face ``f`` with half-edges ``h``
(``a → b``, sign ``s_h = +1`` if ``a < b``) and curvature ``Ω_f = n σ_f``,

    Σ_h s_h δ_e(h) = 2π k_f − Ω_f,                                       (faces)

and per generator ``c`` of H₁ (a cycle of the primal spanning tree closed by one edge),
``⟨c, δ⟩ = θ_c`` with ``θ_c ≡ −hol_ρ(c) (mod 2π)`` so that the new connection has trivial
holonomy around ``c`` (``θ_c`` is the rotation of the field relative to parallel transport along
``c``; default: the admissible value closest to the period of the correction that only enforces
the face conditions). The rotation form of the parallel section is ``ξ = δ`` where ``|δ| < π``,
so the index form ``(dξ + Ω)/2π`` equals ``k`` exactly (Eq. 6.9; ``proofs/derive_prescribed_field.py``).

**Solve.** A particular solution ``δ_p`` by a tree–cotree sweep (``δ = 0`` on a BFS spanning
tree of the vertices, ``θ`` on the generator edges, the edges of a dual spanning tree of the faces
from the subtree sums of the face conditions, leaves first); every solution differs from it by an
exact form ``d₀ f`` (the corrections that change no holonomy), so the minimal-norm one is the
W-orthogonal projection ``δ = δ_p − d₀ L⁻¹ d₀ᵀ W δ_p`` with ``L = d₀ᵀ W d₀`` grounded at one vertex
per component. With the default ``weights="cotan"`` (``W`` = the DEC Hodge star ``⋆₁``,
:func:`dhlb.fem.cotan_edge_weights`) ``L`` is the P1 cotangent Laplacian, positive semidefinite
on every mesh, and ``δ`` converges to the smooth minimiser; ``weights="uniform"`` is the plain
ℓ² norm of Crane et al. (``L`` the combinatorial graph Laplacian). ``L`` is factored through
:func:`dhlb.fem.solve` (the package's direct backends, one factorization for all right-hand
sides: the admissible δ and one harmonic form per generator); it is a plain weighted graph
Laplacian, but going through ``dhlb.fem`` keeps the backend choice, the ordering cache and the
positive-definiteness check of the rest of the package.

**Section.** The new connection is flat with trivial holonomy, so transport along the BFS
spanning tree (:func:`dhlb.bundles.paths.tree_accumulate`) is exact; the closing defect on the
other edges is reported as ``flatness_defect`` (round-off).

**Boundaries.** On a component with boundary the face conditions do not constrain the index sum:
the field's rotation relative to parallel transport along the positively oriented boundary is
``R = 2π Σ_f k_f − Σ_f Ω_f`` (Poincaré–Hopf with boundary, :class:`~dhlb.fields.FieldIndices`),
so any integer sum is admissible; the generators then include all boundary loops but one and
``holonomy`` distributes ``R`` over them. On a closed component ``Σ_f k_f = n χ`` is required.

**Higher-order singularities.** On one triangle ``|2π k_f − Ω_f| < 3π`` is needed (each of the
three ``δ_e`` lies in (−π, π]), so only ``k_f ∈ {−1, 0, +1}`` are accepted; a singularity of
index ``k/n`` with ``|k| > 1`` is prescribed as ``|k|`` unit singularities on distinct faces
(e.g. faces around one vertex), and the result then has exactly those ``|k|`` singular faces.
If the minimal correction still exceeds π on some edge (unit singularities on adjacent faces
of a coarse mesh), the indices cannot be realised and an error names the edge.

Examples
--------
>>> from dhlb.io import read_surface, example_path
>>> from dhlb.fields import prescribed_field
>>> V, F = read_surface(example_path("spot.obj"))
>>> res = prescribed_field(V, F, 1, {0: 1, 3000: 1})        # two +1 of a vector field: χ = 2
>>> res.singularities.input_faces.tolist(), res.singularities.index.tolist()
([0, 3000], [1, 1])
"""

from __future__ import annotations

import numbers
import time
from collections.abc import Mapping

import numpy as np
import scipy.sparse as sp

from dhlb._deprecation import fold_deprecated_kwargs
from dhlb._memory_errors import translate_memory_errors
from dhlb.bundles._util import simplex_name, wrap_angle
from dhlb.bundles.paths import bfs_forest, fundamental_cycles, spanning_forest, tree_accumulate
from dhlb.errors import InvalidParameterError, NonFiniteError, ShapeError
from dhlb.fem import cotan_edge_weights, solve
from dhlb.fields.directions import direction_vectors, field_indices
from dhlb.fields.energy import _tangent, energy_matrices
from dhlb.fields.field import _field_estimate, check_symmetry_memory
from dhlb.fields.options import FieldOptions
from dhlb.fields.result import PrescribedField
from dhlb.linalg import SolverOptions, solver_options
from dhlb.mesh.tangent import TangentBundle

__all__ = ["prescribed_field", "locate_faces"]

_TWO_PI = 2.0 * np.pi
_MARGIN = 1e-3  # |δ| must stay below π − _MARGIN (exact indices with room for round-off)
_RAISE = 3.0  # factor on the weight of an edge where |δ| reached it
_MAX_REWEIGHT = 20
_FLOOR = 0.5  # cotangent weights below this fraction of their median are raised to it


def locate_faces(mesh, points) -> tuple[np.ndarray, np.ndarray]:
    """The face of ``mesh`` nearest to each point and the distance to it.

    The closest point of a triangle is the projection onto its plane if that lies inside,
    else the closest point of one of its three edges.

    Parameters
    ----------
    mesh : SurfaceMesh
    points : (k, 3) array

    Returns
    -------
    faces : (k,) int64, rows of ``mesh.faces``
    distance : (k,) float64

    Raises
    ------
    ShapeError
        ``points`` is not ``(k, 3)``.
    NonFiniteError
        A point is NaN or infinite.

    Examples
    --------
    >>> from dhlb.mesh import validate_surface
    >>> from dhlb.fields.prescribed import locate_faces
    >>> mesh = validate_surface([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], [[0, 1, 2], [1, 3, 2]])
    >>> f, d = locate_faces(mesh, [[0.9, 0.8, 0.5], [0.1, 0.1, 0.0]])
    >>> f.tolist(), d.round(12).tolist()
    ([1, 0], [0.5, 0.0])
    """
    P = np.asarray(points, dtype=np.float64)
    if P.ndim != 2 or P.shape[1] != 3:
        raise ShapeError(f"points must have shape (k, 3), got {P.shape}")
    if not np.all(np.isfinite(P)):
        raise NonFiniteError(f"point {int(np.argmax(~np.isfinite(P).all(axis=1)))} is not finite")
    T = mesh.points[mesh.faces]  # (m, 3, 3)
    A, E1, E2 = T[:, 0], T[:, 1] - T[:, 0], T[:, 2] - T[:, 0]
    g11, g12, g22 = (E1 * E1).sum(1), (E1 * E2).sum(1), (E2 * E2).sum(1)
    det = g11 * g22 - g12 * g12
    faces, dist = np.empty(len(P), np.int64), np.empty(len(P))
    for i, p in enumerate(P):
        w = p - A
        b1, b2 = (w * E1).sum(1), (w * E2).sum(1)
        x = (g22 * b1 - g12 * b2) / det
        y = (g11 * b2 - g12 * b1) / det
        inside = (x >= 0) & (y >= 0) & (x + y <= 1)
        best = np.where(inside, np.linalg.norm(w - x[:, None] * E1 - y[:, None] * E2, axis=1), np.inf)
        for k in range(3):  # distance to the three edges (segments)
            a, b = T[:, k], T[:, (k + 1) % 3]
            e = b - a
            t = np.clip(((p - a) * e).sum(1) / (e * e).sum(1), 0.0, 1.0)
            best = np.minimum(best, np.linalg.norm(p - a - t[:, None] * e, axis=1))
        faces[i] = int(np.argmin(best))
        dist[i] = float(best[faces[i]])
    return faces, dist


def _as_index(value, key) -> int:
    ok = isinstance(value, numbers.Integral) and not isinstance(value, (bool, np.bool_))
    if not ok and isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_)):
        ok = bool(np.isfinite(value) and float(value).is_integer())
    if not ok:
        raise InvalidParameterError(
            f"the index at {key!r} must be an integer k (a singularity of index k/n of the n-direction field), "
            f"got {value!r}")
    return int(value)


def _prescription(mesh, singularities, n_input_faces: int):
    """Per-face prescribed index (mesh orientation) and the list (face, k, key) of the input."""
    if singularities is None:
        items = []
    elif isinstance(singularities, Mapping):
        items = list(singularities.items())
    else:
        try:
            items = [tuple(it) for it in singularities]
        except TypeError:
            raise InvalidParameterError("singularities must map faces (or points) to integer indices, e.g. "
                                        f"{{12: 1, 40: -1}}, got {type(singularities).__name__}") from None
        if any(len(it) != 2 for it in items):
            raise InvalidParameterError("singularities given as a sequence must hold (face or point, index) pairs")
    row_to_face = np.full(max(n_input_faces, 1), -1, np.int64)
    row_to_face[mesh.face_rows] = np.arange(mesh.n_faces)
    K = np.zeros(mesh.n_faces, np.int64)
    faces, points, pkeys, pvals = [], [], [], []
    for key, value in items:
        k = _as_index(value, key)
        if isinstance(key, numbers.Integral) and not isinstance(key, (bool, np.bool_)):
            r = int(key)
            if not 0 <= r < n_input_faces:
                raise InvalidParameterError(f"singular face {r} is out of range: F has {n_input_faces} rows "
                                            f"(faces are rows of the input F, 0 .. {n_input_faces - 1})")
            f = int(row_to_face[r])
            if f < 0:
                raise InvalidParameterError(f"face {r} is not part of the surface (dropped with components='largest')")
            faces.append((f, k))
        else:
            p = np.asarray(key, dtype=np.float64) if not isinstance(key, str) else np.zeros(0)
            if p.shape != (3,):
                raise InvalidParameterError(f"a singularity is located by a face (row of F) or a point (x, y, z), "
                                            f"got {key!r}")
            points.append(p)
            pkeys.append(key)
            pvals.append(k)
    if points:
        fl, _ = locate_faces(mesh, np.array(points))
        faces += [(int(f), k) for f, k in zip(fl, pvals)]
    for f, k in faces:
        K[f] += k
    return K


def _check_prescription(tb: TangentBundle, K: np.ndarray, face_comp: np.ndarray, closed: np.ndarray,
                        chi: np.ndarray) -> None:
    mesh = tb.mesh
    n = tb.n
    excess = np.abs(_TWO_PI * K - n * tb.face_curvature) >= 3 * np.pi
    if np.any(excess):
        f = int(np.argmax(excess))
        raise InvalidParameterError(
            f"index {int(K[f])} at face {int(mesh.face_rows[f])} cannot be realised on one triangle (|2πk − Ω| must "
            f"be < 3π, Ω = {n * tb.face_curvature[f]:.3g}; only −1, 0, +1 fit): prescribe a singularity of index "
            f"k/n with |k| > 1 as |k| unit singularities on distinct faces, e.g. the faces around a vertex")
    sums = np.bincount(face_comp, weights=K, minlength=closed.size).round().astype(np.int64)
    for c in np.nonzero(closed)[0]:
        if sums[c] != n * chi[c]:
            where = "" if closed.size == 1 else f" on connected component {c} (faces of input rows e.g. " \
                f"{int(mesh.face_rows[np.argmax(face_comp == c)])})"
            raise InvalidParameterError(
                f"the prescribed indices sum to {int(sums[c])}{where}, but Poincaré–Hopf needs n·χ = {n}·{int(chi[c])} "
                f"= {n * int(chi[c])} on a closed surface: add or remove indices summing to "
                f"{n * int(chi[c]) - int(sums[c])}")


def _subtree_sums(parent: np.ndarray, depth: np.ndarray, R: np.ndarray) -> np.ndarray:
    """``acc[v] = Σ_{u in the subtree of v} R[u]`` (rows), leaves first, one vectorized step per level."""
    acc = np.array(R, dtype=np.float64, copy=True)
    order = np.argsort(-depth, kind="stable")
    d = depth[order]
    cuts = np.flatnonzero(np.diff(d)) + 1
    for nodes in np.split(order, cuts):
        if depth[nodes[0]] == 0:
            break
        np.add.at(acc, parent[nodes], acc[nodes])
    return acc


@translate_memory_errors("prescribed_field", _field_estimate)
def prescribed_field(V, F=None, n: int | None = None, singularities=None, *, holonomy=None,
                     weights: str = "auto", options: FieldOptions | None = None,
                     solver: SolverOptions | str | None = None, **deprecated) -> PrescribedField:
    """The n-direction field with exactly the prescribed singularities (dualised trivial connection).

    Parameters
    ----------
    V : (k, 3) float array, or SurfaceMesh / TangentBundle
        Vertex positions (or a mesh, then ``F`` is None).
    F : (m, 3) int array, optional
        Triangles (rows of ``V``).
    n : int >= 1, optional
        Symmetry (default: that of a TangentBundle ``V``, else 1).
    singularities : mapping or sequence of pairs
        ``{face: k}`` or ``{(x, y, z): k}``: a row of the input F, or a point (the nearest face is
        used), mapped to the integer index ``k`` of the n-th power field (a singularity of index
        ``k/n`` of the directions; ``k ∈ {−1, 0, +1}`` per face, see the module notes). Entries
        on the same face add up. On a closed component the sum must be ``n χ``.
    holonomy : None or (q,) array of angles
        ``θ_c``: rotation of the field (n-th power) relative to parallel transport along each
        generator of ``res.generators``; admissible values are ``res.admissible_holonomy + 2πZ``.
        None: per generator the admissible value closest to the period of the correction that
        enforces the face conditions only (the smoothest choice up to rounding).
    weights : {"auto", "cotan", "uniform"}
        Norm of δ: the Hodge star ``⋆₁`` (cotangent weights, floored at half their median; converges
        under refinement) or plain ℓ² (Crane et al.; robust, not consistent under refinement).
        Edges where the minimal δ comes within 1e-3 of π get their weight raised ×3 and δ is solved
        again (at most 20 times): δ is then minimal for ``res.edge_weights``. ``"auto"``: cotan, and
        uniform if cotan cannot realise the indices; ``res.weights`` says which was used.
    options : FieldOptions, optional
        Mesh repair (``repair``, ``reorient``, ``components``; :class:`~dhlb.fields.FieldOptions`).
    solver : dhlb.linalg.SolverOptions or str, optional
        The backend of :func:`dhlb.fem.solve` (:class:`~dhlb.linalg.SolverOptions`, or a backend name).
    **deprecated
        The keywords ``reorient``, ``components`` (→ ``options``) and ``backend`` (→ ``solver``) of
        dhlb 0.1, with a :class:`DeprecationWarning`.

    Returns
    -------
    PrescribedField
        A :class:`~dhlb.fields.DirectionField` (``s = 0``; ``energy`` is ``uᴴ A₀ u``) with the
        correction ``delta`` (per canonical edge), ``delta_norm``, ``prescribed`` (per face),
        ``generators``, ``holonomy`` and ``admissible_holonomy``.

    Raises
    ------
    InvalidParameterError
        Poincaré–Hopf violated (the message names the sum and n·χ), a face row out of range,
        a non-integer index, an index that no triangle can carry, ``holonomy`` of the wrong
        length or not admissible, bad ``weights``, or a prescription whose minimal correction
        exceeds π on an edge (not representable on this mesh).
    ResourceLimitError
        The ``n`` directions per vertex would not fit in memory
        (:func:`~dhlb.fields.field.check_symmetry_memory`): refused before any work, with the estimate and
        the largest n that fits.
    InsufficientMemoryError
        The computation ran out of memory all the same (a mesh too large for the memory available): the
        message says about how much it needs and how much is available.
    TypeError
        An unknown keyword argument.

    Examples
    --------
    >>> from dhlb.io import read_surface, example_path
    >>> from dhlb.fields import FieldOptions, prescribed_field
    >>> res = prescribed_field(*read_surface(example_path("torus.obj")), n=4, singularities={5: 1, 100: -1})
    >>> res.face_index[res.singularities.faces].tolist(), res.index_sum, res.generators.shape[0]
    ([1, -1], 0, 2)
    >>> prescribed_field(*read_surface(example_path("torus.obj")), n=4, singularities={5: 1, 100: -1},
    ...                  options=FieldOptions(reorient=True), solver="superlu").index_sum
    0
    """
    options, solver = fold_deprecated_kwargs(
        "prescribed_field", deprecated, ("options", options, FieldOptions(), ("reorient", "components")),
        ("solver", solver, SolverOptions(), ("backend",)))
    reorient, components, backend = options.reorient, options.components, solver_options(solver).backend
    t0 = time.perf_counter()
    if n is None:
        n = V.n if isinstance(V, TangentBundle) else 1
    if isinstance(n, (bool, np.bool_)) or not isinstance(n, numbers.Integral) or n < 1:
        raise InvalidParameterError(f"n must be an integer >= 1, got {n!r}")
    check_symmetry_memory(n, V)
    if weights not in ("auto", "cotan", "uniform"):
        raise InvalidParameterError(f"weights must be 'auto', 'cotan' or 'uniform', got {weights!r}")
    tb = _tangent(V, F, int(n), reorient, components, options.repair)
    mesh, X = tb.mesh, tb.mesh.complex
    n_input_faces = len(np.asarray(F)) if F is not None else int(mesh.face_rows.max(initial=-1)) + 1
    nf, n1 = mesh.n_faces, X.n_simplices(1)

    # components: χ and closedness per component
    ncomp, vlabel = mesh.components
    face_comp = vlabel[mesh.faces[:, 0]]
    he, tw = mesh.halfedge_edge, mesh.halfedge_twin
    E = X.simplices(1)
    chi = (np.bincount(vlabel, minlength=ncomp) - np.bincount(vlabel[E[:, 0]], minlength=ncomp)
           + np.bincount(face_comp, minlength=ncomp))
    closed = np.ones(ncomp, bool)
    closed[face_comp[np.nonzero(tw < 0)[0] // 3]] = False
    K = _prescription(mesh, singularities, n_input_faces)
    _check_prescription(tb, K, face_comp, closed, chi)

    # tree (vertices) – cotree (faces + one virtual face outside the boundary) – generators
    forest = spanning_forest(X)
    Fm = mesh.faces
    a, b = Fm.ravel(), np.roll(Fm, -1, axis=1).ravel()
    sgn = np.where(a < b, 1.0, -1.0)
    h = np.arange(3 * nf, dtype=np.int64)
    link = np.nonzero(((tw > h) | (tw < 0)) & ~forest.tree_mask[he])[0]
    la = link // 3
    lb = np.where(tw[link] >= 0, tw[link] // 3, nf)
    _, _, parent, order = bfs_forest(nf + 1, la, lb, roots=[nf])
    ph = np.full(nf + 1, -1, np.int64)  # half-edge of each face on its cotree edge (to the parent)
    down = (lb < nf) & (parent[lb] == la)
    ph[lb[down]] = tw[link[down]]
    up = parent[la] == lb
    ph[la[up]] = link[up]
    child = np.nonzero(ph >= 0)[0]
    cotree = np.zeros(n1, bool)
    cotree[he[ph[child]]] = True
    gens = np.nonzero(~forest.tree_mask & ~cotree)[0]
    q = gens.size
    depth = tree_accumulate(parent, np.ones(nf + 1, np.int64), np.add, 0, order=order)

    # holonomy of the connection around each generator (fundamental cycle e + tree paths)
    rho = wrap_angle(tb.transport_angles)
    vchild = np.nonzero(forest.parent >= 0)[0]

    def tree_angles(form):
        step = np.zeros(mesh.n_vertices)
        pe = forest.parent_edge[vchild]
        step[vchild] = np.where(forest.parent[vchild] < vchild, form[pe], -form[pe])
        return tree_accumulate(forest, step, np.add, 0.0)

    phi_rho = tree_angles(rho)
    hol = phi_rho[E[gens, 0]] + rho[gens] - phi_rho[E[gens, 1]]
    base = wrap_angle(-hol)

    # particular solutions: column 0 the face conditions (θ = 0), column 1 + j the closed form
    # that is 1 on generator j (face conditions 0)
    g = _TWO_PI * K - n * tb.face_curvature
    Dp = np.zeros((n1, 1 + q))
    Dp[gens, 1 + np.arange(q)] = 1.0
    known = np.where(cotree[he], 0.0, sgn)[:, None] * Dp[he]  # (3nf, 1 + q): tree and generator edges
    R = np.zeros((nf + 1, 1 + q))
    R[:nf] = -known.reshape(nf, 3, 1 + q).sum(axis=1)
    R[:nf, 0] += g
    acc = _subtree_sums(parent, depth, R)
    hc = ph[child]
    Dp[he[hc]] = sgn[hc][:, None] * acc[child]

    # minimal W-norm: project out the exact part, δ = δ_p − d₀ L⁻¹ d₀ᵀ W δ_p; where it exceeds π
    # (an index would move to a neighbour face), raise W there and solve again
    d0 = sp.csr_matrix((np.tile([-1.0, 1.0], n1), E.ravel(), np.arange(0, 2 * n1 + 1, 2)),
                       shape=(n1, mesh.n_vertices))  # X.coboundary(0): (d₀f)_ij = f_j − f_i
    keep = np.ones(mesh.n_vertices, bool)
    keep[forest.roots] = False
    d0k = d0[:, keep]
    t1 = time.perf_counter()
    for kind in (("cotan", "uniform") if weights == "auto" else (weights,)):
        w = _edge_weights(tb, kind)
        reweighted = 0
        for _ in range(_MAX_REWEIGHT + 1):
            delta, theta, L = _minimal(d0k, w, Dp, base, holonomy, X, gens, backend)
            over = np.abs(delta) > np.pi - _MARGIN
            if not np.any(over) or reweighted == _MAX_REWEIGHT:
                break
            w = w.copy()
            w[over] *= _RAISE
            reweighted += 1
        if not np.any(np.abs(delta) >= np.pi):
            break
    weights = kind
    t2 = time.perf_counter()
    if np.any(np.abs(delta) >= np.pi):
        e = int(np.argmax(np.abs(delta)))
        raise InvalidParameterError(
            f"the prescription is not representable on this mesh: the correction is {delta[e]:.3g} (|δ| ≥ π) on "
            f"edge {simplex_name(X, 1, e)} even after {reweighted} reweightings, so an index would move to a "
            "neighbouring face; move nearby singularities apart (or refine the mesh)")

    # the section: parallel transport of the flat connection ρ + δ along the spanning tree
    phi = tree_angles(wrap_angle(rho + delta))
    nontree = forest.nontree
    defect = wrap_angle(phi[E[nontree, 1]] - phi[E[nontree, 0]] - rho[nontree] - delta[nontree])
    flatness = float(np.max(np.abs(defect), initial=0.0))
    A, M = energy_matrices(tb, s=0.0)
    u = np.exp(1j * phi)
    u /= np.sqrt(max(float((u.conj() @ (M @ u)).real), np.finfo(float).tiny))
    energy = float((u.conj() @ (A @ u)).real)
    dirs = direction_vectors(tb, u)
    indices = field_indices(tb, u)
    t3 = time.perf_counter()
    chains = fundamental_cycles(X, forest, gens) if q else sp.csr_matrix((0, n1), dtype=np.int64)
    return PrescribedField(
        n=int(n), s=0.0, lam=0.0, tangent=tb, u=u, directions=dirs, indices=indices, energy=energy,
        eigenvalue=None, t=None, guidance=None,
        solver={"backend": "dhlb.fem.solve", "weights": weights, "unknowns": int(L.shape[0]),
                "right_hand_sides": 1 + q, "reweighted": reweighted, "flatness_defect": flatness},
        timings={"setup": t1 - t0, "solve": t2 - t1, "indices": t3 - t2, "total": time.perf_counter() - t0},
        prescribed=K, delta=delta, delta_norm=float(np.sqrt(delta @ (w * delta))),
        weights=weights, edge_weights=w, generators=chains, holonomy=theta, admissible_holonomy=base,
        flatness_defect=flatness)


def _edge_weights(tb: TangentBundle, weights: str) -> np.ndarray:
    """W per canonical edge: ⋆₁ (cotangent weights, entries below half their median raised to it) or 1."""
    n1 = tb.mesh.complex.n_simplices(1)
    if weights == "uniform":
        return np.ones(n1)
    w = cotan_edge_weights(tb.geometry)
    floor = _FLOOR * float(np.median(w))
    return np.maximum(w, floor) if floor > 0 else np.ones(n1)


def _minimal(d0k, w, Dp, base, holonomy, X, gens, backend):
    """The minimal-W-norm δ for the particular solutions ``Dp`` (columns: faces, unit generators)."""
    q = Dp.shape[1] - 1
    L = (d0k.T @ sp.diags(w) @ d0k).tocsr()
    rhs = d0k.T @ (w[:, None] * Dp)
    fk = solve(L, sp.identity(L.shape[0], format="csr"), 0.0, rhs, backend=backend, positive_definite=True)
    D = Dp - d0k @ fk.reshape(-1, 1 + q)
    delta0, H = D[:, 0], D[:, 1:]
    if not q:
        if holonomy is not None and np.size(holonomy):
            raise InvalidParameterError(
                f"holonomy: the surface has no generators of H₁, got {np.size(holonomy)} angles")
        return delta0, np.zeros(0), L
    if holonomy is None:  # closest admissible value to the period of the face-only minimal correction
        theta_star = -np.linalg.solve(H.T @ (w[:, None] * H), H.T @ (w * delta0))
        theta = base + _TWO_PI * np.round((theta_star - base) / _TWO_PI)
    else:
        theta = _check_holonomy(holonomy, base, X, gens)
    return delta0 + H @ theta, theta, L


def _check_holonomy(holonomy, base: np.ndarray, X, gens: np.ndarray) -> np.ndarray:
    th = np.asarray(holonomy, dtype=np.float64).reshape(-1) if not isinstance(holonomy, str) else None
    if th is None or th.size != base.size:
        raise InvalidParameterError(f"holonomy must give one angle per generator of H₁ ({base.size}), got {holonomy!r}")
    if not np.all(np.isfinite(th)):
        raise InvalidParameterError("holonomy angles must be finite")
    m = (th - base) / _TWO_PI
    off = np.abs(m - np.round(m)) * _TWO_PI > 1e-8 * (1.0 + np.abs(th))
    if np.any(off):
        j = int(np.argmax(off))
        lo = base[j] + _TWO_PI * np.floor(m[j])
        raise InvalidParameterError(
            f"holonomy[{j}] = {th[j]:.12g} is not admissible around generator {j} (closed by edge "
            f"{simplex_name(X, 1, int(gens[j]))}): the field must close up, so it must be {base[j]:.12g} + 2πm, "
            f"e.g. {lo:.12g} or {lo + _TWO_PI:.12g}")
    return base + _TWO_PI * np.round(m)
