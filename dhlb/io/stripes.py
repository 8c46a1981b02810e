"""Stripe patterns as files: OBJ with per-corner texture coordinates and a JSON sidecar; :func:`read_stripes`.

**OBJ** (``write_stripes_obj``): the mesh vertices (compact order, ``v``), one texture coordinate
per face corner ``vt u 0`` with ``u = α'/2π`` (:attr:`StripeTexture.corner_alpha`, the linear
part), and the faces ``f a/ta b/tb c/tc`` in the order and orientation of ``mesh.faces``. Any
renderer that draws ``g(2π u)`` for an even 2π-periodic g (e.g. ``cos``) shows the pattern
correctly on every face except zero and branch faces, which the sidecar describes:

* ``zeros``: face rows (0-based OBJ faces), index n and the zero's position (the barycenter).
  Add ``lArg_n(t)/2π`` (Eq. 4.2; :func:`dhlb.stripes.larg`) to the interpolated u at barycentric
  point t of the face.
* ``branch``: face rows, ``u_m = β_m/2π`` and ``u_l = β_l/2π``. Draw the face as the three cones
  ``(m, i, j)``, ``(m, j, k)``, ``(m, k, i)`` from its barycenter m with u values
  ``(u_m, u_i, u_j)``, ``(u_m, u_j, u_k)``, ``(u_m, u_k, u_l)``.

With ``expand=r`` (r >= 1) the OBJ itself contains the subdivision of
:meth:`StripeTexture.subdivision`: branch faces become their three cones (exact) and zero faces
an ``r × r`` grid per cone (the zero's vertex gets one texture coordinate per adjacent
sub-triangle), so a plain linear-UV renderer is enough; ``obj_face_of`` in the sidecar maps each
OBJ face to its face of the mesh.

Examples
--------
>>> import json, os, tempfile, numpy as np
>>> from dhlb.mesh import validate_surface
>>> from dhlb.io.stripes import write_stripes_obj
>>> from dhlb.stripes import stripe_form, texture_coordinates
>>> V = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]
>>> form = stripe_form(validate_surface(V, [[0, 1, 2], [1, 3, 2]]), np.tile([1.0, 0, 0], (4, 1)), frequency=0.25)
>>> tex = texture_coordinates(form, np.exp(0.5j * np.pi * np.array(V)[:, 0]))
>>> with tempfile.TemporaryDirectory() as d:
...     obj, side = write_stripes_obj(os.path.join(d, "s.obj"), tex)
...     lines = open(obj).read().splitlines()
...     meta = json.load(open(side))
>>> [l for l in lines if l.startswith("vt")][:2], lines[-1], meta["n"], meta["branch"]["faces"]
(['vt 0 0', 'vt 0.25 0'], 'f 2/4 4/5 3/6', 1, [])
"""

from __future__ import annotations

import io
import json
import os
from typing import TYPE_CHECKING

import numpy as np

from dhlb._coerce import check_int
from dhlb._result import Result
from dhlb.stripes.texture import StripeTexture

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["BYTES_PER_OBJ_SUBTRIANGLE", "LoadedStripes", "read_stripes", "stripes_sidecar", "write_stripes_obj"]

TWO_PI = 2.0 * np.pi

_INTERPOLATION = (
    "u = alpha/(2 pi) per face corner, linear part. Regular faces: u(t) = sum_c t_c u_c. Zero faces: "
    "u(t) = sum_c t_c u_c + lArg_n(t)/(2 pi), lArg_n(t) = 2 pi n/3 (c + (t_{c+1} - t_{c+2})/(1 - 3 t_{c+2})) where "
    "t_{c+2} is the smallest barycentric coordinate (Eq. 4.2). Branch faces: linear on the cones (m,i,j), (m,j,k), "
    "(m,k,i) with u values (u_m,u_i,u_j), (u_m,u_j,u_k), (u_m,u_k,u_l). Draw g(2 pi u) with g even and "
    "2pi-periodic (e.g. cos) for line fields (n = 2); any 2pi-periodic g for n = 1.")


