"""Deprecated alias package (dhlb 0.2; removed in 0.3).

Vortex filaments moved to :mod:`dhlb.vortex`, tetrahedral meshes to :mod:`dhlb.mesh`.
"""

from dhlb._deprecation import moved_package

_MESH = ["TetMesh", "ball_tet_mesh", "box_tet_mesh", "check_tet_mesh", "signed_volumes"]
_VORTEX = ["edge_circulation", "gauss_legendre", "velocity_bundle", "FilamentField", "segment_velocity", "superpose",
           "uniform_flow", "hopf_link", "torus_knot", "trefoil", "vortex_ring", "Filament", "FilamentSet",
           "extract_filaments", "face_zeros", "gauss_linking_integral", "hausdorff_distance", "linking_matrix",
           "linking_number", "polyline_distance", "VortexResult", "filament_linking_numbers", "vortex_filaments"]
__getattr__, __dir__ = moved_package(__name__, {**dict.fromkeys(_MESH, "dhlb.mesh"),
                                                **dict.fromkeys(_VORTEX, "dhlb.vortex")})
