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
    DhlbError,
    DhlbWarning,
    InvalidParameterError,
    NonManifoldError,
    ShapeError,
    UnreferencedVertexWarning,
)
from dhlb.geometry.euclidean import EuclideanComplex
from dhlb.mesh import _surface_checks as checks
from dhlb.mesh import _vec3 as vec3
from dhlb.mesh.compact import _renumber
from dhlb.mesh.halfedge import Fans, halfedge_pairs, vertex_fans
from dhlb.topology._keys import argsort_keys
from dhlb.topology.complex import SimplicialComplex

if TYPE_CHECKING:
    from typing import Any

    from numpy.typing import ArrayLike

__all__ = ["SurfaceMesh", "validate_surface"]


class SurfaceMesh:
    """An oriented triangle 2-manifold mesh (see :func:`validate_surface`); compact numbering.

    Made by :func:`validate_surface`, which checks the arrays; the constructor checks nothing and
    makes the arrays read-only. Every parameter is kept as the attribute of the same name.

    Parameters
    ----------
    points : (N, 3) float array
        Coordinates of the compact vertices.
    faces : (m, 3) int array
        Oriented faces in compact vertex numbers (flipped rows reversed: ``(a, c, b)``).
    complex : SimplicialComplex
        Built from the input labels: ``complex.vertex_labels[v]`` is the input row of vertex v.
    face_rows : (m,) int array
        Input row in F of each face.
    flipped : (m,) bool array
        Faces whose orientation was reversed by ``reorient=True``.
    n_input_vertices : int, optional
        Number of rows of the input V (per-vertex input arrays may have this length); default ``N``.
    repair : MeshRepair, optional
        What :func:`dhlb.mesh.repair.repair_surface` did to the input, with the maps back to it
        (``vertex_rows``, ``vertex_of_input``, ``face_of_input``); None for a mesh that needed no repair.
    edge_lengths : (n_1,) float array, optional
        An intrinsic metric, one length per edge of ``complex`` (a mollified mesh, see
        :mod:`dhlb.mesh.repair`): corner angles, areas and the finite elements then come from these
        lengths, not from ``points``; ``points`` still place the mesh in space (frames, pictures).

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import validate_surface
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
        *,
        repair: Any = None,
        edge_lengths: np.ndarray | None = None,
    ):
        self.n_input_vertices = int(points.shape[0] if n_input_vertices is None else n_input_vertices)
        self.points = points
        self.faces = faces
        self.complex = complex
        self.face_rows = face_rows
        self.flipped = flipped
        self.repair = repair
        self.edge_lengths = edge_lengths
        for a in (points, faces, face_rows, flipped) + (() if edge_lengths is None else (edge_lengths,)):
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
        """The label of each compact vertex in ``complex`` (its input row in V, unless the mesh was repaired).

        A repaired mesh (:attr:`repair`) numbers the extra copies of split vertices after the rows of
        V; :attr:`vertex_rows` gives the input row of every vertex.
        """
        return self.complex.vertex_labels

    @property
    def vertex_rows(self) -> np.ndarray:
        """Input row in V of each compact vertex (copies of a split vertex share their row)."""
        return self.complex.vertex_labels if self.repair is None else self.repair.vertex_rows

    @property
    def is_intrinsic(self) -> bool:
        """True when the metric is the mesh's own :attr:`edge_lengths` (a mollified mesh), not ``points``."""
        return self.edge_lengths is not None

    def is_validation_of(self, V, F, components: str = "all") -> bool:
        """Whether ``validate_surface(V, F, components=components)`` gives this mesh again.

        True when ``V`` and ``F`` are the arrays it was built from (equal values), no face was
        flipped and, with ``components="largest"``, there was only one component.  An application
        given a mesh and the arrays again (e.g. a direction field and its ``V, F``) can then use the
        mesh as it is, with its cached fans, angles and frames, instead of validating once more.
        A repaired mesh is the validation of the arrays it was repaired from, with the same repairs
        (:meth:`~dhlb.mesh.repair.MeshRepair.is_repair_of`).

        Parameters
        ----------
        V : (n, 3) float array
            Vertex positions.
        F : (m, 3) int array
            Triangles as rows of V.
        components : {"all", "largest"}, optional
            The ``components`` the validation would be asked for.

        Returns
        -------
        bool

        Examples
        --------
        >>> import numpy as np
        >>> from dhlb.mesh import validate_surface
        >>> V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]]); F = np.array([[0, 1, 2]])
        >>> mesh = validate_surface(V, F)
        >>> mesh.is_validation_of(V, F), mesh.is_validation_of(V + 1.0, F), mesh.is_validation_of(V, F[:, ::-1])
        (True, False, False)
        """
        if not (isinstance(V, np.ndarray) and isinstance(F, np.ndarray)):
            return False
        if self.repair is not None:   # a repaired mesh: the same input arrays and options
            return self.repair.is_repair_of(V, F, components, self.repair.options)
        if V.dtype.kind not in "fiu" or F.dtype.kind not in "iu" or V.shape != (self.n_input_vertices, 3):
            return False
        if F.shape != self.faces.shape or np.any(self.flipped) or (components == "largest" and self.components[0] > 1):
            return False
        labels = self.vertex_labels
        return bool(np.array_equal(F, labels[self.faces]) and np.array_equal(V[labels], self.points))

    @cached_property
    def length_scale(self) -> float:
        """A power of two near the half-size of the mesh's bounding box (the internal length unit).

        Computations whose floating-point range depends on the unit (areas, Gram determinants)
        should use :attr:`unit_points` = ``points / length_scale`` and convert lengths back by
        multiplying with it: dividing by a power of two is exact, so the result does not depend
        on whether the mesh is given in 1e-150 or 1e+150 units.

        Examples
        --------
        >>> import numpy as np
        >>> from dhlb.mesh import validate_surface
        >>> V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]]); F = [[0, 1, 2]]
        >>> a, b = validate_surface(V, F), validate_surface(V * 1e-150, F)
        >>> a.length_scale, float(b.unit_points.max()), bool(np.isclose(a.corner_angles, b.corner_angles).all())
        (1.0, 1.636695303948071, True)
        """
        return checks.length_scale(self.points)

    @cached_property
    def unit_points(self) -> np.ndarray:
        """``points / length_scale`` (exact): coordinates of size about 1, whatever the unit."""
        P = self.points / self.length_scale
        P.setflags(write=False)
        return P

    @cached_property
    def corner_angles(self) -> np.ndarray:
        """``(m, 3)`` Euclidean angle at each corner of each (oriented) face (of :attr:`edge_lengths` if set)."""
        if self.edge_lengths is not None:  # the intrinsic triangles: the geometry's interior angles
            alpha = self.geometry._top.dihedral_angles[self.triangle_of_face]   # (m, 3, 3), sorted vertices
            rank = np.argsort(np.argsort(self.faces, axis=1), axis=1)   # corner p is vertex rank[p] of the triangle
            f = np.arange(self.n_faces)[:, None]
            return alpha[f, (rank + 1) % 3, (rank + 2) % 3]
        Ut, F = self.unit_points.T, self.faces  # angles are scale free; unit points avoid under/overflow
        Q = [np.take(Ut, F[:, p], axis=1) for p in range(3)]
        E = [Q[1] - Q[0], Q[2] - Q[1], Q[0] - Q[2]]  # E[p]: the edge from corner p to corner p + 1
        twice_area = vec3.norm(vec3.cross(E[0], E[1]))  # |e1 × e2| at every corner
        dots = np.empty((F.shape[0], 3))
        for p in range(3):
            dots[:, p] = -vec3.dot(E[p], E[p - 1])  # <E[p], -E[p - 1]>
        return np.arctan2(twice_area[:, None], dots)

    @cached_property
    def geometry(self) -> EuclideanComplex:
        """The Euclidean complex of the mesh (points in compact vertex order, or the intrinsic :attr:`edge_lengths`)."""
        if self.edge_lengths is not None:
            return EuclideanComplex(self.complex, edge_lengths=self.edge_lengths)
        return EuclideanComplex(self.complex, points=self.points)

    @cached_property
    def halfedge_twin(self) -> np.ndarray:
        """``(3m,)`` the opposite of half-edge ``3f + k`` (``faces[f, k] → faces[f, k+1]``), ``-1`` on the boundary."""
        return self._pairs[0]

    @cached_property
    def halfedge_edge(self) -> np.ndarray:
        """``(3m,)`` the row in ``complex.simplices(1)`` of the edge of half-edge ``3f + k``."""
        return self._pairs[1]

    @cached_property
    def _pairs(self):
        return halfedge_pairs(self.faces, self.n_vertices)

    @cached_property
    def fans(self) -> Fans:
        """The corner fans around the vertices (:mod:`dhlb.mesh.halfedge`); raises if a vertex has several."""
        return vertex_fans(self.faces, self.n_vertices, self.corner_angles, self._pairs)

    @cached_property
    def triangle_of_face(self) -> np.ndarray:
        """Row of each face in ``complex.simplices(2)``.

        The triangles of the complex are sorted by ``(row of the edge (s0, s1), s2)`` for their
        sorted vertices ``s0 < s1 < s2`` (``dhlb.topology._keys``); the edge ``(s0, s1)`` of a face
        is its half-edge that does not touch ``s2``, so one sort of these keys gives the rows.
        """
        F, m = self.faces, self.n_faces
        top = np.argmax(F, axis=1)
        prefix = self.halfedge_edge[3 * np.arange(m) + (top + 1) % 3]
        order = argsort_keys(prefix * self.n_vertices + F[np.arange(m), top],
                             self.complex.n_simplices(1) * self.n_vertices)
        out = np.empty(m, np.int64)
        out[order] = np.arange(m)
        return out

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
        out = h[self.halfedge_twin < 0]
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
            return arr[self.vertex_rows]
        if arr.ndim >= 1 and arr.shape[0] == self.n_vertices:
            return arr
        raise ShapeError(f"{what} must have one row per row of the input V ({self.n_input_vertices}) or per "
                         f"compact vertex ({self.n_vertices}), got shape {arr.shape}")

    @cached_property
    def input_vertex_used(self) -> np.ndarray:
        """``(n_input_vertices,)`` bool: True for the rows of the input V that some face uses.

        Outputs in input order (:meth:`to_input`) hold ``fill`` (NaN) on the other rows; writers
        store this mask next to them (key ``vertex_used`` in ``.npz`` files) so that a NaN row is
        never mistaken for a failure.

        Examples
        --------
        >>> import warnings
        >>> from dhlb.mesh import validate_surface
        >>> with warnings.catch_warnings():
        ...     warnings.simplefilter("ignore")
        ...     mesh = validate_surface([[0, 0, 0], [9, 9, 9], [1, 0, 0], [0, 1, 0]], [[0, 2, 3]])
        >>> mesh.input_vertex_used.tolist(), mesh.to_input([1.0, 2.0, 3.0]).tolist()
        ([True, False, True, True], [1.0, nan, 2.0, 3.0])
        """
        if self.repair is not None:
            used = self.repair.vertex_of_input >= 0
        else:
            used = np.zeros(self.n_input_vertices, dtype=bool)
            used[self.vertex_labels] = True
        used.setflags(write=False)
        return used

    def to_input(self, values: ArrayLike, fill: Any = np.nan) -> np.ndarray:
        """Scatter per-vertex values (compact order) back to one row per row of the input V.

        Rows of V that no face uses (see :attr:`input_vertex_used`) get ``fill`` (NaN by default). On a
        repaired mesh a row split into several vertices gets the value of the copy whose fan has the
        largest area, and rows merged into one vertex all get its value (``repair.vertex_of_input``).
        """
        if self.repair is not None:
            return _scatter(values, self.repair.vertex_of_input, fill)
        source = np.full(self.n_input_vertices, -1, np.int64)
        source[self.vertex_labels] = np.arange(self.n_vertices)
        return _scatter(values, source, fill)

    def to_input_faces(self, values: ArrayLike, fill: Any = 0) -> np.ndarray:
        """Scatter per-face values back to one row per row of the input F.

        Faces no longer in the mesh (``components="largest"``, or removed by a repair: a face repeating a
        vertex, a doubled sheet) get ``fill``; a duplicate face merged by a repair gets the value of the
        copy that was kept (``repair.face_of_input``).

        Examples
        --------
        >>> import warnings
        >>> from dhlb.mesh import repair_surface
        >>> with warnings.catch_warnings():
        ...     warnings.simplefilter("ignore")
        ...     mesh = repair_surface([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2], [0, 1, 2]])
        >>> mesh.n_faces, mesh.to_input_faces([7]).tolist()
        (1, [7, 7])
        """
        if self.repair is not None:
            return _scatter(values, self.repair.face_of_input, fill)
        source = np.full(int(self.face_rows.max(initial=-1)) + 1, -1, np.int64)
        source[self.face_rows] = np.arange(self.n_faces)
        return _scatter(values, source, fill)

    def release_caches(self) -> int:
        """Drop the arrays this mesh, its complex and its geometry have derived and cached; return how many.

        Half-edges, corner fans, corner angles, the per-triangle metrics of the geometry and the
        complex's adjacency are recomputed on the next access.  Before a large factorization that needs
        the memory this frees it: :func:`dhlb.fields.direction_field` does so from
        :data:`dhlb.fields.field.LEAN_MIN_VERTICES` vertices on (655 MiB at 655k vertices).

        Returns
        -------
        int
            The number of cached values dropped.

        Examples
        --------
        >>> from dhlb.mesh import validate_surface
        >>> mesh = validate_surface([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
        >>> angles = mesh.corner_angles
        >>> mesh.release_caches() > 0, bool((mesh.corner_angles == angles).all())
        (True, True)
        """
        from dhlb._caches import drop_cached

        dropped = drop_cached(self, keep=("geometry", "length_scale"))
        if "geometry" in vars(self):
            dropped += drop_cached(self.geometry, keep=("complex",))
        return dropped + drop_cached(self.complex)

    def __repr__(self) -> str:
        return (f"SurfaceMesh(n_vertices={self.n_vertices}, n_faces={self.n_faces}, "
                f"chi={self.euler_characteristic}, boundary_edges={len(self.boundary_halfedges)}"
                + ("" if self.repair is None else f", repaired: {', '.join(r.kind for r in self.repair.repairs)}")
                + ")")


