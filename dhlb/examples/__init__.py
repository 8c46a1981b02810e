"""Named simplicial complexes with documented triangulations.

Every function returns a :class:`dhlb.SimplicialComplex` (optionally with vertex coordinates)
whose triangulation, vertex labelling and source are stated in its docstring.

* spheres and balls: :func:`sphere`, :func:`ball`, :func:`simplex`
* surfaces: :func:`torus`, :func:`klein_bottle`, :func:`projective_plane`,
  :func:`moebius_strip`, and the (non-manifold) :func:`dunce_hat`
* grids in any dimension: :func:`cube_nd`, :func:`torus_nd` (Freudenthal–Kuhn)
* quotients of spheres: :func:`lens_space`, :func:`projective_space`
* constructions: :func:`product` (shuffle triangulation), :func:`join`, :func:`cone`,
  :func:`suspension`
* the one exception, arrays instead of a complex: :func:`fingerprint_pad` (vertex positions,
  triangles and the core / delta singularities of a loop fingerprint, seed part 2, Fig. 5)
* (deprecated) ``surface(F, V)``, ``tet_mesh(T, V)``, ``MeshComplex``: now
  :func:`dhlb.mesh.mesh_complex` ``(V, cells)``

Examples
--------
>>> from dhlb import examples
>>> [examples.sphere(2).euler_characteristic, examples.torus().euler_characteristic,
...  examples.projective_plane().euler_characteristic]
[2, 0, 1]
"""

from dhlb.examples.basic import ball, cone, join, simplex, sphere, suspension
from dhlb.examples.fingerprint import fingerprint_pad
from dhlb.examples.grids import cube_nd, torus_nd
from dhlb.examples.products import product
from dhlb.examples.quotients import lens_space, projective_space
from dhlb.examples.surfaces import dunce_hat, klein_bottle, moebius_strip, projective_plane, torus

__all__ = [
    "simplex",
    "ball",
    "sphere",
    "join",
    "cone",
    "suspension",
    "torus",
    "klein_bottle",
    "projective_plane",
    "moebius_strip",
    "dunce_hat",
    "cube_nd",
    "torus_nd",
    "lens_space",
    "projective_space",
    "product",
    "fingerprint_pad",
]


def __getattr__(name):
    # deprecated: mesh arrays moved to dhlb.mesh (argument order (V, cells)); see dhlb.examples.meshes
    if name in ("surface", "tet_mesh", "MeshComplex"):
        from dhlb.examples import meshes

        return getattr(meshes, name)
    raise AttributeError(f"module 'dhlb.examples' has no attribute {name!r}")
