"""Results as files: :func:`write` (the extension chooses the format) and the field files of ``dhlb field``.

:meth:`Result.save <dhlb._result.Result.save>` comes here. Every result writes ``.json`` (its
``to_json()``); beyond that, by kind:

=========================  =============================================================================
DirectionField             ``.npz`` (:func:`write_field_npz`), ``.vtu`` (ParaView), ``.ply`` (mesh + directions)
StripePattern              ``.obj`` (per-corner texture coordinates + ``.json`` sidecar), ``.vtu``
VortexResult               ``.obj`` / ``.ply`` (the filaments as polylines), ``.vtu`` (domain + filaments)
ConformalResult            ``.npz``, ``.mesh`` / ``.msh`` / ``.vtk`` (the deformed tets), ``.vtu`` (ParaView)
=========================  =============================================================================

Every file is written atomically (a temporary name beside the target, renamed at the end).

Examples
--------
>>> import json, os, tempfile
>>> from dhlb.mesh import box_tet_mesh
>>> from dhlb.vortex import uniform_flow, vortex_filaments
>>> res = vortex_filaments(box_tet_mesh(2), None, uniform_flow([0.1, 0, 0]), hbar=1.0)
>>> with tempfile.TemporaryDirectory() as d:
...     [path] = write(res, os.path.join(d, "v.json"))
...     sorted(json.load(open(path)))[:3]
['eigenvalue', 'filaments', 'linking_index']
"""

from __future__ import annotations

import functools
import json
import os

import numpy as np

from dhlb._files import atomic_write
from dhlb.conformal.result import ConformalResult
from dhlb.errors import InvalidParameterError
from dhlb.fields.result import DirectionField
from dhlb.stripes.result import StripePattern
from dhlb.vortex.result import VortexResult

__all__ = ["FIELD_NPZ_NOTE", "write", "write_field_files", "write_field_npz", "write_json"]

FIELD_NPZ_NOTE = ("u, directions, frames, vertex_used: one row per row of the input V; rows with vertex_used == False "
                  "belong to vertices that no face uses and hold NaN. face_index: one entry per row of the input F. "
                  "vertex_rows: the input rows of the mesh's vertices. singular_*: faces (input rows), indices "
                  "(of the n-th power field) and points of the singularities.")


def write_json(result, path: str | os.PathLike[str]) -> str:
    """Write ``result.to_json()`` as a JSON file (standard JSON: no NaN or infinity).

    Parameters
    ----------
    result : Result
        Any result of the applications.
    path : str or path-like
        The file to write (atomically).

    Returns
    -------
    str
        ``path``.

    Raises
    ------
    OutputError
        The file cannot be written.
    """
    out = os.fspath(path)
    with atomic_write(out, "w", encoding="utf-8") as fh:
        json.dump(result.to_json(), fh, indent=1)
    return out


def _unknown(result, path: str, known: tuple[str, ...]):
    ext = os.path.splitext(path)[1].lower()
    raise InvalidParameterError(f"cannot save a {type(result).__name__} as {ext or 'a file without extension'!r} "
                                f"({path}); use {', '.join(known)}")


@functools.singledispatch
def write(result, path: str | os.PathLike[str]) -> list[str]:
    """Write a result to ``path``, in the format of its extension (see the table of the module).

    Parameters
    ----------
    result : DirectionField, StripePattern, VortexResult or ConformalResult
        What to write.
    path : str or path-like
        The file; its extension chooses the format.

    Returns
    -------
    list of str
        The paths written (a stripe OBJ brings its ``.json`` sidecar, a vortex ``.vtu`` its filaments).

    Raises
    ------
    InvalidParameterError
        An extension this kind of result cannot be written as (the message lists those it can), or an
        object that is no result.
    OutputError
        A file cannot be written.
    """
    raise InvalidParameterError(f"cannot save a {type(result).__name__}: dhlb.io.results.write takes a result of "
                                "dhlb.fields, dhlb.stripes, dhlb.vortex or dhlb.conformal")


def write_field_npz(path: str | os.PathLike[str], res: DirectionField) -> str:
    """Write a direction field as ``.npz``, in the input numbering, with the unreferenced-vertex mask and a note.

    Keys ``u``, ``directions``, ``frames``, ``vertex_used`` (one row per row of the input ``V``; NaN rows for
    vertices no face uses), ``face_index`` (one entry per row of the input ``F``), ``vertex_rows``,
    ``singular_faces``, ``singular_index``, ``singular_points`` and ``note`` (:data:`FIELD_NPZ_NOTE`, so
    that the file documents itself).

    Parameters
    ----------
    path : str or path-like
        The ``.npz`` to write (atomically).
    res : DirectionField
        The field.

    Returns
    -------
    str
        ``path``.

    Raises
    ------
    OutputError
        The file cannot be written.

    Examples
    --------
    >>> import os, tempfile, warnings, numpy as np
    >>> from dhlb.fields import direction_field
    >>> V = np.array([[1.0, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1], [5, 5, 5]])
    >>> F = [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]]
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("ignore")
    ...     res = direction_field(V, F, n=1)
    >>> with tempfile.TemporaryDirectory() as d:
    ...     data = dict(np.load(write_field_npz(os.path.join(d, "f.npz"), res)))
    >>> data["vertex_used"].tolist()[-2:], bool(np.isnan(data["directions"][6]).all()), "NaN" in str(data["note"])
    ([True, False], True, True)
    """
    mesh, sing = res.mesh, res.singularities
    out = os.fspath(path)
    with atomic_write(out, "wb") as fh:
        np.savez_compressed(
            fh, u=mesh.to_input(res.u, fill=np.nan + 0j), directions=res.input_directions(),
            frames=mesh.to_input(res.frames), face_index=res.input_face_index(), singular_faces=sing.input_faces,
            singular_index=sing.index, singular_points=sing.points, vertex_rows=mesh.vertex_labels,
            vertex_used=mesh.input_vertex_used, note=np.array(FIELD_NPZ_NOTE))
    return out


