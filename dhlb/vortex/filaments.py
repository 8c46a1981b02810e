"""Vortex filaments: the zero set of a section of a hermitian line bundle over a tetrahedral mesh.

Given a section ``ψ_i = z_i X_i`` of a :class:`~dhlb.bundles.HermitianLineBundle` over a
tetrahedral mesh with vertex positions, the filament (the zero set of ψ) is traced as follows.

1. **Crossed faces.**  The index form ``ind = (dξ + Ω)/2π`` (:func:`dhlb.bundles.index_form`) is an
   integer per canonically oriented triangle: the number of zeros of ψ inside it, counted with
   the sign of the crossing.  A filament crosses triangle ``t`` along its right-hand normal
   (``(p_j − p_i) × (p_k − p_i)`` for ``i < j < k``) when ``ind_t = +1``, against it for ``−1``.
2. **Through tetrahedra.**  For a tetrahedron with canonical orientation sign ``s = ±1`` (the sign
   of its signed volume) the outward flux through the face omitting vertex ``a`` is
   ``s (−1)^a ind(face_a)``.  The fluxes of a tetrahedron sum to ``(dΩ)/2π = 0``; generically one
   face has flux ``−1`` (the filament enters) and one ``+1`` (it leaves).  A tetrahedron with more
   crossings (two filaments through it, or a face with ``|ind| >= 2``) is *ambiguous*: entries are
   paired with exits to minimize the total distance, and the tetrahedron is reported.
3. **Chains.**  Linking "entry face → exit face" in every tetrahedron gives a graph in which every
   crossed face has at most one successor and one predecessor, so it splits into closed loops
   and chains that start and end on boundary faces.  They are ordered by pointer jumping
   (vectorized list ranking), not by walking.
4. **Points.**  On each crossed face ``(i < j < k)`` the point is the zero of the linear
   interpolant of the section written in a local gauge of the face: its barycentric coordinates
   are those of ``0`` in the triangle ``w_i w_j w_k`` of the complex plane,
   ``λ_i : λ_j : λ_k = Im(w̄_j w_k) : Im(w̄_k w_i) : Im(w̄_i w_j)``.  The brief's gauge
   (``placement="vertex"``) transports to vertex ``i``: ``w = (z_i, conj(r_ij) z_j, conj(r_ik) z_k)``.
   The default (``placement="balanced"``) spreads the curvature evenly over the three edges,
   ``w = (|z_i|, |z_j| e^{iξ'_ij}, |z_k| e^{i(ξ'_ij + ξ'_jk)})`` with ``ξ' = ξ + Ω/3``; since
   ``ξ'_ij + ξ'_jk + ξ'_ki = 2π ind``, the zero then lies in the face whenever all ``|ξ'| < π``,
   consistently with the index form.  Both are gauge invariant and agree for a flat connection.
   A zero that still falls outside its face is clamped to it and the face is reported
   (``clamped_faces``; with the balanced gauge this happens only if some ``|ξ'| >= π``, i.e. the
   curvature per face is large: refine the mesh or increase ħ).

Degenerate input is reported rather than guessed: ψ = 0 at a vertex raises
:class:`~dhlb.errors.SectionZeroError` naming it; edges with a tie ``η_ij(ψ_i) = −ψ_j`` (the
zero lies on the edge; the tie rule of ``docs/conventions.md`` assigns it to one side) are listed
in ``tie_edges``.

Examples
--------
>>> import numpy as np
>>> from dhlb.bundles import HermitianLineBundle
>>> from dhlb.mesh import box_tet_mesh
>>> mesh = box_tet_mesh(4)
>>> L = HermitianLineBundle.trivial(mesh.complex)
>>> x, y, _ = mesh.points.T
>>> res = extract_filaments(L, (x - 0.3) + 1j * (y - 0.6), mesh.points)
>>> len(res), res[0].closed
(1, False)
>>> bool(np.allclose(res[0].points[:, :2], [0.3, 0.6])), bool(np.all(np.diff(res[0].points[:, 2]) > 0))
(True, True)
"""

from __future__ import annotations

import itertools
import warnings
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from dhlb.errors import (
    CurvatureMismatchError,
    DhlbWarning,
    InvalidParameterError,
)
from dhlb.mesh.tet import check_tet_complex
from dhlb.vortex._face_zeros import _check_inputs, face_zeros

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from dhlb.bundles.hermitian import HermitianLineBundle

__all__ = ["Filament", "FilamentSet", "extract_filaments", "face_zeros"]



