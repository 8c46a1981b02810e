"""The discrete tangent bundle (n-th power) of an oriented triangle mesh (seed part 1, §6, App. B).

Construction (all vertices in compact numbering, see :mod:`dhlb.mesh.surface`):

* **Rescaled angles** (Eq. 6.1). Θ_i is the sum of the corner angles at vertex i and
  ``s_i = 2π / Θ_i`` at interior vertices, ``s_i = 1`` at boundary vertices (as in the seed: the
  tangent "plane" of a boundary vertex keeps its Euclidean angles). The rescaled angle
  ``θ_i(e)`` of an edge e at i is ``s_i`` times the Euclidean angle swept counterclockwise (for
  the mesh orientation) across the fan of i from the **reference edge** of i to e.
* **Frames**. The unit basis vector X_i at vertex i is the direction of its reference edge:
  the first edge of the fan of a boundary vertex (a boundary edge, so that the fan spans the
  rescaled angles ``[0, Θ_i]``) and, at an interior vertex, the first edge of the corner with
  the smallest index ``3 f + p``. A tangent vector at angle θ has coefficient ``e^{iθ}``; an
  n-vector ``z^n`` in the power representation.
* **Transport** (Eq. 6.2). Moving along the straight edge from i to j keeps the angle with the
  edge; at j the edge direction ``i → j`` has rescaled angle ``θ_j(e_ji) + π``. Hence, per
  canonical edge ``i < j`` with ``z_j = r_ij z_i`` (``docs/conventions.md``),
  ``ρ_ij = n (θ_j(e_ji) + π − θ_i(e_ij))`` and ``r_ij = e^{iρ_ij}``.
* **Curvature** (App. B, derived). Around a face ``(i, j, k)`` in mesh orientation the angle
  changes add up to ``Σ (θ_j(e_ji) − θ_j(e_jk)) + 3π = s_i α_i + s_j α_j + s_k α_k + 3π``
  (mod 2π at interior vertices, whose rescaled angles are defined mod ``s_i Θ_i = 2π``), so the
  holonomy is ``r_ij r_jk r_ki = exp(i n σ_t)`` exactly, with the **geometric curvature**
  ``σ_t = s_i α_i + s_j α_j + s_k α_k − π``, the angle defect pushed into the face. We use
  ``Ω_t = o_t n σ_t`` on the canonical triangle (``o_t`` the mesh orientation); on an n-smooth
  mesh (``|σ_t| < π/n``) it is the principal argument of the holonomy. Gauss–Bonnet:
  ``Σ_t σ_t = 2π|V| − π|T| = 2πχ`` on a closed mesh, so the bundle has degree ``n χ`` (the
  seed's Appendix B prints ``2nπχ`` for the index sum, which should read ``nχ``). With boundary,
  ``Σ_t σ_t + Σ_{i ∈ ∂} (π − Θ_i) = 2πχ``: the boundary turning angles ``κ_i = π − Θ_i`` are
  the geodesic curvature of the boundary.

Examples
--------
>>> import numpy as np
>>> from dhlb.mesh import tangent_bundle
>>> V = [[0, 0, 1], [0, 0, -1], [1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0]]
>>> F = [[0, 2, 4], [0, 4, 3], [0, 3, 5], [0, 5, 2], [1, 4, 2], [1, 3, 4], [1, 5, 3], [1, 2, 5]]
>>> tb = tangent_bundle(V, F, n=4)                  # the octahedron
>>> tb.bundle.degree(), round(float(tb.face_curvature.sum() / (2 * np.pi)), 12)
(8, 2.0)
"""

from __future__ import annotations

from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np

from dhlb._coerce import check_int
from dhlb.bundles.hermitian import HermitianLineBundle
from dhlb.errors import InvalidParameterError, NonFiniteError, ShapeError
from dhlb.geometry.euclidean import EuclideanComplex
from dhlb.mesh._vec3 import cross, dot, unit
from dhlb.mesh.halfedge import TWO_PI, AngleMap
from dhlb.mesh.repair import repair_surface
from dhlb.mesh.surface import SurfaceMesh

