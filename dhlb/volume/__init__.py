"""Vortex filaments of 3-D velocity fields (seed part 3 §2.3; Weißmann, Pinkall, Schröder 2014).

* tetrahedral meshes: :func:`check_tet_mesh` (validate, orient), :func:`box_tet_mesh`,
  :func:`ball_tet_mesh`; :mod:`dhlb.volume.tetgen` wraps fTetWild (optional, ``dhlb[tet]``)
* velocity → 1-form → bundle: :func:`edge_circulation`, :func:`velocity_bundle`
* demo fields and curves: :class:`FilamentField` (regularized Biot–Savart), :func:`uniform_flow`,
  :func:`superpose`, :func:`vortex_ring`, :func:`hopf_link`, :func:`torus_knot`, :func:`trefoil`
* filaments of a section: :func:`extract_filaments` → :class:`FilamentSet` of :class:`Filament`
* curve topology: :func:`linking_number`, :func:`linking_matrix`, :func:`hausdorff_distance`
* the whole pipeline: :func:`vortex_filaments` → :class:`VortexResult`

Examples
--------
>>> import numpy as np
>>> from dhlb.volume import box_tet_mesh, hopf_link, linking_number
>>> box_tet_mesh(2).complex.counts
(27, 98, 120, 48)
>>> linking_number(*hopf_link(n=32))
1
"""
from dhlb.volume.curves import hopf_link, torus_knot, trefoil, vortex_ring
from dhlb.volume.fields import FilamentField, segment_velocity, superpose, uniform_flow
from dhlb.volume.filaments import Filament, FilamentSet, extract_filaments, face_zeros
from dhlb.volume.linking import (
                                 gauss_linking_integral,
                                 hausdorff_distance,
                                 linking_matrix,
                                 linking_number,
                                 polyline_distance,
)
from dhlb.volume.meshes import TetMesh, ball_tet_mesh, box_tet_mesh, check_tet_mesh, signed_volumes
from dhlb.volume.velocity import edge_circulation, gauss_legendre, velocity_bundle
from dhlb.volume.vortex import VortexResult, filament_linking_numbers, vortex_filaments

__all__ = [
    "TetMesh", "ball_tet_mesh", "box_tet_mesh", "check_tet_mesh", "signed_volumes",
    "edge_circulation", "gauss_legendre", "velocity_bundle",
    "FilamentField", "segment_velocity", "superpose", "uniform_flow",
    "hopf_link", "torus_knot", "trefoil", "vortex_ring",
    "Filament", "FilamentSet", "extract_filaments", "face_zeros",
    "gauss_linking_integral", "hausdorff_distance", "linking_matrix", "linking_number", "polyline_distance",
    "VortexResult", "filament_linking_numbers", "vortex_filaments",
]
