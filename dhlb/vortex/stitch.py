"""Vortex filaments of a partitioned mesh: pieces traced per part, keyed by global faces, stitched.

Under MPI every rank holds a patch of the tetrahedral mesh (its own tetrahedra and a halo around
them) with the section and the bundle on it. :func:`filament_pieces` traces the zero set through
the rank's own tetrahedra only (the same core as :func:`~dhlb.vortex.extract_filaments`): closed
loops that stay inside them, and chains that end where the filament leaves them (a *cut*: the
triangle's other tetrahedron belongs to another part) or on the boundary of the whole mesh.
Every crossing is named by the global vertex ids of its triangle (sorted) and its *slot* (which of
the ``|index|`` crossings of the triangle, almost always 0), so pieces of different ranks can be
matched. :func:`stitch_pieces` (on one rank) joins the pieces of all parts end to end at equal
crossings; the point on a triangle shared by two parts is computed from the same values on both
(ψ at its vertices, the connection on its edges, the curvature on it) and kept once.

With the vertex ids increasing along each patch's own vertex order (e.g. the patch's vertices in
increasing global order, or a patch complex built from global vertex ids), the stitched filaments
are those of :func:`~dhlb.vortex.extract_filaments` on the whole mesh: the same points in the same
order, loops starting at the same crossing, in the same order (by their smallest crossing), for any
number of parts.

Examples
--------
>>> import numpy as np
>>> from dhlb.bundles import HermitianLineBundle
>>> from dhlb.mesh import box_tet_mesh
>>> from dhlb.vortex import filament_pieces, stitch_pieces
>>> mesh = box_tet_mesh(4)
>>> L = HermitianLineBundle.trivial(mesh.complex)
>>> x, y, _ = mesh.points.T
>>> psi = (x - 0.3) + 1j * (y - 0.6)                  # zero set: the vertical line (0.3, 0.6, t)
>>> low = mesh.points[mesh.complex.simplices(3)].mean(axis=1)[:, 2] < 0.5    # two parts: z < 1/2, z > 1/2
>>> parts = [filament_pieces(L, psi, mesh.points, part) for part in (low, ~low)]
>>> [len(p) for p in parts], parts[0][0].ends                 # one chain per part
([1, 1], ('boundary', 'cut'))
>>> whole = stitch_pieces(parts)
>>> len(whole), whole[0].closed, whole[0].ends, len(whole[0]) == len(parts[0][0]) + len(parts[1][0]) - 1
(1, False, ('boundary', 'boundary'), True)
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from dhlb.errors import InvalidParameterError, ShapeError
from dhlb.vortex._face_zeros import _check_inputs
from dhlb.vortex.filaments import Filament, _trace

if TYPE_CHECKING:
    from collections.abc import Iterable

    from numpy.typing import ArrayLike

    from dhlb.bundles.hermitian import HermitianLineBundle

__all__ = ["FilamentPiece", "FilamentPieces", "filament_pieces", "stitch_pieces"]

_NO_IDS = np.zeros((0, 1), np.int64)


@dataclass(frozen=True, eq=False)
class FilamentPiece(Filament):
    """A filament, or the part of one inside a set of tetrahedra, with its crossings named globally.

    Made by :func:`filament_pieces` and :func:`stitch_pieces`; every parameter is kept as the
    attribute of the same name.

    Parameters
    ----------
    points : (m, 3) float array
        Points in order along the filament's direction (a loop does not repeat its first point).
    closed : bool
        True for a loop.
    faces : (m, 3) int64 array
        Global vertex ids (increasing) of the triangle of each point.
    slots : (m,) int64 array
        Which crossing of its triangle each point is, ``0 .. |index| - 1`` (0 unless the
        triangle is crossed more than once).
    ends : tuple of two str, or None
        For a chain, what its first and its last point lie on: ``"cut"`` (a triangle whose other
        tetrahedron is not traced: the filament goes on in another part) or ``"boundary"`` (the
        boundary of the whole mesh); None for a loop.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.vortex import FilamentPiece
    >>> p = FilamentPiece(np.zeros((2, 3)), False, np.array([[0, 1, 2], [1, 2, 3]]), np.zeros(2, np.int64),
    ...                   ("boundary", "cut"))
    >>> len(p), p.ends[1]
    (2, 'cut')
    """

    slots: np.ndarray
    ends: tuple | None


@dataclass(frozen=True, eq=False)
class FilamentPieces:
    """The filament pieces of one part, or the stitched filaments of all parts (a sequence of pieces).

    Made by :func:`filament_pieces` and :func:`stitch_pieces`; every parameter is kept as the
    attribute of the same name. The reports of :class:`~dhlb.vortex.FilamentSet`, named by global
    vertex ids (rows sorted; those of a stitched set are the union over the parts, without repeats):

    Parameters
    ----------
    pieces : tuple of FilamentPiece
        The pieces (stitched: the filaments).
    ambiguous_tets : (a, 4) int64 array, optional
        Traced tetrahedra crossed by more than one filament.
    tie_edges : (e, 2) int64 array, optional
        Edges of traced tetrahedra with rotation form ``π``.
    clamped_faces : (c, 3) int64 array, optional
        Crossed triangles of traced tetrahedra whose interpolated zero was clamped into the triangle.
    degenerate_faces : (d, 3) int64 array, optional
        Crossed triangles of traced tetrahedra whose transported values are collinear in C.

    Examples
    --------
    >>> from dhlb.vortex import FilamentPieces
    >>> FilamentPieces(())
    FilamentPieces(0 pieces: 0 closed, 0 cut ends; 0 ambiguous tets, 0 tie edges, 0 clamped faces)
    """

    pieces: tuple
    ambiguous_tets: np.ndarray = field(default_factory=lambda: np.zeros((0, 4), np.int64))
    tie_edges: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), np.int64))
    clamped_faces: np.ndarray = field(default_factory=lambda: np.zeros((0, 3), np.int64))
    degenerate_faces: np.ndarray = field(default_factory=lambda: np.zeros((0, 3), np.int64))

    def __len__(self) -> int:
        return len(self.pieces)

    def __iter__(self):
        return iter(self.pieces)

    def __getitem__(self, i) -> FilamentPiece:
        return self.pieces[i]

    def __repr__(self) -> str:
        n_closed = sum(p.closed for p in self.pieces)
        n_cut = sum(p.ends.count("cut") for p in self.pieces if p.ends)
        return (f"FilamentPieces({len(self)} pieces: {n_closed} closed, {n_cut} cut ends; "
                f"{len(self.ambiguous_tets)} ambiguous tets, {len(self.tie_edges)} tie edges, "
                f"{len(self.clamped_faces)} clamped faces)")


def _rows(arg, n: int, what: str, name: str) -> np.ndarray:
    """Rows ``0 .. n-1`` from a bool mask of length n or an integer array (sorted, unique)."""
    a = np.asarray(arg)
    if a.dtype == bool:
        if a.shape != (n,):
            raise ShapeError(f"{name} as a mask needs one bool per {what}, shape ({n},); got {a.shape}")
        return np.nonzero(a)[0]
    if a.ndim != 1 or (a.size and not np.issubdtype(a.dtype, np.integer)):
        raise ShapeError(f"{name} must be a bool mask or a 1-D array of row numbers of {what}s, got {a.dtype} "
                         f"array of shape {a.shape}")
    if a.size and (a.min() < 0 or a.max() >= n):
        raise InvalidParameterError(f"{name} must be rows 0..{n - 1} of the {what}s, got {int(a.min())}.."
                                    f"{int(a.max())}")
    return np.unique(a.astype(np.int64))


def filament_pieces(
    bundle: HermitianLineBundle,
    section: ArrayLike,
    points: ArrayLike,
    tets: ArrayLike | None = None,
    *,
    vertex_ids: ArrayLike | None = None,
    boundary: ArrayLike | None = None,
    placement: str = "balanced",
) -> FilamentPieces:
    """The pieces of the filaments inside a set of tetrahedra, named by global vertex ids; see the module docstring.

    Traced exactly as :func:`~dhlb.vortex.extract_filaments` (same crossings, points, links and
    checks), but only through ``tets``: a chain ends where the filament leaves them.

    Parameters
    ----------
    bundle : HermitianLineBundle
        Over the 3-complex of the local patch (the traced tetrahedra and their neighbours).
    section : (N,) complex array
        One value per vertex (in the frames of the bundle), nowhere zero.
    points : (N, 3) float array
        Vertex positions (compact vertex order of ``bundle.X``).
    tets : (n_3,) bool array or (k,) int array, optional
        The tetrahedra to trace through, as a mask or rows of ``bundle.X.simplices(3)`` (default: all).
    vertex_ids : (N,) int array, optional
        Global id of each vertex, strictly increasing (default: ``bundle.X.vertex_labels``, right
        for a patch complex built from global vertex ids).
    boundary : (n_2,) bool array, optional
        The triangles on the boundary of the whole mesh (default: those in at most one tetrahedron of
        ``bundle.X``). Needed only when the patch lacks a tetrahedron across some triangle of
        ``tets`` (e.g. a halo of one layer of tetrahedra around the rank's vertices): the end there is
        then a cut, which :func:`stitch_pieces` insists on matching.
    placement : {"balanced", "vertex"}, optional
        Local gauge in which the point on a crossed triangle is interpolated (:func:`~dhlb.vortex.face_zeros`).

    Returns
    -------
    FilamentPieces
        The loops inside ``tets`` and the chains through them, with the reports of ``tets``
        (tie edges and clamped or degenerate triangles on faces shared with other parts are
        reported by each part; :func:`stitch_pieces` removes the repeats).

    Raises
    ------
    ShapeError, InvalidParameterError
        ``tets``, ``vertex_ids`` or ``boundary`` do not fit the complex, or ``vertex_ids`` do not
        increase; and as :func:`~dhlb.vortex.extract_filaments`.
    SectionZeroError, NonFiniteError, NonManifoldError, InconsistentOrientationError, DegenerateSimplexError
        As :func:`~dhlb.vortex.extract_filaments`.
    CurvatureMismatchError
        The index fluxes of a traced tetrahedron do not sum to zero.

    Warns
    -----
    DhlbWarning
        Some traced tetrahedra are crossed more than once (``ambiguous_tets``).

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.bundles import HermitianLineBundle
    >>> from dhlb.mesh import box_tet_mesh
    >>> from dhlb.vortex import filament_pieces
    >>> mesh = box_tet_mesh(4)
    >>> L = HermitianLineBundle.trivial(mesh.complex)
    >>> x, y, _ = mesh.points.T
    >>> top = mesh.points[mesh.complex.simplices(3)].mean(axis=1)[:, 2] > 0.5
    >>> pieces = filament_pieces(L, (x - 0.3) + 1j * (y - 0.6), mesh.points, top)
    >>> p = pieces[0]
    >>> len(pieces), p.ends, bool(np.all(p.points[:, 2] >= 0.5))
    (1, ('cut', 'boundary'), True)
    >>> mesh.points[p.faces[0], 2].tolist()              # it enters through a triangle in the plane z = 1/2
    [0.5, 0.5, 0.5]
    """
    X, P, z = _check_inputs(bundle, section, points)
    tet_rows = None if tets is None else _rows(tets, X.n_simplices(3), "tetrahedron", "tets")
    vid = X.vertex_labels if vertex_ids is None else np.asarray(vertex_ids)
    if vid.shape != (X.n_vertices,) or not np.issubdtype(vid.dtype, np.integer):
        raise ShapeError(f"vertex_ids must be one integer per vertex, shape ({X.n_vertices},); got {vid.dtype} "
                         f"array of shape {vid.shape}")
    vid = vid.astype(np.int64)
    if np.any(np.diff(vid) <= 0):
        i = int(np.argmax(np.diff(vid) <= 0))
        raise InvalidParameterError(f"vertex_ids must increase along the vertex order (so that a simplex is sorted "
                                    f"alike locally and globally); vertex {i + 1} has id {int(vid[i + 1])} after "
                                    f"{int(vid[i])}")
    F3 = X.faces(3)
    if boundary is None:
        on_boundary = np.bincount(F3.ravel(), minlength=X.n_simplices(2)) <= 1
    else:
        on_boundary = np.asarray(boundary)
        if on_boundary.shape != (X.n_simplices(2),) or on_boundary.dtype != bool:
            raise ShapeError(f"boundary must be one bool per triangle, shape ({X.n_simplices(2)},); got "
                             f"{on_boundary.dtype} array of shape {on_boundary.shape}")
    tr = _trace(bundle, z, P, tet_rows, placement)
    F2 = vid[X.simplices(2)]
    kind = np.where(on_boundary, "boundary", "cut")
    pieces = []
    for nodes, closed in tr.chains():
        f = tr.node_face[nodes]
        ends = None if closed else (str(kind[f[0]]), str(kind[f[-1]]))
        pieces.append(FilamentPiece(tr.positions[nodes], closed, F2[f], tr.node_slot[nodes], ends))
    edges = np.nonzero(tr.tie)[0]
    if tet_rows is not None:
        edges = np.intersect1d(edges, X.faces(2)[F3[tet_rows]].ravel())
    return FilamentPieces(tuple(pieces), vid[X.simplices(3)[tr.ambiguous]], vid[X.simplices(1)[edges]],
                          F2[tr.crossed[tr.clamped]], F2[tr.crossed[tr.degenerate]])


def _unique_rows(blocks, width: int) -> np.ndarray:
    a = np.concatenate([np.asarray(b, np.int64).reshape(-1, width) for b in blocks] + [np.zeros((0, width), np.int64)])
    return np.unique(a, axis=0)


def stitch_pieces(parts: Iterable[FilamentPieces]) -> FilamentPieces:
    """Join the filament pieces of all parts end to end at equal crossings; see the module docstring.

    Parameters
    ----------
    parts : iterable of FilamentPieces
        The pieces of every part (:func:`filament_pieces` on tetrahedra that partition the mesh).

    Returns
    -------
    FilamentPieces
        The filaments (loops, and chains whose ends are both ``"boundary"``), each loop starting at
        its smallest crossing ``(face, slot)``, ordered by their smallest crossing; and the reports of
        all parts without repeats.

    Raises
    ------
    InvalidParameterError
        A cut end that no piece continues, or two pieces that start (or end) at the same crossing:
        a part's pieces are missing, or the parts disagree on the data of a shared triangle; the
        message names the triangle by its global vertex ids.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.vortex import FilamentPiece, FilamentPieces, stitch_pieces
    >>> f = np.array([[0, 1, 2], [1, 2, 3], [2, 3, 4]])
    >>> a = FilamentPiece(np.eye(3)[:2], False, f[:2], np.zeros(2, np.int64), ("boundary", "cut"))
    >>> b = FilamentPiece(np.eye(3)[1:], False, f[1:], np.zeros(2, np.int64), ("cut", "boundary"))
    >>> whole = stitch_pieces([FilamentPieces((b,)), FilamentPieces((a,))])
    >>> len(whole), whole[0].points.tolist(), whole[0].ends
    (1, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], ('boundary', 'boundary'))
    >>> try:
    ...     stitch_pieces([FilamentPieces((a,))])
    ... except InvalidParameterError as err:
    ...     print(str(err)[:62])
    no piece continues the filament through the triangle (1, 2, 3)
    """
    parts = list(parts)
    pieces = [p for part in parts for p in part.pieces]
    key = lambda p, i: (*(int(v) for v in p.faces[i]), int(p.slots[i]))  # noqa: E731
    heads, tails = {}, {}
    for n, p in enumerate(pieces):
        if p.closed:
            continue
        for ends, k in ((heads, key(p, 0)), (tails, key(p, -1))):
            if k in ends:
                raise InvalidParameterError(f"two pieces {'start' if ends is heads else 'end'} at the crossing "
                                            f"{k[3]} of the triangle {k[:3]}: the parts overlap or disagree there")
            ends[k] = n
    for p in pieces:  # every cut end must be continued
        if p.closed:
            continue
        for end, k, other in ((0, key(p, 0), tails), (1, key(p, -1), heads)):
            if p.ends[end] == "cut" and k not in other:
                raise InvalidParameterError(
                    f"no piece continues the filament through the triangle {k[:3]} (crossing {k[3]}) where a piece "
                    f"{'starts' if end == 0 else 'ends'} at a cut: a part's pieces are missing, or the parts disagree "
                    "on ψ or the bundle there")
    nxt = {n: heads.get(key(p, -1), -1) for n, p in enumerate(pieces) if not p.closed}
    first = [n for n, p in enumerate(pieces) if not p.closed and key(p, 0) not in tails]
    done = np.zeros(len(pieces), bool)
    out = []
    for n0, closed in [(n, False) for n in first] + [(n, True) for n in range(len(pieces))]:
        if done[n0]:
            continue
        run, n = [], n0
        while n >= 0 and not done[n]:
            done[n] = True
            run.append(pieces[n])
            n = -1 if pieces[n].closed else nxt[n]
        closed = closed and (pieces[n0].closed or n == n0)
        out.append(_join(run, closed))
    out.sort(key=lambda p: _first_crossing(p)[0])
    return FilamentPieces(tuple(out), *(_unique_rows([getattr(part, name) for part in parts], w) for name, w in
                                        (("ambiguous_tets", 4), ("tie_edges", 2), ("clamped_faces", 3),
                                         ("degenerate_faces", 3))))


def _first_crossing(p: FilamentPiece):
    """``(key, position)`` of the smallest crossing ``(face ids, slot)`` of a piece."""
    i = int(np.lexsort((p.slots, *p.faces.T[::-1]))[0])
    return (*(int(v) for v in p.faces[i]), int(p.slots[i])), i


def _join(run: list, closed: bool) -> FilamentPiece:
    """One filament from consecutive pieces (each ends at the crossing where the next starts)."""
    if len(run) == 1 and run[0].closed:
        return run[0]
    cut = slice(None, -1) if closed else slice(None)  # a loop: the last crossing is the first one
    pts = np.concatenate([p.points[1:] if i else p.points for i, p in enumerate(run)])[cut]
    faces = np.concatenate([p.faces[1:] if i else p.faces for i, p in enumerate(run)])[cut]
    slots = np.concatenate([p.slots[1:] if i else p.slots for i, p in enumerate(run)])[cut]
    if closed:  # start at the smallest crossing, as extract_filaments does
        _, i = _first_crossing(FilamentPiece(pts, True, faces, slots, None))
        pts, faces, slots = (np.roll(a, -i, axis=0) for a in (pts, faces, slots))
        return FilamentPiece(pts, True, faces, slots, None)
    return FilamentPiece(pts, False, faces, slots, (run[0].ends[0], run[-1].ends[1]))
