"""n-direction fields on triangle surfaces (seed part 1): an application of the engine.

A field is a section of the n-th power of the tangent bundle of a surface mesh (:mod:`dhlb.mesh`
builds the bundle); this package gives the energies (:mod:`.energy`, Theorem 15 with the
holomorphic/anti-holomorphic split ``E_s``), the alignment fields (:mod:`.guidance`: principal curvature
via the discrete Hopf differential, the boundary, user vectors), the smoothest or aligned field
(:func:`direction_field`), fields with prescribed singularities (:func:`prescribed_field`) and the
reading of a section as 3D directions, indices and singularities (:mod:`.directions`).

Examples
--------
>>> import numpy as np
>>> from dhlb.io import read_surface, example_path
>>> from dhlb.mesh import tangent_bundle
>>> from dhlb.fields import field_indices
>>> tb = tangent_bundle(*read_surface(example_path("torus.obj")), n=4)
>>> u = np.exp(1j * np.arange(tb.mesh.n_vertices))      # any nowhere-vanishing section
>>> field_indices(tb, u).total                            # Poincaré–Hopf: n χ = 0
0
"""

from dhlb.fields.directions import FieldIndices, Singularities, direction_vectors, field_indices, section_values
from dhlb.fields.energy import boundary_form, energy_matrices
from dhlb.fields.field import direction_field, guidance_for
from dhlb.fields.guidance import (
    Guidance,
    boundary_guidance,
    curvature_guidance,
    dihedral_angles,
    hopf_differential,
    user_guidance,
)
from dhlb.fields.options import FieldOptions
from dhlb.fields.prescribed import locate_faces, prescribed_field
from dhlb.fields.result import DirectionField, PrescribedField

__all__ = [
    "Guidance", "boundary_guidance", "curvature_guidance", "dihedral_angles", "hopf_differential", "user_guidance",
    "FieldIndices", "Singularities", "direction_vectors", "field_indices", "section_values",
    "energy_matrices", "boundary_form", "DirectionField", "direction_field", "guidance_for", "FieldOptions",
    "PrescribedField", "prescribed_field", "locate_faces",
]
