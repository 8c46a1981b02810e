"""Validated, oriented triangle surface meshes for the direction-field application.

:func:`validate_surface` turns arrays ``(V, F)`` into a :class:`SurfaceMesh`: an oriented
2-manifold triangle mesh, possibly with boundary and several components, whose vertices are
compacted (unreferenced input rows dropped with a warning) and whose faces keep the row order
(the orientation) of the input, or a consistent re-orientation of it (``reorient=True``).

Numbering: errors and warnings name vertices by their **input row in V** and faces by their
**input row in F**. Inside a :class:`SurfaceMesh` vertices are compact (``0 .. N-1``, increasing
input rows, ``mesh.vertex_labels[v]`` is the input row of vertex ``v``) and face ``f`` is input
row ``mesh.face_rows[f]``. The complex ``mesh.complex`` is built from the input labels, so the
layers below (topology, bundles) also name simplices in input vertex numbers.

Checks, in this order (geometric checks after ``components="largest"`` dropped faces): shapes
and integer indices; a face repeating a vertex
(:class:`~dhlb.errors.DegenerateSimplexError`); duplicate faces, in either orientation
(:class:`~dhlb.errors.InvalidSimplexError`); NaN/inf coordinates of used vertices
(:class:`~dhlb.errors.NonFiniteError`); zero-area faces (DegenerateSimplexError, the criterion of
:class:`dhlb.geometry.SimplexStack`); edges with three or more faces and vertices whose faces do
not form one fan (:class:`~dhlb.errors.NonManifoldError`); non-orientable surfaces such as a
Möbius band (:class:`~dhlb.errors.NonOrientableError`; direction fields on non-orientable
surfaces need a twisted bundle and are future work); faces of an orientable surface that are not
consistently oriented (:class:`~dhlb.errors.InconsistentOrientationError`, or flipped with
``reorient=True``).

Several connected components are allowed (``components="all"``): every per-vertex and per-face
quantity is local, the Euler characteristic and degrees add up over components. With
``components="largest"`` only the component with most faces is kept (a warning says how many
faces were dropped).
"""

from __future__ import annotations

import warnings
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np

from dhlb.errors import (
    DegenerateSimplexError,
    DhlbWarning,
    EmptyComplexError,
    InconsistentOrientationError,
    InvalidParameterError,
    InvalidSimplexError,
    NonFiniteError,
    NonManifoldError,
    NonOrientableError,
    ShapeError,
    UnreferencedVertexWarning,
)
from dhlb.geometry.simplex import SimplexStack
from dhlb.topology.complex import SimplicialComplex
from dhlb.topology.manifold import interior_pairs, is_consistently_oriented, manifold_report

if TYPE_CHECKING:
    from typing import Any

    from numpy.typing import ArrayLike

__all__ = ["SurfaceMesh", "validate_surface"]


def _face(F, r) -> str:
    return f"face {int(r)} (vertices {', '.join(str(int(v)) for v in F[r])})"


def _parse(V, F) -> tuple[np.ndarray, np.ndarray]:
    try:
        P = np.asarray(V, dtype=np.float64)
    except (TypeError, ValueError):
        raise ShapeError("V must be a numeric array of shape (n, 3) (or (n, 2) for a planar mesh)") from None
    if P.ndim != 2 or P.shape[1] not in (2, 3):
        raise ShapeError(f"V must have shape (n, 3) (or (n, 2) for a planar mesh), got {P.shape}")
    if P.shape[1] == 2:
        P = np.column_stack([P, np.zeros(len(P))])
    T = np.asarray(F)
    if T.dtype == object or not (np.issubdtype(T.dtype, np.integer) or np.issubdtype(T.dtype, np.floating)):
        raise InvalidSimplexError(f"F must be an integer array of shape (m, 3), got dtype {T.dtype}")
    if T.ndim != 2 or T.shape[1] != 3:
        raise InvalidSimplexError(f"F must have shape (m, 3) (one triangle per row), got {T.shape}")
    if T.shape[0] == 0:
        raise EmptyComplexError("F has no faces; a surface mesh needs at least one triangle")
    if np.issubdtype(T.dtype, np.floating):
        bad = ~np.isfinite(T).all(axis=1) | np.any(T != np.round(T), axis=1)
        if np.any(bad):
            r = int(np.argmax(bad))
            raise InvalidSimplexError(f"face {r} has non-integer vertex indices {T[r].tolist()}")
    T = T.astype(np.int64)
    bad = np.any((T < 0) | (T >= len(P)), axis=1)
    if np.any(bad):
        r = int(np.argmax(bad))
        raise InvalidSimplexError(f"{_face(T, r)} refers to a vertex outside V (rows 0 .. {len(P) - 1})")
    return P, T