@dataclass(frozen=True, eq=False)
class Filament:
    """One filament: a closed loop or a chain from boundary to boundary.

    Made by :func:`extract_filaments`; every parameter is kept as the attribute of the same name.

    Parameters
    ----------
    points : (m, 3) float array
        Points in order along the filament's direction (closed loops do not repeat the first point).
    closed : bool
        True for a loop (the last point connects to the first).
    faces : (m,) int array
        Row in ``X.simplices(2)`` of the triangle each point lies on.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import box_tet_mesh
    >>> from dhlb.vortex import extract_filaments, uniform_flow, velocity_bundle
    >>> mesh = box_tet_mesh(4, lower=-1, upper=1)
    >>> L = velocity_bundle(mesh.complex, mesh.points, uniform_flow([0.0, 0.0, 0.0]), 1.0)   # trivial bundle
    >>> x, y, _ = mesh.points.T
    >>> psi = (x - 0.1) + 1j * (y - 0.2)                  # zero set: the vertical line (0.1, 0.2, t)
    >>> fil = extract_filaments(L, psi, mesh.points)[0]
    >>> fil.closed, round(fil.length, 6), bool(np.allclose(fil.points[:, :2], [0.1, 0.2]))
    (False, 2.0, True)
    """

    points: np.ndarray
    closed: bool
    faces: np.ndarray

    def __len__(self) -> int:
        return self.points.shape[0]

    @property
    def length(self) -> float:
        """Length of the polyline (including the closing segment of a loop)."""
        P = np.concatenate([self.points, self.points[:1]]) if self.closed else self.points
        return float(np.linalg.norm(np.diff(P, axis=0), axis=1).sum())


@dataclass(frozen=True, eq=False)
class FilamentSet:
    """The filaments of a section and what was found along the way (a sequence of :class:`Filament`).

    Made by :func:`extract_filaments`; every parameter is kept as the attribute of the same name.

    Parameters
    ----------
    filaments : tuple of Filament
        The filaments.
    index : (n_2,) int array
        The index form of the section (one integer per triangle).
    ambiguous_tets : (a,) int array, optional
        Rows in ``X.simplices(3)`` of tetrahedra crossed by more than one filament (or with a face
        of ``|index| >= 2``): the pairing of entries and exits there is a guess (refine the mesh).
    tie_edges : (e,) int array, optional
        Rows in ``X.simplices(1)`` of edges with ``η_ij(ψ_i) = −ψ_j`` exactly (rotation form ``π``).
    clamped_faces : (c,) int array, optional
        Crossed triangles whose interpolated zero fell outside the triangle and was clamped.
    degenerate_faces : (d,) int array, optional
        Crossed triangles whose transported values are collinear in C (point put at the centroid).

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import box_tet_mesh
    >>> from dhlb.vortex import extract_filaments, uniform_flow, velocity_bundle
    >>> mesh = box_tet_mesh(4, lower=-1, upper=1)
    >>> L = velocity_bundle(mesh.complex, mesh.points, uniform_flow([0.0, 0.0, 0.0]), 1.0)   # trivial bundle
    >>> x, y, _ = mesh.points.T
    >>> psi = (x - 0.1) + 1j * (y - 0.2)                  # zero set: the vertical line (0.1, 0.2, t)
    >>> fs = extract_filaments(L, psi, mesh.points)
    >>> len(fs), int(np.abs(fs.index).sum()), fs.ambiguous_tets.size, fs.clamped_faces.size
    (1, 13, 0, 0)
    """

    filaments: tuple
    index: np.ndarray
    ambiguous_tets: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    tie_edges: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    clamped_faces: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    degenerate_faces: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))

    def __len__(self) -> int:
        return len(self.filaments)

    def __iter__(self):
        return iter(self.filaments)

    def __getitem__(self, i) -> Filament:
        return self.filaments[i]

    def __repr__(self) -> str:
        n_closed = sum(f.closed for f in self.filaments)
        return (f"FilamentSet({len(self)} filaments: {n_closed} closed, {len(self) - n_closed} open; "
                f"{self.ambiguous_tets.size} ambiguous tets, {self.tie_edges.size} tie edges, "
                f"{self.clamped_faces.size} clamped faces)")


# ---------------------------------------------------------------------------- chains
def _pair_ambiguous(flux_t, faces_t, start, face_pos):
    """(entry node, exit node) pairs in one tetrahedron, matching entries to exits by distance."""
    ins, outs = [], []
    for a in range(4):
        f, k = int(faces_t[a]), int(flux_t[a])
        slots = [(start[f] + c, face_pos[f]) for c in range(abs(k))]
        (outs if k > 0 else ins).extend(slots)
    if len(ins) <= 4:
        best = min(itertools.permutations(range(len(outs))),
                   key=lambda perm: sum(np.linalg.norm(ins[i][1] - outs[j][1]) for i, j in enumerate(perm)))
    else:  # greedy
        best, free = [], list(range(len(outs)))
        for i in range(len(ins)):
            j = min(free, key=lambda j: np.linalg.norm(ins[i][1] - outs[j][1]))
            free.remove(j)
            best.append(j)
    return [(ins[i][0], outs[j][0]) for i, j in enumerate(best)]