def stripes_sidecar(
    texture: StripeTexture, *, obj_name: str | None = None, obj_face_of: ArrayLike | None = None
) -> dict:
    """The JSON-serializable description of zero and branch faces (see the module docstring).

    Parameters
    ----------
    texture : StripeTexture
        The texture coordinates of the pattern.
    obj_name : str, optional
        The name of the OBJ file it describes (stored as ``"obj"``).
    obj_face_of : (k,) int array, optional
        For an expanded OBJ: the face of the mesh of each OBJ face (stored as ``"obj_face_of"``).

    Returns
    -------
    dict
        ``format``, ``version``, ``obj``, ``n``, ``n_vertices``, ``n_faces``, ``vertex_labels``,
        ``face_rows``, ``frequency`` (min, max, mean), ``interpolation`` (how to draw the pattern),
        ``zeros`` (faces, index, points), ``branch`` (faces, ``u_m``, ``u_l``, points) and ``repairs``
        (what :mod:`dhlb.mesh.repair` did to the input mesh, ``[]`` if nothing); for a repaired mesh also
        ``vertex_rows`` (the input row of each OBJ vertex) and, when it was mollified, ``edge_lengths``
        (its intrinsic metric, per edge of the mesh); lists and numbers only.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import validate_surface
    >>> from dhlb.stripes import stripe_form, texture_coordinates
    >>> V = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]
    >>> mesh = validate_surface(V, [[0, 1, 2], [1, 3, 2]])
    >>> form = stripe_form(mesh, np.tile([1.0, 0, 0], (4, 1)), frequency=0.25)
    >>> tex = texture_coordinates(form, np.exp(0.5j * np.pi * np.array(V)[:, 0]))   # ψ = exp(i ν x), ν = 2π/4
    >>> from dhlb.io.stripes import stripes_sidecar
    >>> side = stripes_sidecar(tex, obj_name="square.obj")
    >>> side["format"], side["n"], side["n_faces"], side["zeros"]["faces"], side["branch"]["faces"]
    ('dhlb-stripes', 1, 2, [], [])
    """
    mesh = texture.mesh
    zf, bf = texture.zero_faces, texture.branch_faces
    out = {
        "format": "dhlb-stripes",
        "version": 1,
        "obj": obj_name,
        "n": int(texture.form.n),
        "n_vertices": int(mesh.n_vertices),
        "n_faces": int(mesh.n_faces),
        "vertex_labels": mesh.vertex_labels.tolist(),
        "face_rows": mesh.face_rows.tolist(),
        "frequency": {"min": float(np.min(texture.form.frequency)), "max": float(np.max(texture.form.frequency)),
                      "mean": float(np.mean(texture.form.frequency))},
        "interpolation": _INTERPOLATION,
        "zeros": {"faces": zf.tolist(), "index": texture.zero_index[zf].tolist(),
                  "points": texture.zero_points.tolist()},
        "branch": {"faces": bf.tolist(), "u_m": (texture.branch_alpha[:, 0] / TWO_PI).tolist(),
                   "u_l": (texture.branch_alpha[:, 1] / TWO_PI).tolist(), "points": texture.branch_points.tolist()},
    }
    out["repairs"] = [] if mesh.repair is None else mesh.repair.to_json()
    if mesh.repair is not None:
        out["vertex_rows"] = mesh.vertex_rows.tolist()
    if mesh.edge_lengths is not None:
        out["edge_lengths"] = mesh.edge_lengths.tolist()
    if obj_face_of is not None:
        out["obj_face_of"] = np.asarray(obj_face_of).tolist()
    return out


def _write_text(path: str, text: str) -> None:
    from dhlb._files import atomic_write

    with atomic_write(path) as fh:
        fh.write(text)