def _field_ply(path: str, res: DirectionField, V=None, F=None) -> str:
    from dhlb.io.ply import write_ply

    mesh = res.mesh
    if V is None:
        V, F, D, used = mesh.points, mesh.faces, res.directions, np.ones(mesh.n_vertices, bool)
    else:
        D, used = res.input_directions(), mesh.input_vertex_used
    props = {f"d{k}{c}": np.where(used, D[:, k, i], 0.0) for k in range(res.n) for i, c in enumerate("xyz")}
    write_ply(path, V, F, binary=True, vertex_properties=props)
    return path


def write_field_files(out: str, res: DirectionField, V, F) -> dict[str, str]:
    """The files of ``dhlb field -o OUT``: ``OUT.ply`` (the input mesh + directions) and ``OUT.npz``.

    Parameters
    ----------
    out : str
        The base path (without extension).
    res : DirectionField
        The field.
    V : (n, 3) float array
        The input vertices (the PLY keeps the input numbering, unreferenced rows included).
    F : (m, 3) int array
        The input faces.

    Returns
    -------
    dict
        ``{"ply": OUT.ply, "npz": OUT.npz, "json": OUT.json}`` (the JSON is the caller's to write).

    Raises
    ------
    OutputError
        A file cannot be written.

    Examples
    --------
    >>> import os, tempfile
    >>> from dhlb.io import read_surface, example_path
    >>> from dhlb.fields import direction_field
    >>> V, F = read_surface(example_path("torus.obj"))
    >>> with tempfile.TemporaryDirectory() as d:
    ...     paths = write_field_files(os.path.join(d, "t"), direction_field(V, F, n=2), V, F)
    ...     sorted(os.path.basename(p) for p in paths.values() if os.path.exists(p))
    ['t.npz', 't.ply']
    """
    paths = {"ply": out + ".ply", "npz": out + ".npz", "json": out + ".json"}
    _field_ply(paths["ply"], res, V, F)
    write_field_npz(paths["npz"], res)
    return paths


@write.register
def _(result: DirectionField, path) -> list[str]:
    out = os.fspath(path)
    ext = os.path.splitext(out)[1].lower()
    if ext == ".json":
        return [write_json(result, out)]
    if ext == ".npz":
        return [write_field_npz(out, result)]
    if ext == ".ply":
        return [_field_ply(out, result)]
    if ext == ".vtu":
        from dhlb.io.paraview import field_to_vtu

        return [field_to_vtu(result, out)]
    return _unknown(result, out, (".json", ".npz", ".ply", ".vtu"))


@write.register
def _(result: StripePattern, path) -> list[str]:
    out = os.fspath(path)
    ext = os.path.splitext(out)[1].lower()
    if ext == ".json":
        return [write_json(result, out)]
    if ext == ".obj":
        from dhlb.io.stripes import write_stripes_obj

        return [p for p in write_stripes_obj(out, result.texture) if p]
    if ext == ".vtu":
        from dhlb.io.paraview import stripes_to_vtu

        return [stripes_to_vtu(result, out)]
    return _unknown(result, out, (".json", ".obj", ".vtu"))


@write.register
def _(result: VortexResult, path) -> list[str]:
    out = os.fspath(path)
    ext = os.path.splitext(out)[1].lower()
    if ext == ".json":
        return [write_json(result, out)]
    if ext in (".obj", ".ply"):
        from dhlb.io.polylines import write_polylines_obj, write_polylines_ply

        return [(write_polylines_ply if ext == ".ply" else write_polylines_obj)(out, result.filaments)]
    if ext == ".vtu":
        from dhlb.io.paraview import vortex_to_vtu

        return list(vortex_to_vtu(result, out))
    return _unknown(result, out, (".json", ".obj", ".ply", ".vtu"))


@write.register
def _(result: ConformalResult, path) -> list[str]:
    out = os.fspath(path)
    ext = os.path.splitext(out)[1].lower()
    if ext == ".json":
        with atomic_write(out, "w") as fh:
            json.dump(result.to_json(), fh)
    elif ext == ".npz":
        with atomic_write(out, "wb") as fh:
            np.savez(fh, points=result.points, tets=result.mesh.tets, phi=result.phi, u=result.u,
                     distortion=result.distortion, scale_error=result.scale_error, eigenvalue=result.eigenvalue)
    elif ext in (".mesh", ".msh", ".vtk"):
        from dhlb.io.volume import write_volume

        write_volume(out, result.points, result.mesh.tets)
    elif ext == ".vtu":  # ParaView: the deformed tets with φ, u and the input points; distortion per tet
        from dhlb.io.meshio_bridge import write_vtu_volume

        write_vtu_volume(out, result.points, result.mesh.tets,
                         point_data={"phi": result.phi, "u": result.u, "input_points": result.mesh.points},
                         cell_data={"distortion": result.distortion, "scale_error": result.scale_error},
                         field_data={"eigenvalue": [float(result.eigenvalue)]})
    else:
        _unknown(result, out, (".json", ".npz", ".mesh", ".msh", ".vtk", ".vtu (ParaView, meshio)"))
    return [out]