def _order_chains(succ: np.ndarray):
    """Split the successor graph into chains/cycles and order each by list ranking.

    Returns ``(order, labels, closed)``: nodes sorted by component then position, each node's
    component, and per component whether it is a cycle.
    """
    n = succ.size
    has = succ >= 0
    src = np.nonzero(has)[0]
    g = sp.csr_matrix((np.ones(src.size), (src, succ[has])), shape=(n, n))
    ncomp, lab = connected_components(g, directed=True, connection="weak")
    pred = np.full(n, -1, np.int64)
    pred[succ[has]] = src
    comp_has_head = np.zeros(ncomp, bool)
    comp_has_head[lab[pred < 0]] = True
    closed = ~comp_has_head
    first = np.full(ncomp, n, np.int64)
    np.minimum.at(first, lab, np.arange(n))
    cut = succ.copy()
    cyc_heads = first[closed]
    cut[pred[cyc_heads]] = -1  # open every cycle just before its smallest node
    rank = (cut >= 0).astype(np.int64)  # steps to the end of the chain, by pointer jumping
    nxt = cut.copy()
    act = nxt >= 0
    while np.any(act):
        idx = np.nonzero(act)[0]
        rank[idx] += rank[nxt[idx]]
        nxt[idx] = nxt[nxt[idx]]
        act = nxt >= 0
    order = np.lexsort((-rank, lab))
    return order, lab, closed


def extract_filaments(
    bundle: HermitianLineBundle, section: ArrayLike, points: ArrayLike, *, placement: str = "balanced"
) -> FilamentSet:
    """The filaments (zero set) of a section over a tetrahedral mesh; see the module docstring.

    Parameters
    ----------
    bundle : HermitianLineBundle
        Over a 3-complex in which every triangle lies in at most two tetrahedra.
    section : (N,) complex array
        One value per vertex (in the frames of the bundle), nowhere zero.
    points : (N, 3) float array
        Vertex positions (compact vertex order of ``bundle.X``).
    placement : {"balanced", "vertex"}, optional
        Local gauge in which the point on a crossed triangle is interpolated (:func:`face_zeros`).

    Returns
    -------
    FilamentSet
        The filaments, the index form and the reported tetrahedra, edges and faces.

    Raises
    ------
    InvalidParameterError
        ``bundle`` is not a hermitian line bundle, or ``placement`` is not one of the values above.
    SectionZeroError
        ψ vanishes at a vertex (named, with its position).
    ShapeError, NonFiniteError
        Wrong shapes or NaN/inf in the section or the positions.
    NonManifoldError
        Not a 3-complex, or a crossed triangle lies in three or more tetrahedra (named).
    InconsistentOrientationError
        Two tetrahedra on the same side of a crossed triangle (a folded mesh; named).
    DegenerateSimplexError
        A tetrahedron of zero volume (named).
    CurvatureMismatchError
        The index fluxes of a tetrahedron do not sum to zero (the bundle's curvature is not closed).

    Warns
    -----
    DhlbWarning
        Some tetrahedra are crossed more than once (``ambiguous_tets``).

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import box_tet_mesh
    >>> from dhlb.vortex import extract_filaments, uniform_flow, velocity_bundle
    >>> mesh = box_tet_mesh(4, lower=-1, upper=1)
    >>> L = velocity_bundle(mesh.complex, mesh.points, uniform_flow([0.0, 0.0, 0.0]), 1.0)   # trivial bundle
    >>> x, y, _ = mesh.points.T
    >>> psi = (x - 0.1) + 1j * (y - 0.2)                  # zero set: the vertical line (0.1, 0.2, t)
    >>> fs = extract_filaments(L, psi, mesh.points)
    >>> len(fs), fs[0].closed, fs[0].points[[0, -1], 2].round(6).tolist()    # from boundary to boundary
    (1, False, [-1.0, 1.0])
    """
    _, P, z = _check_inputs(bundle, section, points)
    tr = _trace(bundle, z, P, None, placement)
    ties = np.nonzero(tr.tie)[0]
    fils = [Filament(tr.positions[nodes], closed, tr.node_face[nodes]) for nodes, closed in tr.chains()]
    return FilamentSet(tuple(fils), tr.index, tr.ambiguous, ties, tr.crossed[tr.clamped], tr.crossed[tr.degenerate])


