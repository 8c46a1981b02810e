"""Results as files: :func:`write` (the extension chooses the format), :func:`read_result`, the field files.

:meth:`Result.save <dhlb._result.Result.save>` comes here. Every result writes ``.json`` (its
``to_json()``); beyond that, by kind:

=========================  =============================================================================
DirectionField             ``.npz`` (:func:`write_field_npz`), ``.vtu`` (ParaView), ``.ply`` (mesh + directions)
StripePattern              ``.obj`` (per-corner texture coordinates + ``.json`` sidecar), ``.vtu``
VortexResult               ``.obj`` / ``.ply`` (the filaments as polylines), ``.vtu`` (domain + filaments)
ConformalResult            ``.npz``, ``.mesh`` / ``.msh`` / ``.vtk`` (the deformed tets), ``.vtu`` (ParaView)
=========================  =============================================================================

Every file is written atomically (a temporary name beside the target, renamed at the end).

:func:`read_result` reads back what any command, :func:`write` or ``dhlb demo`` wrote, one loader per
kind in the io module of that kind: :func:`read_field` (here; a :class:`~dhlb.fields.DirectionField`),
:func:`dhlb.io.stripes.read_stripes`, :func:`dhlb.io.polylines.read_vortex` and
:func:`dhlb.io.volume.read_conformal` (light results with the attributes the pictures and the viewer use).

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
import re

import numpy as np

from dhlb._files import atomic_write
from dhlb.conformal.result import ConformalResult
from dhlb.errors import InvalidParameterError
from dhlb.fields.result import DirectionField
from dhlb.stripes.result import StripePattern
from dhlb.vortex.result import VortexResult

__all__ = ["FIELD_NPZ_NOTE", "read_field", "read_result", "write", "write_field_files", "write_field_npz",
           "write_json"]

FIELD_NPZ_NOTE = ("u, directions, frames, vertex_used: one row per row of the input V; rows with vertex_used == False "
                  "belong to vertices that no face uses and hold NaN. face_index: one entry per row of the input F. "
                  "vertex_rows: the input rows of the mesh's vertices. singular_*: faces (input rows), indices "
                  "(of the n-th power field) and points of the singularities. mesh_points, mesh_faces: the "
                  "validated mesh (its own numbering: vertex_rows and face_rows map its rows to the input's). "
                  "n, s, lam: the symmetry, the energy parameter and lambda. repairs: the repairs made to the "
                  "input mesh (JSON, '[]' if none); for a repaired mesh also vertex_of_input, face_of_input (the "
                  "mesh vertex and face that give each input row its value, -1 for none), mesh_u and mesh_frames "
                  "(per mesh vertex: copies of a split vertex each have their own) and, for a mollified mesh, "
                  "mesh_edge_lengths (its intrinsic metric, per edge of the mesh).")


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
    ``singular_faces``, ``singular_index``, ``singular_points``, the mesh ``mesh_points``, ``mesh_faces``,
    ``face_rows`` (so that :func:`read_field` needs no other file), ``n``, ``s``, ``lam`` and ``note``
    (:data:`FIELD_NPZ_NOTE`, so that the file documents itself).

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
    extra = {"repairs": np.array("[]")}
    if mesh.repair is not None:
        extra = dict(mesh.repair.to_arrays(), mesh_u=res.u, mesh_frames=res.frames, mesh_flipped=mesh.flipped)
        if mesh.edge_lengths is not None:
            extra["mesh_edge_lengths"] = mesh.edge_lengths
    with atomic_write(out, "wb") as fh:
        np.savez_compressed(
            fh, u=mesh.to_input(res.u, fill=np.nan + 0j), directions=res.input_directions(),
            frames=mesh.to_input(res.frames), face_index=res.input_face_index(), singular_faces=sing.input_faces,
            singular_index=sing.index, singular_points=sing.points, vertex_rows=mesh.vertex_rows,
            vertex_used=mesh.input_vertex_used, mesh_points=mesh.points, mesh_faces=mesh.faces,
            face_rows=mesh.face_rows, n=np.int64(res.n), s=np.float64(res.s), lam=np.float64(res.lam),
            note=np.array(FIELD_NPZ_NOTE), **extra)
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
    elif ext == ".npz":  # with the input points: dhlb.io.read_result draws the mesh before and after
        with atomic_write(out, "wb") as fh:
            np.savez(fh, points=result.points, tets=result.mesh.tets, phi=result.phi, u=result.u,
                     distortion=result.distortion, scale_error=result.scale_error, eigenvalue=result.eigenvalue,
                     input_points=result.mesh.points)
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


# ---------------------------------------------------------------------------- reading back
def read_field(path: str | os.PathLike[str]) -> DirectionField:
    """Read back a direction field: ``OUT.npz`` (``dhlb field``, ``dhlb demo``, :func:`write_field_npz`).

    The section ``u`` of the file is put into the frames of the rebuilt tangent bundle and the indices
    are recomputed from it (:func:`dhlb.fields.field_indices`), so the field is the one that was written.
    ``OUT.json`` beside it, when there, supplies the energy, eigenvalue, solver report and timings (NaN
    / None otherwise). A file written before the npz held its mesh needs ``OUT.ply`` beside it.

    Parameters
    ----------
    path : str or path-like
        ``OUT.npz``, ``OUT.ply``, ``OUT.json`` or the output base ``OUT``.

    Returns
    -------
    DirectionField

    Raises
    ------
    InvalidParameterError
        There is no ``OUT.npz`` (a field PLY alone holds the directions, not the section).
    MeshParseError
        The files do not hold a field, or disagree with each other.

    Examples
    --------
    >>> import os, tempfile
    >>> from dhlb.io import read_surface, example_path
    >>> from dhlb.fields import direction_field
    >>> res = direction_field(*read_surface(example_path("torus.obj")), n=4)
    >>> with tempfile.TemporaryDirectory() as d:
    ...     back = read_field(write_field_npz(os.path.join(d, "t.npz"), res))
    >>> back.n, back.index_sum, bool(abs(back.directions - res.directions).max() < 1e-12)
    (4, 0, True)
    """
    import warnings

    from dhlb.errors import MeshParseError, UnreferencedVertexWarning
    from dhlb.io._text import output_stem, read_json
    from dhlb.mesh import tangent_bundle, validate_surface

    base = output_stem(path)
    npz, ply, side = base + ".npz", base + ".ply", base + ".json"
    if not os.path.isfile(npz):
        raise InvalidParameterError(f"{base}: no field file {npz} (a field PLY alone holds the directions, not "
                                    "the section: read the .npz written beside it)")
    try:
        with np.load(npz, allow_pickle=False) as z:
            data = {k: z[k] for k in z.files}
    except (OSError, ValueError) as exc:
        raise MeshParseError(f"not a readable .npz ({exc})", npz) from None
    missing = [k for k in ("u", "directions", "frames", "vertex_rows") if k not in data]
    if missing:
        raise MeshParseError(f"not a field file of dhlb: no {', '.join(missing)}", npz)
    summary = read_json(side) if os.path.isfile(side) else {}
    if "mesh_u" in data:   # a repaired mesh: rebuilt from its parts, the section per mesh vertex
        return _read_repaired_field(data, summary, npz)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UnreferencedVertexWarning)  # the input PLY keeps unused rows
        if "mesh_points" in data:
            mesh = validate_surface(data["mesh_points"], data["mesh_faces"])
        elif os.path.isfile(ply):
            from dhlb.io.ply import read_ply

            mesh = validate_surface(*read_ply(ply))
        else:
            raise MeshParseError(f"holds no mesh (written by an older dhlb) and {ply} is missing", npz)
    rows = np.asarray(data["vertex_rows"], np.int64)
    if rows.shape != (mesh.n_vertices,) or (rows.size and rows.max() >= len(data["u"])):
        raise MeshParseError(f"vertex_rows does not fit the mesh ({mesh.n_vertices} vertices)", npz)
    n = int(data["n"]) if "n" in data else int(data["directions"].shape[1])
    tb = tangent_bundle(mesh, n=n)
    X = np.asarray(data["frames"], np.float64)[rows, 0]  # the written frame X_i, at angle θ_i in the new frame
    theta = np.arctan2(np.einsum("ij,ij->i", X, tb.frames[:, 1]), np.einsum("ij,ij->i", X, tb.frames[:, 0]))
    return _field_from(tb, np.asarray(data["u"], np.complex128)[rows] * np.exp(1j * n * theta), data, summary)


def _field_from(tb, u, data, summary) -> DirectionField:
    from dhlb.fields import direction_vectors, field_indices

    n = tb.n
    s = float(data["s"]) if "s" in data else float(summary.get("s", np.nan))
    lam = float(data["lam"]) if "lam" in data else float(summary.get("lambda", np.nan))
    energy = summary.get("energy")
    return DirectionField(n=n, s=s, lam=lam, tangent=tb, u=u, directions=direction_vectors(tb, u),
                          indices=field_indices(tb, u), energy=float("nan") if energy is None else float(energy),
                          eigenvalue=summary.get("eigenvalue"), t=summary.get("t"), guidance=None,
                          solver=dict(summary.get("solver") or {}), timings=dict(summary.get("timings") or {}))


def _read_repaired_field(data: dict, summary: dict, npz: str) -> DirectionField:
    """The field of a ``.npz`` whose mesh was repaired: the mesh from its parts, ``u`` per mesh vertex."""
    from dhlb.errors import DhlbError, MeshParseError
    from dhlb.mesh import tangent_bundle
    from dhlb.mesh.repair import MeshRepair, repaired_mesh

    needed = ("mesh_points", "mesh_faces", "face_rows", "mesh_frames", "vertex_of_input", "face_of_input",
              "repair_options")
    missing = [k for k in needed if k not in data]
    if missing:
        raise MeshParseError(f"a repaired field without {', '.join(missing)}", npz)
    try:
        info = MeshRepair.from_arrays(data, np.asarray(data["vertex_rows"], np.int64))
        mesh = repaired_mesh(data["mesh_points"], data["mesh_faces"], data["face_rows"], info,
                             data.get("mesh_edge_lengths"), data.get("mesh_flipped"))
    except (DhlbError, ValueError) as exc:
        raise MeshParseError(f"the repaired mesh cannot be rebuilt ({exc})", npz) from None
    u_mesh = np.asarray(data["mesh_u"], np.complex128)
    X = np.asarray(data["mesh_frames"], np.float64)
    if u_mesh.shape != (mesh.n_vertices,) or X.shape[:2] != (mesh.n_vertices, 3):
        raise MeshParseError(f"mesh_u / mesh_frames do not fit the mesh ({mesh.n_vertices} vertices)", npz)
    n = int(data["n"]) if "n" in data else int(data["directions"].shape[1])
    tb = tangent_bundle(mesh, n=n)
    theta = np.arctan2(np.einsum("ij,ij->i", X[:, 0], tb.frames[:, 1]), np.einsum("ij,ij->i", X[:, 0], tb.frames[:, 0]))
    return _field_from(tb, u_mesh * np.exp(1j * n * theta), data, summary)


def _kind(path: str) -> str:
    """``"field"``, ``"stripes"``, ``"vortex"`` or ``"conformal"``: what the files at ``path`` hold."""
    from dhlb.io._text import OUTPUT_EXTENSIONS, output_stem, read_json

    base = output_stem(path)
    ext = os.path.splitext(os.fspath(path))[1].lower() if base != os.fspath(path) else ""
    if ext in (".vtu",):
        raise InvalidParameterError(f"{path}: ParaView files are not read back; open the output base "
                                    f"{base} (its .npz, .obj, .json or .mesh)")
    if ext and ext != ".png" and not os.path.isfile(path):
        raise InvalidParameterError(f"{path}: no such file")
    side = read_json(base + ".json") if os.path.isfile(base + ".json") else {}
    if ext in ("", ".png", ".json", ".npz") and os.path.isfile(base + ".npz"):
        with np.load(base + ".npz", allow_pickle=False) as z:
            keys = set(z.files)
        if "directions" in keys:
            return "field"
        if "tets" in keys:
            return "conformal"
    if side.get("format") == "dhlb-stripes":
        return "stripes"
    if "filaments" in side:
        return "vortex"
    if ("points" in side and "tets" in side) or "distortion_mean" in (side.get("statistics") or {}):
        return "conformal"
    if "singularities" in side and "index_sum" in side:
        return "field"
    for e in (ext,) if ext not in ("", ".png", ".json") else (".obj", ".ply", ".mesh", ".vtk", ".msh"):
        p = base + e
        if not os.path.isfile(p):
            continue
        with open(p, "rb") as fh:
            head = fh.read() if e == ".obj" else fh.read(4096)  # an OBJ's 'l' records come after its vertices
        if e == ".obj" and re.search(rb"^l ", head, re.M):
            return "vortex"
        if e == ".ply" and b"element edge" in head:
            return "vortex"
        if e == ".ply" and (b"property double d0x" in head or b"property float d0x" in head):
            return "field"
    found = sorted(os.path.basename(base) + e for e in OUTPUT_EXTENSIONS if os.path.isfile(base + e))
    raise InvalidParameterError(
        f"{path}: found no output of dhlb field (OUT.npz), stripes (OUT.obj + OUT.json), vortex (OUT.obj, OUT.ply "
        f"or OUT.json of filaments) or conformal (OUT.npz, OUT.json + OUT.mesh)"
        + (f"; there is {', '.join(found)}" if found else ""))


def read_result(path: str | os.PathLike[str]):
    """Read back any output of the commands, of :func:`write` or of ``dhlb demo``, by kind.

    ==========  ==========================================  ==============================================
    kind        files                                       returns
    ==========  ==========================================  ==============================================
    field       ``OUT.npz`` (+ ``OUT.json``, ``OUT.ply``)   :class:`~dhlb.fields.DirectionField`
    stripes     ``OUT.obj`` + ``OUT.json`` (sidecar)        :class:`~dhlb.io.stripes.LoadedStripes`
    vortex      ``OUT.json``, ``OUT.obj`` or ``OUT.ply``    :class:`~dhlb.io.polylines.LoadedVortex`
    conformal   ``OUT.npz``, ``OUT.json`` (+ ``OUT.mesh``)  :class:`~dhlb.io.volume.LoadedConformal`
    ==========  ==========================================  ==============================================

    The light results carry the attributes the pictures (:func:`dhlb.render.registry.picture`) and the
    viewer (:func:`dhlb.render.view.scene_of`) use, so a result read back draws as the one in memory.

    Parameters
    ----------
    path : str or path-like
        One of the files, or the output base ``OUT`` (a ``.png`` of the output names its base too).

    Returns
    -------
    DirectionField, LoadedStripes, LoadedVortex or LoadedConformal

    Raises
    ------
    InvalidParameterError
        No output of dhlb at ``path`` (the message names the files that are there), or a ParaView file.
    MeshParseError
        The files cannot be read.

    Examples
    --------
    >>> import os, tempfile
    >>> from dhlb.mesh import box_tet_mesh
    >>> from dhlb.vortex import FilamentField, vortex_filaments, vortex_ring
    >>> ring = FilamentField([vortex_ring(0.5, center=(0.51, 0.5, 0.49), n=48)], core_radius=0.1)
    >>> res = vortex_filaments(box_tet_mesh(6), None, ring, hbar=1.0)
    >>> with tempfile.TemporaryDirectory() as d:
    ...     _ = write(res, os.path.join(d, "v.json"))
    ...     back = read_result(os.path.join(d, "v"))
    >>> type(back).__name__, len(back.filaments) == len(res.filaments)
    ('LoadedVortex', True)
    """
    path = os.fspath(path)
    if os.path.isdir(path):
        from dhlb.io._text import OUTPUT_EXTENSIONS

        bases = sorted({os.path.splitext(f)[0] for f in os.listdir(path)
                        if os.path.splitext(f)[1].lower() in OUTPUT_EXTENSIONS[:-1]})
        raise InvalidParameterError(f"{path} is a folder: give one output in it"
                                    + (f" ({', '.join(bases[:8])}{' ...' if len(bases) > 8 else ''})"
                                       if bases else ""))
    kind = _kind(path)
    if kind == "field":
        return read_field(path)
    if kind == "stripes":
        from dhlb.io.stripes import read_stripes

        return read_stripes(path)
    if kind == "vortex":
        from dhlb.io.polylines import read_vortex

        return read_vortex(path)
    from dhlb.io.volume import read_conformal

    return read_conformal(path)