def _check_faces(P, T) -> None:
    srt = np.sort(T, axis=1)
    rep = np.any(srt[:, 1:] == srt[:, :-1], axis=1)
    if np.any(rep):
        r = int(np.argmax(rep))
        raise DegenerateSimplexError(f"{_face(T, r)} repeats a vertex; remove it (it has zero area)")
    _, first, inv = np.unique(srt, axis=0, return_index=True, return_inverse=True)
    dup = np.nonzero(first[inv.ravel()] != np.arange(len(T)))[0]
    if dup.size:
        r2 = int(dup[0])
        r1 = int(first[inv.ravel()[r2]])
        same = SimplicialComplex.orientation_of(T[[r1, r2]])
        how = "with the same orientation" if same[0] == same[1] else "with opposite orientations (a doubled sheet)"
        raise InvalidSimplexError(f"faces {r1} and {r2} are the same triangle {tuple(int(v) for v in srt[r2])} "
                                  f"{how}; remove one of them")


def _check_geometry(P, T, rows) -> None:
    used = np.unique(T)
    bad = ~np.isfinite(P[used]).all(axis=1)
    if np.any(bad):
        v = int(used[np.argmax(bad)])
        raise NonFiniteError(f"vertex {v} has a NaN or infinite coordinate {P[v].tolist()} "
                             f"({int(bad.sum())} used vertices affected); give finite coordinates")
    st = SimplexStack.from_points(P[T])
    deg = np.nonzero(~st.positive_definite)[0]
    if deg.size:
        r = int(deg[0])
        raise DegenerateSimplexError(
            f"{deg.size} face(s) have zero area, first face {int(rows[r])} (vertices "
            f"{', '.join(str(int(v)) for v in T[r])}) with area {st.volumes[r]:.3g}; "
            "remove or repair them (collinear vertices)")


def _check_manifold(X, T, rows) -> None:
    _, _, _, counts = interior_pairs(X)
    if np.any(counts > 2):
        e = int(np.argmax(counts > 2))
        a, b = (int(v) for v in X.vertex_labels[X.simplices(1)[e]])
        at = rows[np.isin(T, [a]).any(axis=1) & np.isin(T, [b]).any(axis=1)]
        raise NonManifoldError(f"non-manifold edge ({a}, {b}): it lies in {int(counts[e])} faces "
                               f"(rows {', '.join(str(int(r)) for r in at[:6])}); a surface allows at most 2. "
                               "Split or remove faces there")
    rep = manifold_report(X, limit=1)
    if not rep.is_manifold:
        o = rep.first()
        if o.k == 0:
            v = o.simplex[0]
            raise NonManifoldError(f"non-manifold vertex {v}: its faces form more than one fan (e.g. two "
                                   "surfaces touching at a point); split the vertex")
        raise NonManifoldError(f"not a surface: {o}")


def _orient(X, T, rows, reorient: bool) -> np.ndarray:
    """Flip mask making the faces consistently oriented (all False if they already are)."""
    ok, edge = is_consistently_oriented(X, T)
    if ok:
        return np.zeros(len(T), bool)
    try:
        o = X.orientation()
    except NonOrientableError as err:
        at = getattr(err, "simplex", edge)
        raise NonOrientableError(
            f"the surface is not orientable: it contains a Möbius band (carrying an orientation of the faces "
            f"around it comes back reversed, e.g. at edge {at}). Direction fields are sections of the tangent "
            "bundle of an oriented surface; n-direction fields on non-orientable surfaces (a twisted bundle) "
            "are future work") from None
    if not reorient:
        a, b = edge
        at = rows[np.isin(T, [a]).any(axis=1) & np.isin(T, [b]).any(axis=1)]
        raise InconsistentOrientationError(
            f"faces {int(at[0])} and {int(at[1])} traverse their common edge {edge} in the same direction: "
            "the faces are not consistently oriented. Pass reorient=True to flip faces into a consistent "
            "orientation (the majority orientation of each component is kept)")
    tri = X.index(2, T)
    want = o[tri] * SimplicialComplex.orientation_of(T)  # +1 where the face agrees with o
    _, comp = X.connected_components()
    c = comp[np.searchsorted(X.vertex_labels, T[:, 0])]
    votes = np.bincount(c, weights=want, minlength=int(c.max()) + 1)
    sign = np.where(votes >= 0, 1, -1)
    return want * sign[c] < 0