if TYPE_CHECKING:
    from typing import Any

    from numpy.typing import ArrayLike

__all__ = ["TangentBundle", "tangent_bundle"]


class TangentBundle:
    """The n-th power of the discrete tangent bundle of a :class:`SurfaceMesh`.

    Parameters
    ----------
    mesh : SurfaceMesh
        A validated surface (:func:`~dhlb.mesh.validate_surface`).
    n : int >= 1, optional
        The power: 1 vector fields, 2 line fields, 4 cross fields, ...

    Raises
    ------
    TypeError
        ``mesh`` is not a :class:`SurfaceMesh`.
    InvalidParameterError
        ``n`` is not an integer >= 1 (booleans are refused).

    Notes
    -----
    The attributes (per compact vertex, per face of ``mesh`` or per canonical simplex of
    ``mesh.complex``) are documented at each property. ``bundle`` is the
    :class:`~dhlb.bundles.HermitianLineBundle` and ``geometry`` the
    :class:`~dhlb.geometry.EuclideanComplex` the finite-element engine takes.

    Examples
    --------
    >>> from dhlb.mesh import TangentBundle, validate_surface
    >>> V = [[0, 0, 1], [0, 0, -1], [1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0]]
    >>> F = [[0, 2, 4], [0, 4, 3], [0, 3, 5], [0, 5, 2], [1, 4, 2], [1, 3, 4], [1, 5, 3], [1, 2, 5]]
    >>> tb = TangentBundle(validate_surface(V, F), n=4)    # cross fields on the octahedron
    >>> tb.n, tb.scale.round(12).tolist()                 # s_i = 2π / (4 · π/3)
    (4, [1.5, 1.5, 1.5, 1.5, 1.5, 1.5])
    """

    def __init__(self, mesh: SurfaceMesh, n: int = 1):
        if not isinstance(mesh, SurfaceMesh):
            raise TypeError(f"mesh must be a SurfaceMesh (see validate_surface), got {type(mesh).__name__}")
        n = check_int(n, "n (the number of directions)", 1)
        self.mesh: SurfaceMesh = mesh
        self.n = n

    # ------------------------------------------------------------------ per corner / per face
    @property
    def corner_angles(self) -> np.ndarray:
        """``(m, 3)`` Euclidean angle at each corner of each (oriented) face."""
        return self.mesh.corner_angles

    @cached_property
    def face_normals(self) -> np.ndarray:
        """``(m, 3)`` unit normals of the oriented faces (right-hand rule)."""
        return np.ascontiguousarray(self._face_normals_t.T)

    @cached_property
    def _face_normals_t(self) -> np.ndarray:
        """``(3, m)`` :attr:`face_normals`, coordinates in rows."""
        E = self._corner_edges
        return unit(cross(E[0], -E[2]))[0]

    @cached_property
    def _corner_edges(self) -> np.ndarray:
        """``(3, 3, m)``: ``[p, :, f]`` the first edge ``P[F[f, p+1]] − P[F[f, p]]`` of corner ``(f, p)``."""
        Pt, F = self.mesh.points.T, self.mesh.faces
        Q = [np.take(Pt, F[:, p], axis=1) for p in range(3)]
        E = np.empty((3,) + Q[0].shape)
        for p in range(3):
            np.subtract(Q[(p + 1) % 3], Q[p], out=E[p])
        return E

    @property
    def _fans(self):
        return self.mesh.fans

    @cached_property
    def face_curvature(self) -> np.ndarray:
        """``(m,)`` geometric curvature σ_f = Σ_corners s_i α_i − π of each face (mesh orientation)."""
        s = self.scale[self.mesh.faces]
        return np.sum(s * self.corner_angles, axis=1) - np.pi

    # ------------------------------------------------------------------ per vertex
    @property
    def angle_sums(self) -> np.ndarray:
        """``(N,)`` Θ_i, the sum of the Euclidean corner angles at each vertex."""
        return self._fans.total

    @cached_property
    def is_boundary_vertex(self) -> np.ndarray:
        """Bool per vertex: True on the boundary."""
        return self._fans.boundary

    @cached_property
    def scale(self) -> np.ndarray:
        """``(N,)`` s_i = 2π/Θ_i at interior vertices and 1 at boundary vertices (Eq. 6.1)."""
        return np.where(self._fans.boundary, 1.0, TWO_PI / self._fans.total)

    @cached_property
    def reference_neighbors(self) -> np.ndarray:
        """``(N,)`` the other end of the reference edge of each vertex (compact numbers)."""
        return self._fans.first[self._fans.start]

    @cached_property
    def reference_vectors(self) -> np.ndarray:
        """``(N, 3)`` X_i: unit 3D vector along the reference edge (rescaled angle 0)."""
        return np.ascontiguousarray(self._reference_vectors_t.T)

    @cached_property
    def _reference_vectors_t(self) -> np.ndarray:
        """``(3, N)`` :attr:`reference_vectors`, coordinates in rows."""
        Pt = self.mesh.points.T
        return unit(np.take(Pt, self.reference_neighbors, axis=1) - Pt)[0]

    @cached_property
    def normals(self) -> np.ndarray:
        """``(N, 3)`` unit vertex normals, the corner-angle-weighted mean of the face normals."""
        return np.ascontiguousarray(self._frames_t[2].T)

    def _normals_t(self) -> np.ndarray:
        """``(3, N)`` :attr:`normals`, coordinates in rows."""
        alpha, fn = self.corner_angles, self._face_normals_t
        idx, nv = self.mesh.faces.ravel(), self.mesh.n_vertices
        N = np.stack([np.bincount(idx, weights=(alpha * fn[k][:, None]).ravel(), minlength=nv) for k in range(3)])
        N, nrm = unit(N)
        weak = nrm <= 1e-12 * np.max(nrm)
        if np.any(weak):  # cancelling fan normals: use the face of the reference corner
            N[:, weak] = fn[:, self._fans.start[weak] // 3]
        return N

    @cached_property
    def frames(self) -> np.ndarray:
        """``(N, 3, 3)`` orthonormal frames: rows T1 (projected reference edge), T2 = N × T1, N."""
        return np.ascontiguousarray(self._frames_t.transpose(2, 0, 1))

    @cached_property
    def _frames_t(self) -> np.ndarray:
        """``(3, 3, N)``: ``[k, :, i]`` the frame vector k (T1, T2, N) at vertex i, coordinates in the middle axis."""
        N = self._normals_t()
        X = self._reference_vectors_t
        T1, nrm = unit(X - (X[0] * N[0] + X[1] * N[1] + X[2] * N[2]) * N)
        weak = nrm <= 1e-9
        if np.any(weak):  # reference edge parallel to the normal: any unit vector orthogonal to N
            Nw = N[:, weak]
            alt = np.where(np.abs(Nw[:1]) < 0.9, [[1.0], [0], [0]], [[0], [1.0], [0]])
            T1[:, weak] = unit(cross(Nw, alt))[0]
        out = np.empty((3,) + N.shape)
        out[0], out[2] = T1, N
        cross(N, T1, out=out[1])
        return out

    @cached_property
    def boundary_turning(self) -> np.ndarray:
        """``(N,)`` turning angle π − Θ_i of the boundary at boundary vertices (geodesic curvature), 0 inside."""
        return np.where(self._fans.boundary, np.pi - self._fans.total, 0.0)

    # ------------------------------------------------------------------ rescaled angles of edges
    @cached_property
    def corner_edge_angles(self) -> np.ndarray:
        """``(m, 3, 2)``: rescaled angles at each corner of its first and its second edge."""
        fa = self._fans
        s = self.scale[fa.vertex]
        first = s * fa.prefix
        return np.stack([first, first + s * self.corner_angles.ravel()], axis=-1).reshape(-1, 3, 2)

    @cached_property
    def _edge_corner(self) -> np.ndarray:
        """For each canonical edge, one corner whose first edge lies on it."""
        he, tw = self.mesh.halfedge_edge, self.mesh.halfedge_twin
        h = np.arange(he.size, dtype=np.int64)
        out = np.empty(self.mesh.complex.n_simplices(1), np.int64)
        out[he] = np.where(tw >= 0, np.minimum(h, tw), h)  # both half-edges of an edge write the same value
        return out

    @cached_property
    def edge_angles(self) -> np.ndarray:
        """``(n_1, 2)`` per canonical edge ``i < j``: θ_i(e_ij) at i and θ_j(e_ji) at j (rescaled)."""
        c = self._edge_corner
        c2 = 3 * (c // 3) + (c % 3 + 1) % 3  # corner at the other end, same face
        ang = self.corner_edge_angles.reshape(-1, 2)
        at_v, at_a = ang[c, 0], ang[c2, 1]
        low = self._fans.vertex[c] < self._fans.first[c]
        return np.stack([np.where(low, at_v, at_a), np.where(low, at_a, at_v)], axis=1)

    @cached_property
    def transport_angles(self) -> np.ndarray:
        """``(n_1,)`` ρ_ij = n (θ_j(e_ji) + π − θ_i(e_ij)) per canonical edge (not wrapped)."""
        th = self.edge_angles
        return self.n * (th[:, 1] + np.pi - th[:, 0])

    @cached_property
    def curvature(self) -> np.ndarray:
        """``(n_2,)`` Ω_t = o_t n σ_t per canonical triangle (``docs/conventions.md`` orientation)."""
        m = self.mesh
        return m.triangle_sign * self.n * self.face_curvature[m.face_of_triangle]

    @cached_property
    def curvature_density(self) -> np.ndarray:
        """``(n_2,)`` n σ_t / area_t per canonical triangle: the density nK of ½∫ nK|ψ|² (orientation-free)."""
        return self.n * self.face_curvature[self.mesh.face_of_triangle] / self.geometry.volumes(2)

    @cached_property
    def bundle(self) -> HermitianLineBundle:
        """The hermitian line bundle with connection ``exp(iρ)`` and curvature Ω on ``mesh.complex``."""
        # finite angles give a unit connection whose holonomy is exp(iΩ) by construction (module docstring)
        return HermitianLineBundle._from_checked(self.mesh.complex, np.exp(1j * self.transport_angles),
                                                 self.curvature)

    @cached_property
    def geometry(self) -> EuclideanComplex:
        """The Euclidean complex (vertex positions in compact order): :attr:`SurfaceMesh.geometry`."""
        return self.mesh.geometry

    @cached_property
    def total_curvature(self) -> float:
        """Σ_t o_t Ω_t = n Σ σ_t (2π n χ on a closed mesh)."""
        return float(self.n * self.face_curvature.sum())

    @cached_property
    def total_boundary_turning(self) -> float:
        """N Σ_{i ∈ ∂} (π − Θ_i); ``total_curvature + total_boundary_turning = 2π n χ``."""
        return float(self.n * self.boundary_turning.sum())

    # ------------------------------------------------------------------ angles <-> 3D directions
    @cached_property
    def angle_map(self) -> AngleMap:
        """The piecewise-linear map between rescaled angles and polar angles in the vertex frames."""
        fa, Pt, F = self._fans, self.mesh.points.T, self.mesh.faces
        N, m = self.mesh.n_vertices, F.shape[0]
        bnd = np.nonzero(fa.boundary)[0]
        # breakpoints in fan order, placed directly (no sort): per vertex its corners' first edges by
        # rank, the last boundary edge at a boundary vertex, and the closing 2π
        size = fa.count + fa.boundary + 1
        off = np.zeros(N + 1, np.int64)
        np.cumsum(size, out=off[1:])
        th, ps = np.empty(off[-1]), np.empty(off[-1])
        th[off[1:] - 1] = TWO_PI
        ps[off[1:] - 1] = TWO_PI
        pos = np.take(off, fa.vertex)
        pos += fa.rank
        th[pos] = self.corner_edge_angles[:, :, 0].ravel()
        pos_b = off[bnd] + fa.count[bnd]
        th[pos_b] = self.corner_edge_angles.reshape(-1, 2)[fa.last[bnd], 1]
        # polar angle of each first edge in the frame of its vertex, one corner p of all faces at a time
        E, pos = self._corner_edges, pos.reshape(m, 3)
        rank = fa.rank.reshape(m, 3)
        for p in range(3):
            psi = self._polar(E[p], F[:, p])
            psi[rank[:, p] == 0] = 0.0
            ps[pos[:, p]] = psi
        ps[pos_b] = self._polar(np.take(Pt, fa.second[fa.last[bnd]], axis=1) - np.take(Pt, bnd, axis=1), bnd)
        return AngleMap.from_offsets(off, th, ps)

    def _polar(self, d: np.ndarray, verts: np.ndarray) -> np.ndarray:
        """Polar angle in ``[0, 2π)`` of the ``(3, k)`` vectors ``d`` in the frames ``(T1, T2)`` of ``verts``."""
        T = self._frames_t
        T1, T2 = [np.take(T[0, k], verts) for k in range(3)], [np.take(T[1, k], verts) for k in range(3)]
        psi = np.arctan2(dot(d, T2), dot(d, T1))
        return np.mod(psi, TWO_PI, out=psi)

    def half_edge_transport(self, a: ArrayLike, b: ArrayLike) -> np.ndarray:
        """``r_ab`` for the half-edges ``a → b`` (``conj(r_ba)`` of the canonical edge when ``a > b``).

        Examples
        --------
        >>> import numpy as np
        >>> from dhlb.mesh import tangent_bundle
        >>> tb = tangent_bundle([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]], n=2)
        >>> r01, r10 = tb.half_edge_transport([0, 1], [1, 0])
        >>> bool(np.isclose(r01 * r10, 1.0))
        True
        """
        a, b = np.asarray(a, np.int64), np.asarray(b, np.int64)
        N = self.mesh.n_vertices
        E = self.mesh.complex.simplices(1)
        lo, hi = np.minimum(a, b), np.maximum(a, b)
        r = self.bundle.connection[np.searchsorted(E[:, 0] * N + E[:, 1], lo * N + hi)]
        return np.where(a < b, r, np.conj(r))

    def angles_to_vectors(self, vertices: ArrayLike, angles: ArrayLike) -> np.ndarray:
        """Unit 3D tangent vectors at ``vertices`` with the given rescaled angles (broadcast).

        Examples
        --------
        >>> import numpy as np
        >>> from dhlb.mesh import tangent_bundle
        >>> tb = tangent_bundle([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
        >>> tb.angles_to_vectors([0, 0], [0.0, np.pi / 2]).round(12).tolist()
        [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
        """
        v, th = np.broadcast_arrays(np.asarray(vertices, np.int64), np.asarray(angles, np.float64))
        psi = self.angle_map.to_polar(v.ravel(), th.ravel())
        T = self._frames_t
        c, s = np.cos(psi), np.sin(psi)
        out = np.empty(v.size * 3)
        for k in range(3):
            out[k::3] = c * np.take(T[0, k], v.ravel()) + s * np.take(T[1, k], v.ravel())
        return out.reshape(v.shape + (3,))

    def vectors_to_angles(self, vectors: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """Rescaled angle and length of the tangential part of one 3D vector per vertex.

        ``vectors`` has one row per compact vertex or per row of the input V. Returns
        ``(angles, lengths)``, each ``(N,)``; the angle of a vector with no tangential part is 0.
        """
        W = np.asarray(self.mesh.per_vertex(np.asarray(vectors, dtype=np.float64), "vectors"), np.float64)
        if W.ndim != 2 or W.shape[1] != 3:
            raise ShapeError(f"vectors must have shape (n, 3), got {W.shape}")
        if not np.all(np.isfinite(W)):
            v = int(np.argmax(~np.isfinite(W).all(axis=1)))
            raise NonFiniteError(f"the vector at vertex {int(self.mesh.vertex_rows[v])} is not finite")
        T = self.frames
        x, y = np.sum(W * T[:, 0], 1), np.sum(W * T[:, 1], 1)
        psi = np.arctan2(y, x)
        theta = self.angle_map.to_rescaled(np.arange(len(W)), psi)
        return theta, np.hypot(x, y)

    def release_caches(self) -> int:
        """Drop what this bundle and its mesh have derived and cached, except the line bundle; return how many.

        The bundle's angles, frames and curvatures and the mesh's arrays
        (:meth:`SurfaceMesh.release_caches`) are recomputed on the next access; :attr:`bundle` (the
        connection and curvature the energy was built from) and :attr:`geometry` stay.

        Returns
        -------
        int
            The number of cached values dropped.

        Examples
        --------
        >>> from dhlb.mesh import tangent_bundle
        >>> tb = tangent_bundle([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]], n=2)
        >>> rho = tb.transport_angles
        >>> tb.release_caches() > 0, bool((tb.transport_angles == rho).all())
        (True, True)
        """
        from dhlb._caches import drop_cached

        return drop_cached(self, keep=("bundle", "geometry")) + self.mesh.release_caches()

    def __repr__(self) -> str:
        return f"TangentBundle(n={self.n}, {self.mesh!r})"


def tangent_bundle(
    V: ArrayLike | SurfaceMesh,
    F: ArrayLike | None = None,
    n: int = 1,
    *,
    reorient: bool = False,
    components: str = "all",
    repair: Any = "none",
) -> TangentBundle:
    """The discrete n-th tangent power bundle of a triangle mesh (validated first).

    Parameters
    ----------
    V : (n, 3) float array or SurfaceMesh
        Vertex positions, or an already validated mesh (then ``F`` must be None).
    F : (m, 3) int array, optional
        Triangles as rows of ``V``; required when ``V`` is an array.
    n : int >= 1, optional
        The power: 1 vector fields, 2 line fields, 4 cross fields, ...
    reorient : bool, optional
        Passed to :func:`dhlb.mesh.validate_surface` (ignored for a :class:`SurfaceMesh`).
    components : {"all", "largest"}, optional
        Passed to :func:`dhlb.mesh.validate_surface` (ignored for a :class:`SurfaceMesh`).
    repair : str or RepairOptions, optional
        The repairs allowed (:func:`dhlb.mesh.repair_surface`; ignored for a :class:`SurfaceMesh`); default
        ``"none"``: :func:`dhlb.mesh.validate_surface`, every defect an error.

    Returns
    -------
    TangentBundle
        ``.bundle`` (HermitianLineBundle), ``.geometry`` (EuclideanComplex), frames, rescaled angles.

    Raises
    ------
    InvalidParameterError
        Both a :class:`SurfaceMesh` and ``F`` are given, or an array ``V`` without ``F``; or ``n``
        is not an integer >= 1.
    DhlbError
        The errors of :func:`~dhlb.mesh.validate_surface` on a bad mesh (``ShapeError``,
        ``InvalidSimplexError``, ``NonManifoldError``, ``NonOrientableError``, ...).

    Examples
    --------
    >>> from dhlb.io import read_surface, example_path
    >>> from dhlb.mesh import tangent_bundle
    >>> tb = tangent_bundle(*read_surface(example_path("torus.obj")), n=2)
    >>> tb.bundle.degree(), tb.mesh.euler_characteristic
    (0, 0)
    """
    if isinstance(V, SurfaceMesh):
        if F is not None:
            raise InvalidParameterError("pass either a SurfaceMesh or the arrays (V, F), not both")
        return TangentBundle(V, n)
    if F is None:
        raise InvalidParameterError("tangent_bundle needs the face array F (or a SurfaceMesh as V)")
    return TangentBundle(repair_surface(V, F, repair, reorient=reorient, components=components), n)