def _expanded(texture, refine: int):
    """Vertices, per-corner (vertex, u) of the subdivision; original corners reuse mesh vertices."""
    mesh = texture.mesh
    sub = texture.subdivision(refine)
    T = len(sub.face)
    bary = sub.bary.reshape(-1, 3)
    face = np.repeat(sub.face, 3)
    corner = np.isclose(bary.max(axis=1), 1.0, rtol=0, atol=1e-14)
    vid = np.empty(3 * T, np.int64)
    vid[corner] = mesh.faces[face[corner], np.argmax(bary[corner], axis=1)]
    key = np.column_stack([face[~corner], np.round(bary[~corner] * 2**40).astype(np.int64)])
    _uk, first, inv = np.unique(key, axis=0, return_index=True, return_inverse=True)
    vid[~corner] = mesh.n_vertices + inv.ravel()
    extra = np.einsum("pc,pcd->pd", bary[~corner][first], mesh.points[mesh.faces[face[~corner][first]]])
    return np.vstack([mesh.points, extra]), vid.reshape(T, 3), sub.alpha / TWO_PI, sub.face


BYTES_PER_OBJ_SUBTRIANGLE = 700
"""Measured peak memory of an expanded stripe OBJ (:func:`write_stripes_obj` with ``expand`` >= 1) per sub-triangle."""


def _check_expand(texture: StripeTexture, expand, max_bytes) -> int:
    """``expand`` checked: an integer >= 0 whose subdivision fits in ``max_bytes`` (refused before the work)."""
    from dhlb._coerce import check_real
    from dhlb.errors import InvalidParameterError, ResourceLimitError
    from dhlb.stripes.isolines import MAX_BYTES

    expand = check_int(expand, "expand", 0)
    budget = MAX_BYTES if max_bytes is None else check_real(max_bytes, "max_bytes")
    if budget <= 0:
        raise InvalidParameterError(f"max_bytes must be a positive number, got {max_bytes!r}")
    if not expand:
        return 0
    z, b = int(texture.zero_faces.size), int(texture.branch_faces.size)
    fixed = texture.mesh.n_faces - z + 2 * b                 # plain faces, and three cones per branch face
    estimate = BYTES_PER_OBJ_SUBTRIANGLE * (fixed + 6.0 * expand * expand * z)
    if estimate > budget:
        room = budget / BYTES_PER_OBJ_SUBTRIANGLE - fixed
        largest = int(np.sqrt(room / (6.0 * z))) if z and room >= 6.0 * z else 0
        raise ResourceLimitError(
            "expand", expand, estimate, budget,
            f"the subdivision has {fixed:,} + 6·expand²·{z} sub-triangles (6·expand² in each of the {z} zero "
            f"faces); allowed: {f'expand 0 to {largest}' if largest else 'expand = 0'} for this pattern, or a larger "
            "max_bytes")
    return expand


