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
    OverwriteError
        ``path`` (or a file written beside it) is a file the result was read from.
    """
    from dhlb._files import refuse_overwrite

    out = os.fspath(path)
    stem, ext = os.path.splitext(out)
    side = [stem + ".json"] if ext.lower() == ".obj" else []   # a stripe OBJ brings its sidecar
    refuse_overwrite([out, *side], getattr(result, "_read_from", ()), role="a file this result was read from")
    return _write(result, path)


@functools.singledispatch
def _write(result, path) -> list[str]:
    """:func:`write` by the kind of result (one registered function per kind)."""
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


@_write.register
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


@_write.register
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


@_write.register
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


@_write.register
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

    Every array is checked before it is used (kind, shape, range of the indices, finiteness where a
    value must be finite, the frames unit tangent vectors of the mesh, the vertex rows the rows the
    mask ``vertex_used`` marks), and so are the values of ``OUT.json`` that are used.

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
        The files do not hold a field (an empty, truncated or damaged archive, pickled objects, a
        missing key, a wrong dtype or shape, an index out of range, a non-finite value, frames or rows
        that do not fit the mesh), or disagree with each other; the message names the file and the key.

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

    from dhlb.errors import DhlbError, MeshParseError, UnreferencedVertexWarning
    from dhlb.io._text import check_array, load_npz, output_stem
    from dhlb.mesh import tangent_bundle, validate_surface

    base = output_stem(path)
    npz, ply, side = base + ".npz", base + ".ply", base + ".json"
    if not os.path.isfile(npz):
        raise InvalidParameterError(f"{base}: no field file {npz} (a field PLY alone holds the directions, not "
                                    "the section: read the .npz written beside it)")
    data = load_npz(npz)
    missing = [k for k in ("u", "directions", "frames", "vertex_rows") if k not in data]
    if missing:
        raise MeshParseError(f"not a field file of dhlb: no {', '.join(missing)}", npz)
    n_in, n = _check_field_arrays(data, npz)
    summary = _field_summary(side, n) if os.path.isfile(side) else {}
    if "mesh_u" in data:   # a repaired mesh: rebuilt from its parts, the section per mesh vertex
        return _read_repaired_field(data, summary, npz, n)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UnreferencedVertexWarning)  # the input PLY keeps unused rows
        if "mesh_points" in data or "mesh_faces" in data:
            P, F = _check_mesh_arrays(data, npz)
            try:
                mesh = validate_surface(P, F)
            except DhlbError as exc:
                raise MeshParseError(f"mesh_points and mesh_faces are not a valid surface ({exc})", npz) from None
        elif os.path.isfile(ply):
            from dhlb.io.ply import read_ply

            V, F = read_ply(ply)
            try:
                mesh = validate_surface(V, F)
            except DhlbError as exc:
                raise MeshParseError(f"not the mesh of the field {npz} ({exc})", ply) from None
        else:
            raise MeshParseError(f"holds no mesh (written by an older dhlb) and {ply} is missing", npz)
    _check_summary_mesh(summary, side, mesh)
    rows = check_array(data["vertex_rows"], npz, "vertex_rows", kind="i", shape=(mesh.n_vertices,),
                       bounds=(0, n_in - 1, f"rows of u, which has {n_in}"),
                       dims=f"({mesh.n_vertices},): one row per vertex of the mesh")
    seen = np.zeros(n_in, bool)
    seen[rows] = True
    if int(seen.sum()) != rows.size:
        first = int(rows[np.flatnonzero(np.bincount(rows, minlength=n_in)[rows] > 1)[0]])
        raise MeshParseError(f"vertex_rows names row {first} twice (one row per vertex of a mesh that was not "
                             "repaired)", npz)
    if "vertex_used" in data:
        used = check_array(data["vertex_used"], npz, "vertex_used", kind="b", shape=(n_in,))
        if not np.array_equal(used, seen):
            r = int(np.flatnonzero(used != seen)[0])
            raise MeshParseError(f"vertex_rows and vertex_used disagree on row {r} (vertex_used[{r}] = "
                                 f"{bool(used[r])}, but vertex_rows {'does not name' if used[r] else 'names'} it)",
                                 npz)
    u = _finite_rows(data["u"], rows, npz, "u", np.complex128)
    X = _finite_rows(data["frames"][:, 0], rows, npz, "frames", np.float64)
    tb = tangent_bundle(mesh, n=n)
    theta = _frame_angles(X, tb, npz, "frames", rows)
    return _field_from(tb, u * np.exp(1j * n * theta), data, summary)


def _check_field_arrays(data: dict, npz: str) -> tuple[int, int]:
    """Check the arrays of a field ``.npz`` that are in the input numbering; ``(rows of V, n)``."""
    from dhlb.errors import MeshParseError
    from dhlb.io._text import check_array, check_number

    u = check_array(data["u"], npz, "u", kind="c", shape=(None,), dims="(n,): one value per row of the input V")
    n_in = u.shape[0]
    D = check_array(data["directions"], npz, "directions", shape=(n_in, None, 3),
                    dims=f"({n_in}, n, 3): n directions per row of u")
    check_array(data["frames"], npz, "frames", shape=(n_in, None, 3), dims=f"({n_in}, 3, 3): a frame per row of u")
    if data["frames"].shape[1] == 0 or D.shape[1] == 0:
        raise MeshParseError(f"frames and directions need at least one vector per row, got shapes "
                             f"{data['frames'].shape} and {D.shape}", npz)
    n = D.shape[1]
    if "n" in data:
        n_file = check_number(data["n"], npz, "n", integer=True, low=1)
        if n_file != n:
            raise MeshParseError(f"n = {n_file}, but directions holds {n} directions per vertex", npz)
    for key in ("s", "lam"):
        if key in data:
            check_number(data[key], npz, key)
    faces = None
    if "face_index" in data:
        faces = check_array(data["face_index"], npz, "face_index", kind="i", shape=(None,)).size
    if "singular_faces" in data:
        sf = check_array(data["singular_faces"], npz, "singular_faces", kind="i", shape=(None,),
                         bounds=(0, None if faces is None else faces - 1, f"rows of face_index, which has {faces}"))
        k = sf.size
        if "singular_index" in data:
            check_array(data["singular_index"], npz, "singular_index", kind="i", shape=(k,),
                        dims=f"({k},): one per singular face")
        if "singular_points" in data:
            check_array(data["singular_points"], npz, "singular_points", shape=(k, 3), finite=True,
                        dims=f"({k}, 3): one per singular face")
    return n_in, n


def _check_mesh_arrays(data: dict, npz: str):
    """``mesh_points`` and ``mesh_faces`` of a field ``.npz``, checked (kinds, shapes, finite, index range)."""
    from dhlb.errors import MeshParseError
    from dhlb.io._text import check_array

    for key in ("mesh_points", "mesh_faces"):
        if key not in data:
            raise MeshParseError(f"has no {key} (mesh_points and mesh_faces come together)", npz)
    P = check_array(data["mesh_points"], npz, "mesh_points", shape=(None, 3), finite=True)
    F = check_array(data["mesh_faces"], npz, "mesh_faces", kind="i", shape=(None, 3), bounds=(0, len(P) - 1,
                    f"rows of mesh_points, which has {len(P)}"))
    return P, F


def _finite_rows(values, rows, npz: str, key: str, dtype) -> np.ndarray:
    """``values[rows]`` (rows of the input V used by the mesh), which must be finite."""
    from dhlb.errors import MeshParseError

    out = np.asarray(values, dtype)[rows]
    bad = ~np.isfinite(out).reshape(len(out), -1).all(axis=1)
    if bad.any():
        i = int(np.argmax(bad))
        raise MeshParseError(f"{key}[{int(rows[i])}] is not finite, but row {int(rows[i])} belongs to vertex {i} "
                             "of the mesh (only unused rows hold NaN)", npz)
    return out


def _frame_angles(X, tb, npz: str, key: str, rows=None) -> np.ndarray:
    """The angle of each written frame vector ``X`` in the frames of ``tb``; ``X`` must be unit tangent vectors."""
    from dhlb.errors import MeshParseError

    c0 = np.einsum("ij,ij->i", X, tb.frames[:, 0])
    c1 = np.einsum("ij,ij->i", X, tb.frames[:, 1])
    norm = np.einsum("ij,ij->i", X, X)
    bad = (np.abs(norm - 1.0) > 1e-6) | (np.abs(c0 * c0 + c1 * c1 - 1.0) > 1e-6)
    if bad.any():
        i = int(np.argmax(bad))
        row = i if rows is None else int(rows[i])
        what = "not a unit vector" if abs(norm[i] - 1.0) > 1e-6 else "not tangent to the mesh there"
        raise MeshParseError(f"{key}[{row}, 0] (the frame of vertex {i}) is {what}: the frames do not fit the mesh",
                             npz)
    return np.arctan2(c1, c0)


def _field_summary(side: str, n: int) -> dict:
    """The values of a field's ``OUT.json`` that :func:`read_field` uses, checked (types; ``n`` as in the npz)."""
    from dhlb.errors import MeshParseError
    from dhlb.io._text import check_json_type, check_number, read_json

    summary = read_json(side)
    for key in ("energy", "eigenvalue", "t", "s", "lambda"):
        if key in summary:
            check_number(summary[key], side, key, optional=True, finite=False)
    for key in ("solver", "timings"):
        if key in summary:
            check_json_type(summary[key], (dict, type(None)), side, key)
    if "n" in summary and check_number(summary["n"], side, "n", integer=True) != n:
        raise MeshParseError(f"n = {summary['n']}, but the field .npz beside it has n = {n}: the files are of "
                             "different runs", side)
    return summary