class SurfaceMesh:
    """An oriented triangle 2-manifold mesh (see :func:`validate_surface`); compact numbering.

    Attributes
    ----------
    points : (N, 3) float64
        Coordinates of the compact vertices.
    faces : (m, 3) int64
        Oriented faces in compact vertex numbers (flipped rows reversed: ``(a, c, b)``).
    complex : SimplicialComplex
        Built from the input labels: ``complex.vertex_labels[v]`` is the input row of vertex v.
    face_rows : (m,) int64
        Input row in F of each face.
    flipped : (m,) bool
        Faces whose orientation was reversed by ``reorient=True``.
    n_input_vertices : int
        Number of rows of the input V (per-vertex input arrays may have this length).

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.surface import validate_surface
    >>> V = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]
    >>> mesh = validate_surface(V, [[0, 1, 2], [1, 3, 2]])
    >>> mesh.n_vertices, mesh.n_faces, mesh.euler_characteristic, mesh.is_closed
    (4, 2, 1, False)
    >>> mesh.boundary_halfedges.tolist()
    [[0, 1], [1, 3], [2, 0], [3, 2]]
    """

    def __init__(
        self,
        points: np.ndarray,
        faces: np.ndarray,
        complex: SimplicialComplex,
        face_rows: np.ndarray,
        flipped: np.ndarray,
        n_input_vertices: int | None = None,
    ):
        self.n_input_vertices = int(points.shape[0] if n_input_vertices is None else n_input_vertices)
        self.points = points
        self.faces = faces
        self.complex = complex
        self.face_rows = face_rows
        self.flipped = flipped
        for a in (points, faces, face_rows, flipped):
            a.setflags(write=False)

    @property
    def n_vertices(self) -> int:
        """Number of vertices."""
        return self.points.shape[0]

    @property
    def n_faces(self) -> int:
        """Number of triangles."""
        return self.faces.shape[0]

    @property
    def vertex_labels(self) -> np.ndarray:
        """Input row in V of each compact vertex."""
        return self.complex.vertex_labels

    @cached_property
    def triangle_of_face(self) -> np.ndarray:
        """Row of each face in ``complex.simplices(2)``."""
        return self.complex.index(2, self.vertex_labels[self.faces])

    @cached_property
    def face_sign(self) -> np.ndarray:
        """±1: orientation of each (oriented) face relative to its sorted, canonical triangle."""
        return SimplicialComplex.orientation_of(self.faces)

    @cached_property
    def face_of_triangle(self) -> np.ndarray:
        """Face of each canonical triangle (inverse of :attr:`triangle_of_face`)."""
        out = np.empty(self.n_faces, np.int64)
        out[self.triangle_of_face] = np.arange(self.n_faces)
        return out

    @cached_property
    def triangle_sign(self) -> np.ndarray:
        """The mesh orientation ``o_t`` per canonical triangle (the fundamental cycle on closed meshes)."""
        return self.face_sign[self.face_of_triangle]

    @cached_property
    def euler_characteristic(self) -> int:
        """The Euler characteristic ``V − E + F``."""
        return self.complex.euler_characteristic

    @cached_property
    def components(self) -> tuple[int, np.ndarray]:
        """Number of connected components and a component label per vertex."""
        return self.complex.connected_components()

    @cached_property
    def boundary_halfedges(self) -> np.ndarray:
        """``(b, 2)`` boundary edges ``(a, b)`` as traversed by their face (the induced boundary orientation)."""
        h = np.stack([self.faces, np.roll(self.faces, -1, axis=1)], axis=-1).reshape(-1, 2)
        N = self.n_vertices
        keys = h[:, 0] * N + h[:, 1]
        twin = np.isin(h[:, 1] * N + h[:, 0], keys)
        out = h[~twin]
        return out[np.lexsort((out[:, 1], out[:, 0]))]

    @cached_property
    def is_boundary_vertex(self) -> np.ndarray:
        """Bool per vertex: True on the boundary."""
        mask = np.zeros(self.n_vertices, bool)
        mask[self.boundary_halfedges.ravel()] = True
        return mask

    @property
    def is_closed(self) -> bool:
        """True if the surface has no boundary."""
        return self.boundary_halfedges.shape[0] == 0

    def per_vertex(self, values: ArrayLike, what: str = "values") -> np.ndarray:
        """Per-vertex input data in compact order: ``values`` has one row per compact vertex or per row of V."""
        arr = np.asarray(values)
        if arr.ndim >= 1 and arr.shape[0] == self.n_input_vertices:
            return arr[self.vertex_labels]
        if arr.ndim >= 1 and arr.shape[0] == self.n_vertices:
            return arr
        raise ShapeError(f"{what} must have one row per row of the input V ({self.n_input_vertices}) or per "
                         f"compact vertex ({self.n_vertices}), got shape {arr.shape}")

    def to_input(self, values: ArrayLike, fill: Any = np.nan) -> np.ndarray:
        """Scatter per-vertex values (compact order) back to one row per row of the input V."""
        arr = np.asarray(values)
        out = np.full((self.n_input_vertices,) + arr.shape[1:], fill, dtype=np.result_type(arr, np.asarray(fill)))
        out[self.vertex_labels] = arr
        return out

    def __repr__(self) -> str:
        return (f"SurfaceMesh(n_vertices={self.n_vertices}, n_faces={self.n_faces}, "
                f"chi={self.euler_characteristic}, boundary_edges={len(self.boundary_halfedges)})")