def write_stripes_obj(
    path: str | os.PathLike[str], texture: StripeTexture, *, sidecar: bool = True, expand: int = 0,
    max_bytes: float | None = None,
) -> tuple[str, str | None]:
    """Write the pattern as an OBJ with per-corner UVs (and ``<path minus .obj>.json`` as the sidecar).

    Parameters
    ----------
    path : str or path-like
        The OBJ file; its folder must exist.
    texture : StripeTexture
        The texture coordinates of the pattern.
    sidecar : bool, optional
        Also write the JSON description of zero and branch faces.
    expand : int, optional
        0: the mesh faces as they are; r >= 1: the subdivision (branch cones, r × r grids in zero faces).
    max_bytes : float, optional
        Memory budget of an expanded OBJ (default :data:`dhlb.stripes.isolines.MAX_BYTES`, 1 GB): the
        sub-triangles are counted before the work (:data:`BYTES_PER_OBJ_SUBTRIANGLE` each).

    Returns
    -------
    obj_path : str
        The OBJ file written.
    json_path : str or None
        The sidecar written (``path`` with ``.obj`` replaced by ``.json``), None without ``sidecar``.

    Raises
    ------
    InvalidParameterError
        ``expand`` is not an integer >= 0, or ``max_bytes`` is not a positive number.
    ResourceLimitError
        The subdivision of ``expand`` would exceed ``max_bytes``; the message states the estimate and the
        largest ``expand`` that fits. Nothing is written.
    OutputError
        A file cannot be written (missing folder, no permission, disk full): one line naming the path.
        Each file is written to a temporary file in its folder and renamed when complete, so an
        interrupted run never leaves a half-written file at the target.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import validate_surface
    >>> from dhlb.stripes import stripe_form, texture_coordinates
    >>> V = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]
    >>> mesh = validate_surface(V, [[0, 1, 2], [1, 3, 2]])
    >>> form = stripe_form(mesh, np.tile([1.0, 0, 0], (4, 1)), frequency=0.25)
    >>> tex = texture_coordinates(form, np.exp(0.5j * np.pi * np.array(V)[:, 0]))   # ψ = exp(i ν x), ν = 2π/4
    >>> import os, pathlib, tempfile
    >>> from dhlb.io.stripes import write_stripes_obj
    >>> with tempfile.TemporaryDirectory() as d:
    ...     obj, side = write_stripes_obj(os.path.join(d, "square.obj"), tex)
    ...     lines = pathlib.Path(obj).read_text().splitlines()
    >>> os.path.basename(side), sum(s.startswith("vt ") for s in lines), lines[-1]
    ('square.json', 6, 'f 2/4 4/5 3/6')
    """
    expand = _check_expand(texture, expand, max_bytes)
    mesh = texture.mesh
    if expand:
        P, tri, u, face_of = _expanded(texture, int(expand))
    else:
        P, tri, u, face_of = mesh.points, mesh.faces, texture.corner_alpha / TWO_PI, None
    m = len(tri)
    buf = io.StringIO()
    buf.write(f"# dhlb stripe pattern (n = {texture.form.n}): u = alpha / 2pi per face corner; {m} faces\n")
    np.savetxt(buf, P, fmt="v %.17g %.17g %.17g")
    np.savetxt(buf, u.reshape(-1, 1), fmt="vt %.17g 0")
    idx = np.stack([tri + 1, np.arange(1, 3 * m + 1).reshape(m, 3)], axis=-1).reshape(m, 6)
    np.savetxt(buf, idx, fmt="f %d/%d %d/%d %d/%d")
    out = os.fspath(path)
    _write_text(out, buf.getvalue())
    side = None
    if sidecar:
        base = out[:-4] if out.lower().endswith(".obj") else out
        side = base + ".json"
        data = stripes_sidecar(texture, obj_name=os.path.basename(out), obj_face_of=face_of)
        data["expanded"] = int(expand)
        _write_text(side, json.dumps(data))
    return out, side


# ---------------------------------------------------------------------------- reading back
class _FileForm:
    """What a texture read from a file knows of its stripe form: ``mesh``, ``n`` and the frequency range."""

    def __init__(self, mesh, n: int, frequency: np.ndarray):
        self.mesh, self.n, self.frequency = mesh, n, frequency


class _FileTexture(StripeTexture):
    """A :class:`~dhlb.stripes.StripeTexture` rebuilt from its OBJ and sidecar (no section ψ, no spinning form).

    Evaluation, subdivision, isolines, zero and branch points work as on the texture that was written.
    """

    def __init__(self, form: _FileForm, corner_alpha, zero_index, branch_faces, branch_alpha):
        self.form, self.mesh, self.psi, self.spinning = form, form.mesh, None, None
        m = self.mesh.n_faces
        self.corner_alpha = np.asarray(corner_alpha, np.float64).reshape(m, 3)
        self.zero_index = np.asarray(zero_index, np.int64)
        self.branch_faces = np.asarray(branch_faces, np.int64)
        self.branch_alpha = np.asarray(branch_alpha, np.float64).reshape(-1, 2)
        self.is_branch = np.zeros(m, bool)
        self.is_branch[self.branch_faces] = True
        self.winding_defect = 0.0
        self._branch_row = np.full(m, -1, np.int64)
        self._branch_row[self.branch_faces] = np.arange(self.branch_faces.size)
        for a in (self.zero_index, self.corner_alpha, self.branch_faces, self.branch_alpha, self.is_branch):
            a.setflags(write=False)