def _check_summary_mesh(summary: dict, side: str, mesh) -> None:
    """The counts of a field's ``OUT.json`` against the mesh of its ``.npz`` (files of different runs)."""
    from dhlb.errors import MeshParseError
    from dhlb.io._text import check_number

    for key, have in (("n_vertices", mesh.n_vertices), ("n_faces", mesh.n_faces)):
        if key in summary and check_number(summary[key], side, key, integer=True) != have:
            raise MeshParseError(f"{key} = {summary[key]}, but the mesh of the field .npz beside it has {have}: "
                                 "the files are of different runs", side)


def _field_from(tb, u, data, summary) -> DirectionField:
    from dhlb.fields import direction_vectors, field_indices

    n = tb.n
    s, lam = (float(data[k]) if k in data else float(np.nan if summary.get(j) is None else summary[j])
              for k, j in (("s", "s"), ("lam", "lambda")))
    energy = summary.get("energy")
    return DirectionField(n=n, s=s, lam=lam, tangent=tb, u=u, directions=direction_vectors(tb, u),
                          indices=field_indices(tb, u), energy=float("nan") if energy is None else float(energy),
                          eigenvalue=summary.get("eigenvalue"), t=summary.get("t"), guidance=None,
                          solver=dict(summary.get("solver") or {}), timings=dict(summary.get("timings") or {}))


