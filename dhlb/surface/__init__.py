"""Layer 5 application: n-direction fields on triangle surfaces (seed part 1).

:func:`validate_surface` checks a mesh, :func:`tangent_bundle` builds the n-th power of its
discrete tangent bundle (a :class:`~dhlb.bundles.HermitianLineBundle` with geometry, frames and
rescaled angles), :mod:`.guidance` gives alignment fields and :mod:`.directions` turns a section
into 3D directions and singularities.
"""

from dhlb.surface.mesh import SurfaceMesh, validate_surface
from dhlb.surface.tangent import TangentBundle, tangent_bundle

__all__ = ["SurfaceMesh", "validate_surface", "TangentBundle", "tangent_bundle"]
