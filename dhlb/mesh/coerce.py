"""What every application calls first: a mesh object from whatever the user passed (arrays or a mesh).

:func:`as_surface` and :func:`as_tangent_bundle` accept ``(V, F)`` arrays, a :class:`SurfaceMesh` or a
:class:`TangentBundle`; :func:`as_tet_mesh` accepts ``(V, T)`` arrays or a :class:`TetMesh`. Arrays are
validated (:func:`validate_surface`, :func:`check_tet_mesh`); a mesh object is used as it is (it was
validated when it was made). Passing a mesh object *and* a cell array is an error, never a silent choice.

Examples
--------
>>> from dhlb.mesh import as_surface, as_tet_mesh, box_tet_mesh
>>> mesh = as_surface([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
>>> as_surface(mesh) is mesh, as_tet_mesh(box_tet_mesh(1)).tets.shape
(True, (6, 4))
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from dhlb._coerce import check_int
from dhlb.errors import InvalidParameterError
from dhlb.mesh.repair import repair_surface
from dhlb.mesh.surface import SurfaceMesh
from dhlb.mesh.tangent import TangentBundle, tangent_bundle
from dhlb.mesh.tet import TetMesh, check_tet_mesh

if TYPE_CHECKING:
    from typing import Any

    from numpy.typing import ArrayLike

__all__ = ["as_surface", "as_tangent_bundle", "as_tet_mesh"]


def _both(what: str, cells: str, caller: str) -> InvalidParameterError:
    return InvalidParameterError(f"{caller}: pass either a {what} as V (and {cells}=None) or the arrays V and {cells}, "
                                 "not both")


def as_surface(V: ArrayLike | SurfaceMesh | TangentBundle, F: ArrayLike | None = None, *, reorient: bool = False,
               components: str = "all", repair: Any = "none", caller: str = "dhlb") -> SurfaceMesh:
    """The validated surface mesh of ``(V, F)``, or ``V`` itself when it is a mesh (or a tangent bundle's mesh).

    Parameters
    ----------
    V : (n, 3) float array, SurfaceMesh or TangentBundle
        Vertex positions, or a mesh made before.
    F : (m, 3) int array, optional
        Triangles (rows of ``V``); None when ``V`` is a mesh.
    reorient, components, repair
        As for :func:`validate_surface` (arrays only).
    caller : str
        The public function on whose behalf this runs (named in error messages).

    Returns
    -------
    SurfaceMesh
        The validated, consistently oriented mesh.

    Raises
    ------
    InvalidParameterError
        A mesh object and ``F`` both given, or arrays without ``F``.
    ShapeError, InvalidSimplexError, NonManifoldError, NonFiniteError
        Invalid arrays (see :func:`validate_surface`).
    """
    if isinstance(V, TangentBundle):
        V = V.mesh
    if isinstance(V, SurfaceMesh):
        if F is not None:
            raise _both("SurfaceMesh (or TangentBundle)", "F", caller)
        return V
    if F is None:
        raise InvalidParameterError(f"{caller} needs the face array F (or a SurfaceMesh as V)")
    return repair_surface(V, F, repair, reorient=reorient, components=components)   # "none": validate_surface


def as_tangent_bundle(V: ArrayLike | SurfaceMesh | TangentBundle, F: ArrayLike | None = None, n: int | None = None,
                      *, reorient: bool = False, components: str = "all", repair: Any = "none",
                      caller: str = "dhlb") -> TangentBundle:
    """The n-th power of the tangent bundle of ``(V, F)``, of a :class:`SurfaceMesh`, or a given bundle.

    Parameters
    ----------
    V : (n, 3) float array, SurfaceMesh or TangentBundle
        Vertex positions, or a mesh / bundle made before.
    F : (m, 3) int array, optional
        Triangles; None when ``V`` is a mesh or bundle.
    n : int, optional
        The power (symmetry of the field); default 1, or that of a given bundle. A bundle of another
        power is rebuilt on the same mesh.
    reorient, components, repair
        As for :func:`validate_surface` (arrays only).
    caller : str
        The public function on whose behalf this runs (named in error messages).

    Returns
    -------
    TangentBundle

    Raises
    ------
    InvalidParameterError
        A mesh object and ``F`` both given, or arrays without ``F``; a bad ``n``.
    ShapeError, InvalidSimplexError, NonManifoldError, NonFiniteError
        Invalid arrays (see :func:`validate_surface`).
    """
    if isinstance(V, TangentBundle):
        if F is not None:
            raise _both("TangentBundle", "F", caller)
        return V if n is None or (check_int(n, "n (the number of directions)", 1) == V.n) else TangentBundle(V.mesh, n)
    mesh = as_surface(V, F, reorient=reorient, components=components, repair=repair, caller=caller)
    return tangent_bundle(mesh, None, 1 if n is None else n)


def as_tet_mesh(V: ArrayLike | TetMesh, T: ArrayLike | None = None, *, orientation: str = "fix",
                caller: str = "dhlb") -> TetMesh:
    """The validated, positively oriented tet mesh of ``(V, T)``, or ``V`` itself when it is a :class:`TetMesh`.

    Parameters
    ----------
    V : (n, 3) float array or TetMesh
        Vertex positions, or a mesh made before.
    T : (m, 4) int array, optional
        Tetrahedra (rows of ``V``); None when ``V`` is a mesh.
    orientation : {"fix", "require"}
        As for :func:`check_tet_mesh` (arrays only).
    caller : str
        The public function on whose behalf this runs (named in error messages).

    Returns
    -------
    TetMesh

    Raises
    ------
    InvalidParameterError
        A mesh and ``T`` both given, or arrays without ``T``.
    ShapeError, InvalidSimplexError, NonManifoldError, NonFiniteError, DegenerateSimplexError
        Invalid arrays (see :func:`check_tet_mesh`).
    """
    if isinstance(V, TetMesh):
        if T is not None:
            raise _both("TetMesh", "T", caller)
        return V
    if T is None:
        raise InvalidParameterError(f"{caller} needs the tetrahedra T (or a TetMesh as V)")
    return check_tet_mesh(V, T, orientation=orientation)
