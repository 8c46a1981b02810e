"""Deprecated alias package (dhlb 0.2; removed in 0.3).

n-direction fields moved to :mod:`dhlb.fields`, surface meshes and their tangent bundle to :mod:`dhlb.mesh`,
``stripe_pattern`` to :mod:`dhlb.stripes`.
"""

from dhlb._deprecation import moved_package

_MESH = ["SurfaceMesh", "validate_surface", "TangentBundle", "tangent_bundle"]
_FIELDS = ["Guidance", "boundary_guidance", "curvature_guidance", "dihedral_angles", "hopf_differential",
           "user_guidance", "FieldIndices", "Singularities", "direction_vectors", "field_indices", "section_values",
           "energy_matrices", "boundary_form", "DirectionField", "direction_field", "guidance_for",
           "PrescribedField", "prescribed_field", "locate_faces"]
__getattr__, __dir__ = moved_package(__name__, {**dict.fromkeys(_MESH, "dhlb.mesh"),
                                                **dict.fromkeys(_FIELDS, "dhlb.fields"),
                                                "stripe_pattern": "dhlb.stripes"})
