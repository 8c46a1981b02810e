"""Deprecated: complexes from mesh arrays moved to :mod:`dhlb.mesh` with the ``(V, cells)`` argument order.

``surface(F, V)`` is :func:`dhlb.mesh.mesh_complex` ``(V, F, dim=2)``, ``tet_mesh(T, V)`` is
``mesh_complex(V, T, dim=3)``; ``MeshComplex`` is :class:`dhlb.mesh.MeshComplex`.
"""

import importlib

from dhlb._deprecation import moved_module, warn_moved

__getattr__, __dir__ = moved_module(__name__, "dhlb.mesh.arrays")


def surface(F, V=None):
    """Deprecated: use ``dhlb.mesh.mesh_complex(V, F)``.

    Parameters
    ----------
    F : (m, 3) int array
        Triangles.
    V : (n, d) float array, optional
        Vertex coordinates.

    Returns
    -------
    MeshComplex
        As :func:`dhlb.mesh.mesh_complex`.
    """
    warn_moved("dhlb.examples.surface(F, V)", "dhlb.mesh.mesh_complex(V, F)")
    return importlib.import_module("dhlb.mesh.arrays").mesh_complex(V, F, dim=2)


def tet_mesh(T, V=None):
    """Deprecated: use ``dhlb.mesh.mesh_complex(V, T)``.

    Parameters
    ----------
    T : (m, 4) int array
        Tetrahedra.
    V : (n, d) float array, optional
        Vertex coordinates.

    Returns
    -------
    MeshComplex
        As :func:`dhlb.mesh.mesh_complex`.
    """
    warn_moved("dhlb.examples.tet_mesh(T, V)", "dhlb.mesh.mesh_complex(V, T)")
    return importlib.import_module("dhlb.mesh.arrays").mesh_complex(V, T, dim=3)
