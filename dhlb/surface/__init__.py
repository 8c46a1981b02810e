"""Layer 5 application: n-direction fields on triangle surfaces (seed part 1).

:func:`validate_surface` checks a mesh, :func:`tangent_bundle` builds the n-th power of its
discrete tangent bundle (a :class:`~dhlb.bundles.HermitianLineBundle` with geometry, frames and
rescaled angles), :mod:`.guidance` gives alignment fields (principal curvature via the discrete
Hopf differential, the boundary, user vectors) and :mod:`.directions` turns a section into 3D
directions, indices and singularities.

Examples
--------
>>> import numpy as np
>>> from dhlb.io import read_surface, example_path
>>> from dhlb.surface import tangent_bundle, field_indices
>>> tb = tangent_bundle(*read_surface(example_path("torus.obj")), n=4)
>>> u = np.exp(1j * np.arange(tb.mesh.n_vertices))      # any nowhere-vanishing section
>>> field_indices(tb, u).total                            # Poincaré–Hopf: n χ = 0
0
"""

from dhlb.surface.directions import FieldIndices, Singularities, direction_vectors, field_indices, section_values
from dhlb.surface.energy import boundary_form, energy_matrices
from dhlb.surface.field import direction_field, guidance_for
from dhlb.surface.guidance import (
    Guidance,
    boundary_guidance,
    curvature_guidance,
    dihedral_angles,
    hopf_differential,
    user_guidance,
)
from dhlb.surface.mesh import SurfaceMesh, validate_surface
from dhlb.surface.prescribed import locate_faces, prescribed_field
from dhlb.surface.result import DirectionField, PrescribedField
from dhlb.surface.tangent import TangentBundle, tangent_bundle

__all__ = [
    "SurfaceMesh", "validate_surface", "TangentBundle", "tangent_bundle",
    "Guidance", "boundary_guidance", "curvature_guidance", "dihedral_angles", "hopf_differential", "user_guidance",
    "FieldIndices", "Singularities", "direction_vectors", "field_indices", "section_values",
    "energy_matrices", "boundary_form", "DirectionField", "direction_field", "guidance_for", "stripe_pattern",
    "PrescribedField", "prescribed_field", "locate_faces",
]


def __getattr__(name):
    # ``dhlb.surface.stripe_pattern`` (the name) lives in the stripes application, which
    # itself builds on this package: import it lazily to keep the import graph acyclic.
    if name == "stripe_pattern":
        from dhlb.stripes.pattern import stripe_pattern

        return stripe_pattern
    raise AttributeError(f"module 'dhlb.surface' has no attribute {name!r}")