def _read_repaired_field(data: dict, summary: dict, npz: str, n: int) -> DirectionField:
    """The field of a ``.npz`` whose mesh was repaired: the mesh from its parts, ``u`` per mesh vertex."""
    import json

    from dhlb.errors import DhlbError, MeshParseError
    from dhlb.io._text import check_array, check_number, check_repairs
    from dhlb.mesh import tangent_bundle
    from dhlb.mesh.repair import MeshRepair, repaired_mesh

    needed = ("mesh_points", "mesh_faces", "face_rows", "mesh_frames", "vertex_of_input", "face_of_input",
              "repair_options", "repairs")
    missing = [k for k in needed if k not in data]
    if missing:
        raise MeshParseError(f"a repaired field without {', '.join(missing)}", npz)
    n_in = data["u"].shape[0]
    P, F = _check_mesh_arrays(data, npz)
    N, M = len(P), len(F)
    rows = check_array(data["vertex_rows"], npz, "vertex_rows", kind="i", shape=(N,), bounds=(0, n_in - 1,
                       f"rows of u, which has {n_in}"), dims=f"({N},): one row per row of mesh_points")
    voi = check_array(data["vertex_of_input"], npz, "vertex_of_input", kind="i", shape=(n_in,), bounds=(-1, N - 1,
                      f"-1 or a row of mesh_points, which has {N}"), dims=f"({n_in},): one per row of u")
    m_in = M if "face_index" not in data else data["face_index"].shape[0]
    foi = check_array(data["face_of_input"], npz, "face_of_input", kind="i", shape=(m_in,), bounds=(-1, M - 1,
                      f"-1 or a row of mesh_faces, which has {M}"), dims=f"({m_in},): one per row of face_index")
    face_rows = check_array(data["face_rows"], npz, "face_rows", kind="i", shape=(M,), bounds=(0, m_in - 1,
                            f"rows of face_of_input, which has {m_in}"), dims=f"({M},): one per row of mesh_faces")
    lost = np.flatnonzero(voi[rows] < 0)
    if lost.size:
        v = int(lost[0])
        raise MeshParseError(f"vertex_rows[{v}] = {int(rows[v])}, but vertex_of_input[{int(rows[v])}] = -1 (that "
                             "row has no vertex of the mesh): vertex_rows and vertex_of_input disagree", npz)
    if "vertex_used" in data:
        used = check_array(data["vertex_used"], npz, "vertex_used", kind="b", shape=(n_in,))
        if not np.array_equal(used, voi >= 0):
            r = int(np.flatnonzero(used != (voi >= 0))[0])
            raise MeshParseError(f"vertex_used[{r}] = {bool(used[r])} disagrees with vertex_of_input[{r}] = "
                                 f"{int(voi[r])}", npz)
    for key in ("repairs", "repair_options"):
        if data[key].shape != () or data[key].dtype.kind != "U":
            raise MeshParseError(f"{key} must be a text (a 0-d string array), got a {data[key].dtype} array of "
                                 f"shape {data[key].shape}", npz)
    try:
        items = json.loads(str(data["repairs"]))
    except (ValueError, RecursionError) as exc:
        raise MeshParseError(f"repairs is not readable JSON ({exc})", npz) from None
    check_repairs(items, npz, "repairs")
    delta = check_number(data["repair_delta"], npz, "repair_delta", low=0.0) if "repair_delta" in data else 0.0
    lengths = flipped = None
    if "mesh_edge_lengths" in data:
        lengths = check_array(data["mesh_edge_lengths"], npz, "mesh_edge_lengths", shape=(None,), finite=True)
        if lengths.size and lengths.min() <= 0:
            i = int(np.argmin(lengths))
            raise MeshParseError(f"mesh_edge_lengths[{i}] = {float(lengths[i])!r} is not a positive length", npz)
    if "mesh_flipped" in data:
        flipped = check_array(data["mesh_flipped"], npz, "mesh_flipped", kind="b", shape=(M,),
                              dims=f"({M},): one per row of mesh_faces")
    u_mesh = check_array(data["mesh_u"], npz, "mesh_u", kind="c", shape=(N,), finite=True,
                         dims=f"({N},): one value per row of mesh_points")
    X = check_array(data["mesh_frames"], npz, "mesh_frames", shape=(N, None, 3), finite=True,
                    dims=f"({N}, 3, 3): a frame per row of mesh_points")
    if X.shape[1] == 0:
        raise MeshParseError(f"mesh_frames needs at least one vector per vertex, got shape {X.shape}", npz)
    arrays = {"repairs": data["repairs"], "repair_options": data["repair_options"], "repair_delta": delta,
              "vertex_of_input": voi, "face_of_input": foi}
    try:
        info = MeshRepair.from_arrays(arrays, rows)
        mesh = repaired_mesh(P, F, face_rows, info, lengths, flipped)
    except (DhlbError, ValueError, TypeError) as exc:
        raise MeshParseError(f"the repaired mesh cannot be rebuilt ({exc})", npz) from None
    _check_summary_mesh(summary, os.path.splitext(npz)[0] + ".json", mesh)
    tb = tangent_bundle(mesh, n=n)
    theta = _frame_angles(X[:, 0], tb, npz, "mesh_frames")
    return _field_from(tb, u_mesh * np.exp(1j * n * theta), data, summary)