def _scatter(values, source: np.ndarray, fill) -> np.ndarray:
    """``out[r] = values[source[r]]`` where ``source[r] >= 0``, else ``fill`` (one row per input row)."""
    arr = np.asarray(values)
    out = np.full((source.size,) + arr.shape[1:], fill, dtype=np.result_type(arr, np.asarray(fill)))
    rows = np.flatnonzero(source >= 0)
    out[rows] = arr[source[rows]]
    return out


def _distinct_halfedges(F: np.ndarray, n_vertices: int):
    """:func:`~dhlb.mesh.halfedge.halfedge_pairs` of ``F``, or None when two directed half-edges coincide.

    Distinct directed half-edges mean an edge-manifold, consistently oriented surface (only the fans
    remain to be checked); otherwise the general checks of :func:`validate_surface` say what is wrong.
    """
    try:
        return halfedge_pairs(F, n_vertices)
    except NonManifoldError:
        return None


def _surface_complex(F: np.ndarray, labels: np.ndarray, pairs) -> tuple[SimplicialComplex, np.ndarray]:
    """The complex of the faces ``F`` (compact numbers; input vertex ``labels``) from their half-edges.

    ``pairs`` is :func:`~dhlb.mesh.halfedge.halfedge_pairs` of ``F``: its edge rows are those of the
    complex. The key of a triangle ``s0 < s1 < s2`` is ``row of (s0, s1) * n + s2``, and the edge
    ``(s0, s1)`` of a face is its half-edge that does not touch ``s2``, so one sort gives the
    triangles, the row of each face (:attr:`SurfaceMesh.triangle_of_face`) and the edges of each
    triangle (``complex.faces(2)``).
    """
    n, m = labels.size, F.shape[0]
    _, edge, n_edges = pairs
    ekeys = np.empty(n_edges, np.int64)
    a, b = F.ravel(), np.roll(F, -1, axis=1).ravel()
    ekeys[edge] = np.minimum(a, b) * n + np.maximum(a, b)
    top = np.argmax(F, axis=1)
    tkeys = edge[3 * np.arange(m) + (top + 1) % 3] * n + F[np.arange(m), top]
    order = argsort_keys(tkeys, n_edges * n)
    tri = np.empty(m, np.int64)
    tri[order] = np.arange(m)
    # faces(2): the edge omitting corner p of a face is its half-edge p + 1; corners by increasing vertex
    low = np.argmin(F, axis=1)
    corners = np.stack([low, 3 - low - top, top], axis=1)[order]
    faces = edge[3 * order[:, None] + (corners + 1) % 3]
    return SimplicialComplex._from_keys(labels, [ekeys, tkeys[order]], faces), tri