def validate_surface(V: ArrayLike, F: ArrayLike, *, reorient: bool = False, components: str = "all") -> SurfaceMesh:
    """Check a triangle mesh and return it as an oriented :class:`SurfaceMesh`.

    Parameters
    ----------
    V : (n, 3) float array (or (n, 2) for a planar mesh, padded with z = 0)
    F : (m, 3) int array
        Triangles as rows of V; the vertex order of each row is its orientation.
    reorient : bool
        If the surface is orientable but the faces are not consistently oriented, flip faces
        (keeping the majority orientation of each component) instead of raising.
    components : {"all", "largest"}
        Keep all connected components, or only the one with most faces (warning).

    Raises
    ------
    InvalidSimplexError, EmptyComplexError, ShapeError
        Bad shapes, indices outside V, duplicate faces.
    NonFiniteError
        A used vertex has a NaN or infinite coordinate.
    DegenerateSimplexError
        A face repeats a vertex or has zero area.
    NonManifoldError
        An edge with three or more faces, or a vertex whose faces form several fans.
    NonOrientableError
        The surface is not orientable (e.g. a Möbius band).
    InconsistentOrientationError
        Orientable, but the faces are inconsistently oriented and ``reorient=False``.

    Warns
    -----
    UnreferencedVertexWarning
        Rows of V used by no face are dropped.

    Examples
    --------
    >>> from dhlb.surface import validate_surface
    >>> V = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]
    >>> try:
    ...     validate_surface(V, [[0, 1, 2], [1, 2, 3]])
    ... except Exception as err:
    ...     print(type(err).__name__)
    InconsistentOrientationError
    >>> validate_surface(V, [[0, 1, 2], [1, 2, 3]], reorient=True).flipped.tolist()
    [False, True]
    """
    if components not in ("all", "largest"):
        raise InvalidParameterError(f"components must be 'all' or 'largest', got {components!r}")
    P, T = _parse(V, F)
    _check_faces(P, T)
    rows = np.arange(len(T), dtype=np.int64)
    T0 = T
    X = SimplicialComplex(T)
    if components == "largest":
        ncomp, comp = X.connected_components()
        if ncomp > 1:
            fc = comp[np.searchsorted(X.vertex_labels, T[:, 0])]
            keep = fc == np.argmax(np.bincount(fc))
            warnings.warn(f"kept the largest of {ncomp} components ({int(keep.sum())} faces); "
                          f"{int((~keep).sum())} faces dropped", DhlbWarning, stacklevel=2)
            T, rows = T[keep], rows[keep]
            X = SimplicialComplex(T)
    _check_geometry(P, T, rows)
    unused = np.setdiff1d(np.arange(len(P)), np.unique(T0))  # not counting dropped components
    if unused.size:
        warnings.warn(f"{unused.size} vertices of V are used by no face and were dropped (first: "
                      f"{', '.join(str(int(v)) for v in unused[:5])}); mesh.vertex_labels maps compact "
                      "vertices to rows of V", UnreferencedVertexWarning, stacklevel=2)
    _check_manifold(X, T, rows)
    flip = _orient(X, T, rows, reorient)
    T = np.where(flip[:, None], T[:, [0, 2, 1]], T)
    faces = np.searchsorted(X.vertex_labels, T)
    return SurfaceMesh(np.ascontiguousarray(P[X.vertex_labels]), faces, X, rows, flip, len(P))