class LoadedStripes(Result):
    """A stripe pattern read back by :func:`read_stripes`: the texture, without the section and the form.

    It draws as the :class:`~dhlb.stripes.StripePattern` that was written (:func:`dhlb.render.view.scene_of`,
    :func:`dhlb.render.registry.picture`, :meth:`show`).

    Parameters
    ----------
    texture : StripeTexture
        The per-corner α, zero indices and branch data (kept as ``texture``).
    summary : dict
        The sidecar (kept as ``summary``; :meth:`to_json` returns it).

    Attributes
    ----------
    mesh : SurfaceMesh
        The mesh of the OBJ.
    n : int
        1 for a vector field, 2 for a line field.
    """

    def __init__(self, texture: StripeTexture, summary: dict):
        self.texture, self.summary = texture, summary
        self.mesh, self.n = texture.mesh, int(texture.form.n)

    corner_alpha = property(lambda self: self.texture.corner_alpha, doc="(m, 3) α per face corner.")
    zero_faces = property(lambda self: self.texture.zero_faces, doc="Faces containing a zero.")
    zero_index = property(lambda self: self.texture.zero_index, doc="(m,) index of every face.")
    branch_faces = property(lambda self: self.texture.branch_faces, doc="Branch triangles.")

    def to_json(self) -> dict:
        """The sidecar the pattern was read with.

        Returns
        -------
        dict
        """
        return dict(self.summary)

    def summary_rows(self) -> list[tuple[str, object]]:
        """The headline numbers, as ``(label, value)`` pairs.

        Returns
        -------
        list of (str, object)
        """
        return [("n", self.n), ("vertices, faces", f"{self.mesh.n_vertices}, {self.mesh.n_faces}"),
                ("zeros (index sum)", f"{self.zero_faces.size} ({int(self.zero_index.sum())})"),
                ("branch faces", self.branch_faces.size)]

    def __repr__(self) -> str:
        return (f"LoadedStripes(n={self.n}, zeros={self.zero_faces.size}, branch_faces={self.branch_faces.size}, "
                f"{self.mesh!r})")


