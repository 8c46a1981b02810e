"""Meshes: the one place that validates and describes triangle and tetrahedral meshes.

Everything an application needs of its mesh comes from here, with the argument order ``(V, F)`` for
surfaces and ``(V, T)`` for tetrahedral meshes (libigl, gpytoolbox):

* surfaces: :func:`validate_surface` → :class:`SurfaceMesh` (half-edge tables, vertex fans, boundary),
  its discrete tangent bundle :func:`tangent_bundle` → :class:`TangentBundle`; the meshes people have
  (non-manifold, doubled, degenerate) repaired and mapped back to the input by :func:`repair_surface`
  (:mod:`dhlb.mesh.repair`);
* tetrahedral meshes: :func:`check_tet_mesh` → :class:`TetMesh` (validated, positively oriented),
  generators :func:`box_tet_mesh`, :func:`ball_tet_mesh`, and :mod:`dhlb.mesh.tetgen` (any closed
  surface through fTetWild, optional);
* what every application calls first: :func:`as_surface`, :func:`as_tangent_bundle`, :func:`as_tet_mesh`
  (arrays or a mesh object → a validated mesh);
* arrays: :func:`mesh_complex` (the complex of ``(V, cells)`` with the input orientation),
  :func:`compact_mesh` (drop unreferenced vertices), :func:`signed_volumes`;
* distributed assembly (:mod:`dhlb.mesh.partition`): :func:`partition_vertices` (METIS),
  :func:`vertex_layout`, the local meshes :func:`surface_part`, :func:`tet_part` (→ :class:`MeshPart`),
  a box's slab built alone :func:`box_tet_part`, and :func:`owned_rows`; under MPI
  :mod:`dhlb.mesh.distribute` (rank 0 validates and partitions, every rank gets its part).

Examples
--------
>>> from dhlb.mesh import box_tet_mesh, validate_surface
>>> validate_surface([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]]).n_faces
1
>>> box_tet_mesh(2).complex.counts
(27, 98, 120, 48)
"""

import lazy_loader as _lazy

# Lazy (SPEC 1, as the top-level package): ``from dhlb.mesh.compact import compact_mesh`` in a reader
# does not load the surface, tet and topology machinery.
_ATTRS = {
    "arrays": ["MeshComplex", "mesh_arrays", "mesh_complex"],
    "coerce": ["as_surface", "as_tangent_bundle", "as_tet_mesh"],
    "compact": ["compact_mesh"],
    "repair": ["MeshRepair", "RepairOptions", "repair_surface"],
    "partition": ["MeshPart", "VertexLayout", "box_tet_part", "owned_rows", "partition_vertices", "surface_part",
                  "tet_part", "vertex_layout"],
    "surface": ["SurfaceMesh", "validate_surface"],
    "tangent": ["TangentBundle", "tangent_bundle"],
    "tet": ["TetMesh", "ball_tet_mesh", "box_tet_mesh", "check_tet_mesh", "signed_volumes"],
}
__getattr__, __dir__, _ = _lazy.attach(__name__, submodules=[], submod_attrs=_ATTRS)

__all__ = [
    "SurfaceMesh", "validate_surface", "TangentBundle", "tangent_bundle",
    "TetMesh", "check_tet_mesh", "box_tet_mesh", "ball_tet_mesh", "signed_volumes",
    "MeshComplex", "mesh_complex", "mesh_arrays", "compact_mesh",
    "as_surface", "as_tangent_bundle", "as_tet_mesh",
    "repair_surface", "RepairOptions", "MeshRepair",
    "partition_vertices", "vertex_layout", "VertexLayout", "surface_part", "tet_part", "MeshPart", "owned_rows",
    "box_tet_part",
]
