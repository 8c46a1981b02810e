"""Vortex filaments of 3-D velocity fields (seed part 3 §2.3; Weißmann, Pinkall, Schröder 2014).

* on tetrahedral meshes of :mod:`dhlb.mesh` (:func:`~dhlb.mesh.box_tet_mesh`, :func:`~dhlb.mesh.ball_tet_mesh`,
  :func:`~dhlb.mesh.check_tet_mesh`)
* velocity → 1-form → bundle: :func:`edge_circulation`, :func:`velocity_bundle`
* demo fields and curves: :class:`FilamentField` (regularized Biot–Savart), :func:`uniform_flow`,
  :func:`superpose`, :func:`vortex_ring`, :func:`hopf_link`, :func:`torus_knot`, :func:`trefoil`
* filaments of a section: :func:`extract_filaments` → :class:`FilamentSet` of :class:`Filament`
* filaments of a partitioned mesh: :func:`filament_pieces` per part → :class:`FilamentPieces` of
  :class:`FilamentPiece`, joined by :func:`stitch_pieces`
* curve topology: :func:`linking_number`, :func:`linking_matrix`, :func:`hausdorff_distance`
* the whole pipeline: :func:`vortex_filaments` → :class:`VortexResult`

Examples
--------
>>> import numpy as np
>>> from dhlb.mesh import box_tet_mesh
>>> from dhlb.vortex import hopf_link, linking_number
>>> box_tet_mesh(2).complex.counts
(27, 98, 120, 48)
>>> linking_number(*hopf_link(n=32))
1
"""
from dhlb.vortex.curves import hopf_link, torus_knot, trefoil, vortex_ring
from dhlb.vortex.filaments import Filament, FilamentSet, extract_filaments, face_zeros
from dhlb.vortex.flows import FilamentField, segment_velocity, superpose, uniform_flow
from dhlb.vortex.linking import (
                                 gauss_linking_integral,
                                 hausdorff_distance,
                                 linking_matrix,
                                 linking_number,
                                 polyline_distance,
)
from dhlb.vortex.options import VortexOptions
from dhlb.vortex.pipeline import VortexResult, filament_linking_numbers, vortex_filaments
from dhlb.vortex.stitch import FilamentPiece, FilamentPieces, filament_pieces, stitch_pieces
from dhlb.vortex.velocity import edge_circulation, gauss_legendre, velocity_bundle

__all__ = [
    "edge_circulation", "gauss_legendre", "velocity_bundle",
    "FilamentField", "segment_velocity", "superpose", "uniform_flow",
    "hopf_link", "torus_knot", "trefoil", "vortex_ring",
    "Filament", "FilamentSet", "extract_filaments", "face_zeros",
    "FilamentPiece", "FilamentPieces", "filament_pieces", "stitch_pieces",
    "gauss_linking_integral", "hausdorff_distance", "linking_matrix", "linking_number", "polyline_distance",
    "VortexResult", "VortexOptions", "filament_linking_numbers", "vortex_filaments",
]