def read_stripes(path: str | os.PathLike[str]) -> LoadedStripes:
    """Read back a stripe pattern: ``OUT.obj`` (:func:`write_stripes_obj`, ``dhlb stripes``) and its sidecar.

    The OBJ is read by :func:`dhlb.io.polylines.read_uv_obj`; every value of the sidecar that is used is
    checked (types, shapes, face numbers in range and not repeated, finite values, counts that match
    the OBJ, the repair record) before the texture is rebuilt.

    Parameters
    ----------
    path : str or path-like
        ``OUT.obj``, ``OUT.json`` or the output base ``OUT``.

    Returns
    -------
    LoadedStripes
        Its ``texture`` evaluates as the texture that was written (α to the last bits of the file).

    Raises
    ------
    MeshParseError
        A file is missing or unreadable, the sidecar is not a dhlb-stripes sidecar or does not fit the
        OBJ (a wrong type, a face number outside the faces or repeated, a non-finite value, counts that
        differ from the OBJ), the OBJ is not a valid surface, or the OBJ was written with ``expand`` >= 1
        (the subdivision, not the mesh); the message names the file and the field or line.
    NonFiniteError
        A vertex of the OBJ has a NaN or infinite coordinate (the message names the line).

    Examples
    --------
    >>> import os, tempfile
    >>> from dhlb.fields import direction_field
    >>> from dhlb.io import example_path, read_surface
    >>> from dhlb.stripes import stripe_pattern
    >>> V, F = read_surface(example_path("torus.obj"))
    >>> res = stripe_pattern(V, F, direction_field(V, F, n=2), spacing=4.0)
    >>> with tempfile.TemporaryDirectory() as d:
    ...     _ = write_stripes_obj(os.path.join(d, "s.obj"), res.texture)
    ...     back = read_stripes(os.path.join(d, "s"))
    >>> back.n, bool(np.allclose(back.texture.evaluate([0, 5], [[0.2, 0.3, 0.5]] * 2), res.evaluate([0, 5],
    ...                                                         [[0.2, 0.3, 0.5]] * 2), rtol=0, atol=1e-12))
    (2, True)
    """
    from dhlb.errors import DhlbError, MeshParseError
    from dhlb.io._text import check_json_type, check_number, output_stem, read_json
    from dhlb.io.polylines import read_uv_obj
    from dhlb.mesh import validate_surface

    base = output_stem(path)
    obj, side = base + ".obj", base + ".json"
    for p in (obj, side):
        if not os.path.isfile(p):
            raise MeshParseError("missing: a stripe pattern is the OBJ and its JSON sidecar", p)
    meta = read_json(side)
    if meta.get("format") != "dhlb-stripes":
        raise MeshParseError("not the sidecar of a dhlb stripe pattern (no 'format': 'dhlb-stripes')", side)
    if "version" in meta and check_number(meta["version"], side, "version", integer=True) != 1:
        raise MeshParseError(f"version {meta['version']} of the stripes sidecar; this dhlb reads version 1", side)
    expanded = check_number(meta.get("expanded", 0), side, "expanded", integer=True, low=0, optional=True)
    if expanded:
        raise MeshParseError(f"the OBJ holds the subdivision (expand={expanded}), not the mesh: write the "
                             "pattern with expand=0 to read it back", side)
    for key in ("n", "zeros", "branch"):
        if key not in meta:
            raise MeshParseError(f"the sidecar has no {key!r}", side)
    n = check_number(meta["n"], side, "n", integer=True, low=1, high=2)
    V, F, U = read_uv_obj(obj)
    _check_counts(meta, side, obj, len(V), len(F))
    lengths = _sidecar_lengths(meta, side)
    if lengths is not None:   # a mollified mesh: its own metric (zero-area faces in space)
        from dhlb.mesh.repair import repaired_mesh

        try:
            mesh = repaired_mesh(V, F, np.arange(len(F)), None, lengths)
        except (DhlbError, TypeError, ValueError) as exc:
            raise MeshParseError(f"the mesh and the sidecar's edge_lengths do not fit ({exc})", side) from None
    else:
        import warnings

        from dhlb.errors import UnreferencedVertexWarning

        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", UnreferencedVertexWarning)   # refused below
                mesh = validate_surface(V, F)
        except DhlbError as exc:
            raise MeshParseError(f"not the mesh of a stripe pattern ({exc})", obj) from None
    if mesh.n_vertices != len(V):
        raise MeshParseError(f"{len(V) - mesh.n_vertices} vertices are on no face: not the OBJ of a stripe pattern",
                             obj)
    zf, zi, bf, balpha = _sidecar_faces(meta, side, mesh.n_faces, n)
    zero_index = np.zeros(mesh.n_faces, np.int64)
    zero_index[zf] = zi
    freq = check_json_type(meta.get("frequency", {}), dict, side, "frequency")
    frequency = np.array([check_number(freq.get(k), side, f"frequency.{k}", low=0.0, optional=True)
                          for k in ("min", "max")], dtype=float)
    if "interpolation" in meta:
        check_json_type(meta["interpolation"], str, side, "interpolation")
    if "obj" in meta:
        check_json_type(meta["obj"], (str, type(None)), side, "obj")
    tex = _FileTexture(_FileForm(mesh, n, frequency), TWO_PI * U, zero_index, bf, balpha)
    return LoadedStripes(tex, meta)


