"""Vortex filaments in 3-D velocity fields (seed part 3 §2.3; Weißmann, Pinkall, Schröder 2014).

Work in progress: tetrahedral meshes, velocity 1-forms, filament extraction and linking numbers.
"""
from dhlb.volume.meshes import TetMesh, ball_tet_mesh, box_tet_mesh, check_tet_mesh, signed_volumes

__all__ = ["TetMesh", "ball_tet_mesh", "box_tet_mesh", "check_tet_mesh", "signed_volumes"]