def _kind(path: str) -> str:
    """``"field"``, ``"stripes"``, ``"vortex"`` or ``"conformal"``: what the files at ``path`` hold."""
    from dhlb.errors import MeshParseError
    from dhlb.io._text import OUTPUT_EXTENSIONS, npz_keys, output_stem, read_json

    base = output_stem(path)
    ext = os.path.splitext(os.fspath(path))[1].lower() if base != os.fspath(path) else ""
    if ext in (".vtu",):
        raise InvalidParameterError(f"{path}: ParaView files are not read back; open the output base "
                                    f"{base} (its .npz, .obj, .json or .mesh)")
    if ext and ext != ".png" and not os.path.isfile(path):
        raise InvalidParameterError(f"{path}: no such file")
    side = read_json(base + ".json") if os.path.isfile(base + ".json") else {}
    if ext in ("", ".png", ".json", ".npz") and os.path.isfile(base + ".npz"):
        keys = npz_keys(base + ".npz")
        if "directions" in keys:
            return "field"
        if "tets" in keys:
            return "conformal"
        if ext == ".npz":
            raise MeshParseError(f"an .npz archive of {', '.join(sorted(keys)) or 'no arrays'}: not a field "
                                 "(directions, u, ...) nor a conformal deformation (points, tets, ...) of dhlb", path)
    if side.get("format") == "dhlb-stripes":
        return "stripes"
    if "filaments" in side:
        return "vortex"
    stats = side.get("statistics")
    if ("points" in side and "tets" in side) or (isinstance(stats, dict) and "distortion_mean" in stats):
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
    from dhlb._result import mark_read_from
    from dhlb.io._text import OUTPUT_EXTENSIONS, output_stem

    result = _read_kind(path, _kind(path))
    base = output_stem(path)   # save() and to_html() never write over the files it was read from
    mark_read_from(result, [os.fspath(path)] + [base + e for e in OUTPUT_EXTENSIONS if os.path.isfile(base + e)])
    return result


def _read_kind(path, kind: str):
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