def _check_counts(meta: dict, side: str, obj: str, n_vertices: int, n_faces: int) -> None:
    """The sidecar's counts and per-vertex / per-face lists against the OBJ (a truncated OBJ, another pattern)."""
    from dhlb.errors import MeshParseError
    from dhlb.io._text import check_array, check_json_type, check_number, check_repairs

    for key, have, what in (("n_vertices", n_vertices, "vertices"), ("n_faces", n_faces, "faces")):
        if key in meta and check_number(meta[key], side, key, integer=True, low=0) != have:
            raise MeshParseError(f"{key} = {meta[key]}, but {os.path.basename(obj)} has {have} {what} (a truncated "
                                 "OBJ, or the sidecar of another pattern)", side)
    for key, count, what in (("vertex_labels", n_vertices, "vertex"), ("vertex_rows", n_vertices, "vertex"),
                             ("face_rows", n_faces, "face")):
        if key in meta:
            check_array(meta[key], side, key, kind="i", shape=(count,), bounds=(0, None),
                        dims=f"({count},): one per {what} of {os.path.basename(obj)}")
    if "repairs" in meta:
        check_repairs(meta["repairs"], side, "repairs")
    if "obj_face_of" in meta:
        check_json_type(meta["obj_face_of"], list, side, "obj_face_of")


def _sidecar_lengths(meta: dict, side: str):
    """The ``edge_lengths`` of a mollified mesh in the sidecar (finite, positive), or None."""
    from dhlb.errors import MeshParseError
    from dhlb.io._text import check_array

    if meta.get("edge_lengths") is None:
        return None
    L = check_array(meta["edge_lengths"], side, "edge_lengths", shape=(None,), finite=True)
    if L.size and L.min() <= 0:
        i = int(np.argmin(L))
        raise MeshParseError(f"edge_lengths[{i}] = {float(L[i])!r} is not a positive length", side)
    return L


def _sidecar_faces(meta: dict, side: str, m: int, n: int):
    """Zero faces and indices, branch faces and their α of the sidecar, checked against the ``m`` faces."""
    from dhlb.errors import MeshParseError
    from dhlb.io._text import check_array, check_json_type

    out = []
    for key in ("zeros", "branch"):
        part = check_json_type(meta[key], dict, side, key)
        if "faces" not in part:
            raise MeshParseError(f"{key} has no 'faces'", side)
        faces = check_array(part["faces"], side, f"{key}.faces", kind="i", shape=(None,), bounds=(0, m - 1,
                            f"face rows of the OBJ, which has {m} faces"))
        counts = np.bincount(faces, minlength=m)
        if faces.size and counts.max() > 1:
            raise MeshParseError(f"{key}.faces names face {int(np.argmax(counts))} twice", side)
        k = faces.size
        values = []
        for field in ("index",) if key == "zeros" else ("u_m", "u_l"):
            if field not in part:
                raise MeshParseError(f"{key} has no {field!r}", side)
            values.append(check_array(part[field], side, f"{key}.{field}", kind="i" if field == "index" else "f",
                                      shape=(k,), finite=True, dims=f"({k},): one per face of {key}.faces"))
        if "points" in part:
            check_array(part["points"], side, f"{key}.points", shape=(k, 3) if k else None, finite=True,
                        dims=f"({k}, 3): one per face of {key}.faces")
        out.append((faces, values))
    (zf, (zi,)), (bf, (um, ul)) = out
    if zi.size and np.any(zi == 0):
        i = int(np.flatnonzero(zi == 0)[0])
        raise MeshParseError(f"zeros.index[{i}] = 0, but the index of a zero face is not 0", side)
    both = np.intersect1d(zf, bf)
    if both.size:
        raise MeshParseError(f"face {int(both[0])} is in zeros.faces and in branch.faces (a branch face has no zero)",
                             side)
    if n == 1 and bf.size:
        raise MeshParseError(f"n = 1 (a vector field), but branch.faces names {bf.size} faces: branch faces belong "
                             "to line fields (n = 2)", side)
    return zf, zi, bf, TWO_PI * np.column_stack([um, ul]).reshape(-1, 2)