def _checked_geometry(X: SimplicialComplex, P: np.ndarray, kept: np.ndarray, T: np.ndarray, rows: np.ndarray):
    """The Euclidean complex of the mesh (:attr:`SurfaceMesh.geometry`), or None if it cannot be built.

    Finite coordinates and faces of nonzero area (:func:`~dhlb.mesh._surface_checks.check_geometry`, whose
    message names the face by its input row); the geometry's own test is the same one, so it is run once,
    and the named check only when the geometry refuses the points. (The check works in units of the mesh
    size and passes meshes in 1e-150 units the geometry may refuse: then it is None here and
    :attr:`SurfaceMesh.geometry` raises when asked for.)
    """
    try:
        with np.errstate(all="ignore"):   # coordinates near 1e±300 overflow inside; the refusal is what counts
            return EuclideanComplex(X, points=np.ascontiguousarray(P[kept]))
    except DhlbError:
        checks.check_geometry(P, T, rows)
        return None


def validate_surface(V: ArrayLike, F: ArrayLike, *, reorient: bool = False, components: str = "all") -> SurfaceMesh:
    """Check a triangle mesh and return it as an oriented :class:`SurfaceMesh`.

    Every defect is an error here; :func:`dhlb.mesh.repair_surface` repairs what other tools repair
    routinely (non-manifold vertices and edges, duplicate faces, doubled sheets, zero-area faces) and
    returns a mesh that maps back to the input.

    Parameters
    ----------
    V : (n, 3) float array
        Vertex positions (or ``(n, 2)`` for a planar mesh, padded with z = 0).
    F : (m, 3) int array
        Triangles as rows of V; the vertex order of each row is its orientation.
    reorient : bool, optional
        If the surface is orientable but the faces are not consistently oriented, flip faces
        (keeping the majority orientation of each component) instead of raising.
    components : {"all", "largest"}, optional
        Keep all connected components, or only the one with most faces (warning).

    Returns
    -------
    SurfaceMesh
        The compacted, consistently oriented mesh; ``mesh.face_rows`` and ``mesh.vertex_rows``
        map its faces and vertices back to the rows of ``F`` and ``V``.

    Raises
    ------
    InvalidParameterError
        ``components`` is neither ``"all"`` nor ``"largest"``.
    InvalidSimplexError, EmptyComplexError, ShapeError
        Bad shapes, indices outside V, duplicate faces.
    RaggedInputError, InvalidTypeError
        ``V`` or ``F`` has rows of different lengths, or holds complex or non-numeric values.
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
    >>> from dhlb.mesh import validate_surface
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
    return _validate(V, F, reorient, components)


def _validate(V, F, reorient: bool, components: str) -> SurfaceMesh:
    """:func:`validate_surface` without repairs: every defect is an error."""
    P, T = checks.parse(V, F)
    checks.check_faces(P, T)
    rows = np.arange(len(T), dtype=np.int64)
    T0 = T
    X = None
    if components == "largest":
        X = SimplicialComplex(T)
        ncomp, comp = X.connected_components()
        if ncomp > 1:
            fc = comp[np.searchsorted(X.vertex_labels, T[:, 0])]
            keep = fc == np.argmax(np.bincount(fc))
            warnings.warn(f"kept the largest of {ncomp} components ({int(keep.sum())} faces); "
                          f"{int((~keep).sum())} faces dropped", DhlbWarning, stacklevel=3)
            T, rows = T[keep], rows[keep]
            X = None
    kept, compact = _renumber(len(P), T)
    Fc = compact[T]
    pairs = _distinct_halfedges(Fc, kept.size)
    tri = None
    if pairs is not None:  # the complex from the half-edges: no second sort of the edges
        X, tri = _surface_complex(Fc, kept, pairs)
    elif X is None:
        X = SimplicialComplex(T)
    geometry = _checked_geometry(X, P, kept, T, rows)
    unused = np.flatnonzero(_renumber(len(P), T0)[1] < 0)  # not counting dropped components
    if unused.size:
        warnings.warn(UnreferencedVertexWarning(
            f"{unused.size} vertices of V are used by no face and were dropped (first: "
            f"{', '.join(str(int(v)) for v in unused[:5])}); mesh.vertex_labels maps compact vertices to rows of V",
            dropped=unused, cell="face"), stacklevel=3)
    if pairs is not None:
        flip = np.zeros(len(T), bool)
    else:
        checks.check_manifold(X, T, rows)
        flip = checks.orient(X, T, rows, reorient)
        T = np.where(flip[:, None], T[:, [0, 2, 1]], T)
        Fc = compact[T]
    mesh = SurfaceMesh(np.ascontiguousarray(P[kept]), Fc, X, rows, flip, len(P))
    # what was computed on the way (the cached properties compute the same from the mesh)
    if pairs is not None:
        mesh.__dict__.update(_pairs=pairs, triangle_of_face=tri)
    if geometry is not None:
        mesh.__dict__["geometry"] = geometry
    try:
        _ = mesh.fans  # one fan per vertex (cached: the tangent bundle uses it)
    except NonManifoldError:
        checks.check_manifold(X, T, rows)  # names the vertex in input numbers
        raise
    return mesh