@dataclass(frozen=True, eq=False)
class _Trace:
    """The crossings of the zero set through a set of tetrahedra and how they link (see :func:`_trace`)."""

    index: np.ndarray      # (n_2,) the index form
    tie: np.ndarray        # (n_1,) bool: rotation form π
    crossed: np.ndarray    # (c,) crossed triangles (rows of X.simplices(2)) of the traced tetrahedra
    clamped: np.ndarray    # (c,) bool, from face_zeros
    degenerate: np.ndarray  # (c,) bool, from face_zeros
    node_face: np.ndarray  # (n,) triangle of each crossing (a triangle of index ±k carries k crossings)
    node_slot: np.ndarray  # (n,) which of the |index| crossings of its triangle, 0 .. |index| - 1
    positions: np.ndarray  # (n, 3) point of each crossing
    succ: np.ndarray       # (n,) the next crossing along the filament inside the traced tetrahedra, or -1
    ambiguous: np.ndarray  # (a,) traced tetrahedra (rows of X.simplices(3)) crossed more than once

    def chains(self):
        """``(nodes, closed)`` per chain or loop, in order along the filament (:func:`_order_chains`)."""
        if self.succ.size == 0:
            return []
        order, lab, closed = _order_chains(self.succ)
        cuts = np.nonzero(np.diff(lab[order]))[0] + 1
        return [(nodes, bool(closed[lab[nodes[0]]])) for nodes in np.split(order, cuts)]


def _trace(bundle, z, P, tets, placement: str) -> _Trace:
    """Crossed triangles, their points, and the links "entry → exit" through the tetrahedra ``tets``.

    ``tets`` are rows of ``X.simplices(3)`` (None: all, and then every crossed triangle is a node,
    also one that lies in no tetrahedron); the caller has checked the inputs with :func:`_check_inputs`.
    """
    from dhlb.bundles.index import index_form, rotation_form

    X = bundle.X
    if placement not in ("balanced", "vertex"):
        raise InvalidParameterError(f"placement must be 'balanced' or 'vertex', got {placement!r}")
    ind = index_form(bundle, z)
    tie = rotation_form(bundle, z) == np.pi
    rows = np.arange(X.n_simplices(3)) if tets is None else tets
    F3 = X.faces(3)[rows]
    crossed = np.nonzero(ind)[0] if tets is None else np.unique(F3[ind[F3] != 0])
    flux = check_tet_complex(X, P, crossed)[rows][:, None] * np.array([1, -1, 1, -1]) * ind[F3]
    bad = flux.sum(axis=1) != 0
    if np.any(bad):
        t = int(np.argmax(bad))
        tet = tuple(int(v) for v in X.vertex_labels[X.simplices(3)[rows[t]]])
        raise CurvatureMismatchError(f"the index fluxes of the tetrahedron {tet} sum to {int(flux[t].sum())}, "
                                     "not 0: the bundle's curvature is not closed there")
    n2 = X.n_simplices(2)
    pos, _, clamped, degenerate = face_zeros(bundle, z, P, crossed, placement=placement)
    mult = np.abs(ind[crossed])
    start = np.full(n2, -1, np.int64)
    start[crossed] = np.cumsum(mult) - mult
    face_pos = np.zeros((n2, 3))
    face_pos[crossed] = pos
    node_face = np.repeat(crossed, mult)
    succ = np.full(node_face.size, -1, np.int64)
    k_out = np.where(flux > 0, flux, 0).sum(axis=1)
    simple = np.nonzero(k_out == 1)[0]
    fin = F3[simple, np.argmin(flux[simple], axis=1)]
    fout = F3[simple, np.argmax(flux[simple], axis=1)]
    succ[start[fin]] = start[fout]
    amb = np.nonzero(k_out >= 2)[0]
    for t in amb:  # rare: only tetrahedra crossed more than once
        for a, b in _pair_ambiguous(flux[t], F3[t], start, face_pos):
            succ[a] = b
    if amb.size:
        warnings.warn(f"{amb.size} tetrahedra are crossed by more than one filament; entries and exits were paired "
                      "by distance there (see FilamentSet.ambiguous_tets); refine the mesh to resolve them",
                      DhlbWarning, stacklevel=3)
    node_slot = np.arange(node_face.size) - start[node_face]
    return _Trace(ind, tie, crossed, clamped, degenerate, node_face, node_slot, face_pos[node_face], succ,
                  rows[amb].astype(np.int64))
