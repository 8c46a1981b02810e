"""Every result reader checks what it reads (issue 39): a bad file is one typed error naming the file and the field.

Small real outputs of the four applications are written once (a field and a field on a repaired mesh, stripe
patterns on a plain and on a repaired, mollified mesh, vortex filaments as JSON, OBJ and PLY, a conformal map as
``.npz``, ``.json`` and ``.mesh`` + summary); each test copies them, breaks one thing (an empty or truncated file,
bytes that are no text, pickled objects, a wrong shape or dtype, an index out of range or negative, a NaN, a
string where a list belongs, files that disagree) and reads them back through :func:`dhlb.io.read_result` or the
reader of that kind. A file changed in a way that keeps it valid reads to an equal result.
"""

from __future__ import annotations

import json
import os
import pickle
import shutil
import warnings
import zipfile

import numpy as np
import pytest

from dhlb.conformal import conformal_deformation
from dhlb.errors import DhlbError, InvalidParameterError, MeshParseError, NonFiniteError, ResourceLimitError
from dhlb.fields import direction_field
from dhlb.io import read_result
from dhlb.io.polylines import (
    read_polylines_obj,
    read_polylines_ply,
    read_uv_obj,
    read_vortex,
    write_polylines_obj,
    write_polylines_ply,
)
from dhlb.io.results import read_field
from dhlb.io.stripes import BYTES_PER_OBJ_SUBTRIANGLE, _check_expand, read_stripes, write_stripes_obj
from dhlb.io.volume import read_conformal
from dhlb.mesh import ball_tet_mesh
from dhlb.stripes import stripe_pattern
from tests.surface_meshes import icosphere

OCTA_V = np.array([[1.0, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]])
OCTA_F = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])
DROP = object()


def _repaired_soup():
    """An octahedron with a sliver (mollified) and a small octahedron touching it at a vertex (split)."""
    V = np.vstack([OCTA_V, [[0.0, -1.0, 0.0]], OCTA_V * 0.5 + [1.5, 0, 0]])
    F = np.vstack([OCTA_F[:6], [[3, 6, 5], [6, 1, 5], [3, 1, 6]], OCTA_F[7:]])
    G = OCTA_F + len(OCTA_V) + 1
    G[G == len(OCTA_V) + 2] = 0
    return V, np.vstack([F, G])


@pytest.fixture(scope="module")
def made(tmp_path_factory):
    """The pristine outputs, once: ``(folder, results)``."""
    d = tmp_path_factory.mktemp("outputs")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        field = direction_field(np.vstack([OCTA_V, [[5.0, 5, 5]]]), OCTA_F, n=2)   # one unused row
        field.save(d / "f.npz")
        field.save(d / "f.json")
        V, F = _repaired_soup()
        rfield = direction_field(V, F, n=2)
        rfield.save(d / "fr.npz")
        rstripes = stripe_pattern(V, F, rfield, spacing=1.0)
        rstripes.save(d / "sr.obj")
        Vi, Fi = icosphere(1)
        stripes = stripe_pattern(Vi, Fi, direction_field(Vi, Fi, n=2), spacing=3.0)
        stripes.save(d / "s.obj")
        conformal = conformal_deformation(ball_tet_mesh(1), None, 0.5)
    assert rfield.mesh.is_intrinsic and rstripes.texture.zero_faces.size and rstripes.texture.branch_faces.size
    assert stripes.texture.zero_faces.size and stripes.texture.branch_faces.size
    t = np.linspace(0, 2 * np.pi, 6, endpoint=False)
    loop = np.column_stack([0.5 * np.cos(t), 0.5 * np.sin(t), 0.1 + 0 * t])
    chain = np.array([[0.0, 0, -1], [0.1, 0, 0], [0.0, 0.1, 1]])
    curves = [(loop, True), (chain, False)]
    summary = {"mesh": "box 2", "filaments": [{"points": P.tolist(), "closed": c} for P, c in curves],
               "linking_numbers": [[0, 0], [0, 0]], "linking_index": [0, 0], "timings": {}, "eigenvalue": 0.25,
               "statistics": {}}
    (d / "v.json").write_text(json.dumps(summary, indent=1))
    write_polylines_obj(d / "v.obj", curves)
    write_polylines_obj(d / "wo.obj", curves)   # no JSON beside: the OBJ alone
    write_polylines_ply(d / "wp.ply", curves)
    conformal.save(d / "c.npz")
    conformal.save(d / "cj.json")
    conformal.save(d / "cm.mesh")
    (d / "cm.json").write_text(json.dumps({"mesh": "ball 1", "u": "0.5", "eigenvalue": float(conformal.eigenvalue),
                                           "statistics": conformal.statistics, "timings": conformal.timings}))
    return d, {"field": field, "rfield": rfield, "stripes": stripes, "rstripes": rstripes, "curves": curves,
               "conformal": conformal}


def _copy(made, tmp_path, *names):
    for name in names:
        shutil.copy(made[0] / name, tmp_path / name)
    return [tmp_path / name for name in names]


def _resave(path, compressed=True, **changes):
    """Rewrite the ``.npz`` at ``path`` with some arrays replaced (a function of the data), or dropped (DROP)."""
    with np.load(path) as z:
        data = {k: z[k] for k in z.files}
    for key, value in changes.items():
        if value is DROP:
            data.pop(key, None)
        else:
            data[key] = value(data) if callable(value) else value
    (np.savez_compressed if compressed else np.savez)(path, **data)


def _edit_json(path, change):
    data = json.loads(path.read_text())
    change(data)
    path.write_text(json.dumps(data))


def _edit_text(path, change):
    path.write_text(change(path.read_text()))


def _raises(kind, fragment, fn, *args, names=None, **kwargs):
    """``fn(*args, **kwargs)`` raises ``kind`` (a DhlbError) whose message holds ``fragment`` and the file ``names``."""
    with pytest.raises(kind) as info:
        fn(*args, **kwargs)
    msg = str(info.value)
    assert isinstance(info.value, DhlbError)
    assert fragment in msg, msg
    if names is not None:
        assert names in msg, msg
    return msg


def _set(key, index, value):
    def change(data):
        a = data[key].copy()
        a[index] = value
        return a
    return change


# ----------------------------------------------------------------------------------------- the field .npz
def _bad_header_member(path):
    """A field archive whose u.npy announces a billion values and holds 16 bytes."""
    header = b"{'descr': '<c16', 'fortran_order': False, 'shape': (1000000000,), }"
    header += b" " * (117 - len(header)) + b"\n"
    with zipfile.ZipFile(path, "a") as zf:
        zf.writestr("u.npy", b"\x93NUMPY\x01\x00" + len(header).to_bytes(2, "little") + header + b"\0" * 16)


def _truncate(frac):
    def cut(path):
        data = path.read_bytes()
        path.write_bytes(data[:int(len(data) * frac)])
    return cut


def _flip_byte(path):
    """Flip a byte in the middle of the compressed data of ``u.npy`` (its CRC no longer matches)."""
    data = bytearray(path.read_bytes())
    info = zipfile.ZipFile(path).getinfo("u.npy")
    start = info.header_offset + 30 + int.from_bytes(data[info.header_offset + 26:info.header_offset + 28], "little") \
        + int.from_bytes(data[info.header_offset + 28:info.header_offset + 30], "little")
    data[start + info.compress_size // 2] ^= 0xFF
    path.write_bytes(bytes(data))


FILE_CORRUPTIONS = [   # (name, change of the file, fragment of the message)
    ("empty", lambda p: p.write_bytes(b""), "the file is empty (0 bytes)"),
    ("truncated-half", _truncate(0.5), "damaged or truncated"),
    ("truncated-end", _truncate(0.98), "damaged or truncated"),
    ("flipped-byte", _flip_byte, "damaged or truncated"),
    ("random-bytes", lambda p: p.write_bytes(np.random.default_rng(1).bytes(3000)), "not an .npz archive"),
    ("text", lambda p: p.write_text("u = 1\n"), "not an .npz archive"),
    ("single-npy", lambda p: np.save(open(p, "wb"), np.arange(4)), "a single .npy array"),
    ("pickle", lambda p: p.write_bytes(pickle.dumps({"u": [1, 2]})), "a pickle of Python objects"),
    ("pickled-array", lambda p: _resave(p, u=np.array([{}, None], dtype=object)), "'u' holds pickled Python objects"),
    ("not-npy-member", lambda p: zipfile.ZipFile(p, "a").writestr("readme.txt", "hi"), "'readme.txt' is not an .npy"),
    ("header-lies", lambda p: (_resave(p, u=DROP), _bad_header_member(p)), "'u' is damaged: its header announces"),
]


@pytest.mark.parametrize("name, change, fragment", FILE_CORRUPTIONS, ids=[c[0] for c in FILE_CORRUPTIONS])
def test_a_broken_field_archive_is_a_parse_error(made, tmp_path, name, change, fragment):
    npz, _ = _copy(made, tmp_path, "f.npz", "f.json")
    change(npz)
    _raises(MeshParseError, fragment, read_result, npz, names="f.npz")
    _raises(MeshParseError, fragment, read_result, tmp_path / "f", names="f.npz")   # the base: _kind looks first


def _negate(key):
    return lambda d: -d[key]


FIELD_CORRUPTIONS = [
    ("vertex_rows-negated", {"vertex_rows": _negate("vertex_rows")}, "vertex_rows[1] = -1 is outside 0 .. 6"),
    ("vertex_rows-past-u", {"vertex_rows": lambda d: d["vertex_rows"] + 3}, "vertex_rows[4] = 7 is outside 0 .. 6"),
    ("vertex_rows-float", {"vertex_rows": lambda d: d["vertex_rows"] + 0.5}, "vertex_rows must hold integers"),
    ("vertex_rows-short", {"vertex_rows": lambda d: d["vertex_rows"][:-1]}, "vertex_rows must have shape (6,)"),
    ("vertex_rows-twice", {"vertex_rows": _set("vertex_rows", 1, 0)}, "vertex_rows names row 0 twice"),
    ("vertex_rows-unused-row", {"vertex_rows": _set("vertex_rows", 5, 6)}, "disagree on row 5"),
    ("vertex_used-flipped", {"vertex_used": lambda d: ~d["vertex_used"]}, "disagree on row 0"),
    ("u-nan", {"u": _set("u", 2, np.nan)}, "u[2] is not finite"),
    ("u-text", {"u": lambda d: d["u"].astype(str)}, "u must hold numbers, got text"),
    ("u-2d", {"u": lambda d: d["u"][:, None]}, "u must have shape (n,)"),
    ("frames-zero", {"frames": lambda d: 0 * d["frames"]}, "frames[0, 0] (the frame of vertex 0) is not a unit vector"),
    ("frames-normal", {"frames": lambda d: d["frames"][:, ::-1]}, "is not tangent to the mesh there"),
    ("frames-shape", {"frames": lambda d: d["frames"][:, :, :2]}, "frames must have shape (7, 3, 3)"),
    ("directions-rows", {"directions": lambda d: d["directions"][:-1]}, "directions must have shape (7, n, 3)"),
    ("n-other", {"n": np.int64(3)}, "n = 3, but directions holds 2 directions per vertex"),
    ("n-vector", {"n": np.array([2, 2])}, "n must be a single integer"),
    ("s-nan", {"s": np.float64(np.nan)}, "s must be finite"),
    ("mesh_faces-past", {"mesh_faces": _set("mesh_faces", (3, 1), 99)}, "mesh_faces[3, 1] = 99 is outside 0 .. 5"),
    ("mesh_faces-negative", {"mesh_faces": _negate("mesh_faces")}, "mesh_faces[0, 1] = -2 is outside 0 .. 5"),
    ("mesh_faces-repeat", {"mesh_faces": _set("mesh_faces", (0, 1), 0)}, "mesh_points and mesh_faces are not a valid"),
    ("mesh_points-inf", {"mesh_points": _set("mesh_points", (4, 2), np.inf)}, "mesh_points[4, 2] is not finite (inf)"),
    ("mesh_faces-dropped", {"mesh_faces": DROP}, "has no mesh_faces"),
    ("u-dropped", {"u": DROP}, "not a field file of dhlb: no u"),
    ("singular_faces-past", {"singular_faces": lambda d: d["singular_faces"] + 50},
     "singular_faces[0] = 51 is outside"),
    ("singular_points-nan", {"singular_points": _set("singular_points", (1, 0), np.nan)}, "singular_points[1, 0]"),
]


@pytest.mark.parametrize("name, changes, fragment", FIELD_CORRUPTIONS, ids=[c[0] for c in FIELD_CORRUPTIONS])
def test_a_field_archive_with_bad_values_is_a_parse_error(made, tmp_path, name, changes, fragment):
    npz, _ = _copy(made, tmp_path, "f.npz", "f.json")
    _resave(npz, **changes)
    _raises(MeshParseError, fragment, read_result, tmp_path / "f", names="f.npz")


SUMMARY_CORRUPTIONS = [
    ("energy-text", lambda d: d.update(energy="low"), "energy must be a number or null, got the string 'low'"),
    ("solver-list", lambda d: d.update(solver=[1]), "solver must be an object or null, got a list of 1 items"),
    ("n-other", lambda d: d.update(n=4), "n = 4, but the field .npz beside it has n = 2"),
    ("n_faces-other", lambda d: d.update(n_faces=9), "n_faces = 9, but the mesh of the field .npz beside it has 8"),
    ("lambda-list", lambda d: d.update({"lambda": [0]}), "lambda must be a number or null"),
]


@pytest.mark.parametrize("name, change, fragment", SUMMARY_CORRUPTIONS, ids=[c[0] for c in SUMMARY_CORRUPTIONS])
def test_a_field_summary_with_bad_values_is_a_parse_error(made, tmp_path, name, change, fragment):
    _, side = _copy(made, tmp_path, "f.npz", "f.json")
    _edit_json(side, change)
    _raises(MeshParseError, fragment, read_field, tmp_path / "f.npz", names="f.json")


JSON_FILE_CORRUPTIONS = [
    ("empty", b"", "the file is empty"),
    ("truncated", b'{"n": 2, "s": 0.0, "sing', "line 1: not readable JSON"),
    ("binary", b"\x00\x01\x02{}", "binary data (a NUL byte)"),
    ("latin-1", b'{"note": "caf\xe9"}', "byte 13 (0xe9) is not UTF-8 text"),
    ("utf-16", '{"n": 2}'.encode("utf-16"), "UTF-16 or UTF-32"),
    ("deep", b"[" * 100000 + b"]" * 100000, "nested too deeply"),
    ("a-list", b"[1, 2]", "holds a list, not a JSON object"),
]


@pytest.mark.parametrize("name, content, fragment", JSON_FILE_CORRUPTIONS, ids=[c[0] for c in JSON_FILE_CORRUPTIONS])
def test_a_broken_json_beside_a_result_is_a_parse_error(made, tmp_path, name, content, fragment):
    _, side = _copy(made, tmp_path, "f.npz", "f.json")
    side.write_bytes(content)
    _raises(MeshParseError, fragment, read_result, tmp_path / "f.npz", names="f.json")


REPAIRED_CORRUPTIONS = [
    ("vertex_of_input-past", {"vertex_of_input": _set("vertex_of_input", 3, 40)},
     "vertex_of_input[3] = 40 is outside -1 .. 12"),
    ("face_of_input-negative", {"face_of_input": _set("face_of_input", 2, -5)}, "face_of_input[2] = -5 is outside"),
    ("face_rows-short", {"face_rows": lambda d: d["face_rows"][:-2]}, "face_rows must have shape (18,)"),
    ("vertex_rows-negated", {"vertex_rows": _negate("vertex_rows")}, "vertex_rows[1] = -1 is outside 0 .. 12"),
    ("vertex_rows-unused-row", {"vertex_rows": _set("vertex_rows", 2, 8)},
     "vertex_rows[2] = 8, but vertex_of_input[8] = -1"),
    ("repairs-not-json", {"repairs": np.array("[{")}, "repairs is not readable JSON"),
    ("repairs-numbers", {"repairs": np.arange(3)}, "repairs must be a text"),
    ("repairs-count-text", {"repairs": np.array('[{"kind": "split", "count": "1", "message": ""}]')},
     "repairs[0].count must be an integer, got the string '1'"),
    ("repairs-value-inf", {"repairs": np.array('[{"kind": "mollify", "count": 1, "message": "", "value": Infinity}]')},
     "repairs[0].value must be finite"),
    ("repairs-dict", {"repairs": np.array('{"kind": "split"}')}, "repairs must be a list, got an object"),
    ("repair_options-bogus", {"repair_options": np.array("glue")}, "the repaired mesh cannot be rebuilt"),
    ("repair_delta-vector", {"repair_delta": np.zeros(2)}, "repair_delta must be a single number"),
    ("repair_delta-negative", {"repair_delta": np.float64(-1.0)}, "repair_delta must be >= 0.0"),
    ("edge_lengths-negative", {"mesh_edge_lengths": _set("mesh_edge_lengths", 4, -1.0)},
     "mesh_edge_lengths[4] = -1.0 is not a positive length"),
    ("edge_lengths-short", {"mesh_edge_lengths": lambda d: d["mesh_edge_lengths"][:-1]},
     "cannot be rebuilt (edge_lengths has shape (26,)"),
    ("mesh_u-nan", {"mesh_u": _set("mesh_u", 5, np.nan)}, "mesh_u[5] is not finite"),
    ("mesh_flipped-short", {"mesh_flipped": lambda d: d["mesh_flipped"][:3]}, "mesh_flipped must have shape (18,)"),
    ("mesh_frames-zero", {"mesh_frames": lambda d: 0 * d["mesh_frames"]}, "mesh_frames[0, 0] (the frame of vertex 0)"),
    ("vertex_used-flipped", {"vertex_used": lambda d: ~d["vertex_used"]}, "vertex_used[0] = False disagrees"),
    ("mesh_frames-dropped", {"mesh_frames": DROP}, "a repaired field without mesh_frames"),
]


@pytest.mark.parametrize("name, changes, fragment", REPAIRED_CORRUPTIONS, ids=[c[0] for c in REPAIRED_CORRUPTIONS])
def test_a_repaired_field_archive_with_bad_values_is_a_parse_error(made, tmp_path, name, changes, fragment):
    [npz] = _copy(made, tmp_path, "fr.npz")
    _resave(npz, **changes)
    _raises(MeshParseError, fragment, read_result, npz, names="fr.npz")


@pytest.mark.parametrize("name", ["f", "fr"])
def test_a_field_archive_saved_another_valid_way_reads_the_same(made, tmp_path, name):
    [npz] = _copy(made, tmp_path, f"{name}.npz")
    ints = ["vertex_rows", "mesh_faces", "face_rows", "face_index"] + (["vertex_of_input"] if name == "fr" else [])
    _resave(npz, compressed=False, **{k: (lambda d, k=k: d[k].astype(np.int32)) for k in ints})
    back, res = read_result(npz), made[1]["field" if name == "f" else "rfield"]
    assert back.index_sum == res.index_sum and np.array_equal(back.face_index, res.face_index)
    assert np.abs(back.directions - res.directions).max() < 1e-12


def test_an_npz_of_something_else_is_named(made, tmp_path):
    np.savez(tmp_path / "x.npz", a=np.arange(3))
    _raises(MeshParseError, "an .npz archive of a: not a field", read_result, tmp_path / "x.npz", names="x.npz")


def test_a_summary_of_a_wrong_shape_is_no_type_error(tmp_path):
    (tmp_path / "x.json").write_text('{"statistics": 5}')
    _raises(InvalidParameterError, "found no output of dhlb", read_result, tmp_path / "x.json")


# ----------------------------------------------------------------------------------------- stripe patterns
def _obj_lines(change):
    def edit(path):
        lines = path.read_text().splitlines()
        path.write_text("\n".join(change(lines)) + "\n")
    return edit


def _first(prefix, lines):
    return next(i for i, ln in enumerate(lines) if ln.startswith(prefix))


def _replace_first(prefix, new):
    def change(lines):
        i = _first(prefix, lines)
        return lines[:i] + [new] + lines[i + 1:]
    return change


OBJ_CORRUPTIONS = [   # on s.obj: 42 vertices (lines 2..43), 240 texture coordinates, 80 faces
    ("random-bytes", lambda p: p.write_bytes(np.random.default_rng(2).bytes(4000)), MeshParseError,
     "not a text OBJ file"),
    ("latin-1-number", lambda p: p.write_bytes(p.read_bytes().replace(b"\nv ", b"\nv 0.5 1\xe9 0\nv ", 1)),
     MeshParseError,
     "line 2: cannot read '1\ufffd' as a number vertex coordinate: bytes that are not UTF-8 text"),
    ("vertex-short", _obj_lines(_replace_first("v ", "v 0.5 1")), MeshParseError,
     "line 2: a vertex needs 3 coordinates, got 2"),
    ("vertex-nan", _obj_lines(_replace_first("v ", "v nan 0 0")), NonFiniteError, "line 2: vertex 1 (0-based 0)"),
    ("vt-inf", _obj_lines(_replace_first("vt ", "vt inf 0")), MeshParseError,
     "line 44: texture coordinate 1 is not finite (inf)"),
    ("face-past", _obj_lines(_replace_first("f ", "f 1/1 2/2 99999/3")), MeshParseError,
     "line 284: refers to vertex 99999 but the file has only 42 vertices"),
    ("face-vt-zero", _obj_lines(_replace_first("f ", "f 1/0 2/2 3/3")), MeshParseError,
     "line 284: texture coordinate index 0 is invalid"),
    ("face-no-vt", _obj_lines(_replace_first("f ", "f 1 2 3")), MeshParseError,
     "line 284: expected a triangle 'f a/ta b/tb c/tc'"),
    ("face-quad", _obj_lines(_replace_first("f ", "f 1/1 2/2 3/3 4/4")), MeshParseError,
     "line 284: expected a triangle"),
    ("face-repeats", _obj_lines(_replace_first("f ", "f 1/1 1/2 3/3")), MeshParseError,
     "line 284: face (1 1 3) repeats a vertex"),
    ("unknown-statement", _obj_lines(lambda ls: ls[:5] + ["vx 1 2 3"] + ls[5:]), MeshParseError,
     "line 6: unknown OBJ statement 'vx'"),
    ("truncated", _obj_lines(lambda ls: ls[:300]), MeshParseError, "n_faces = 80, but s.obj has 17 faces"),
    ("empty", lambda p: p.write_text(""), MeshParseError, "no faces ('f a/ta b/tb c/tc' lines)"),
    ("a-mesh", _obj_lines(lambda ls: [ln.split("/")[0] if ln.startswith("f") else ln for ln in ls]), MeshParseError,
     "expected a triangle"),
]


@pytest.mark.parametrize("name, change, kind, fragment", OBJ_CORRUPTIONS, ids=[c[0] for c in OBJ_CORRUPTIONS])
def test_a_broken_stripes_obj_is_a_parse_error(made, tmp_path, name, change, kind, fragment):
    obj, _ = _copy(made, tmp_path, "s.obj", "s.json")
    change(obj)
    _raises(kind, fragment, read_result, tmp_path / "s.obj", names="s.obj")


def _zeros(**kw):
    return lambda d: d["zeros"].update(kw)


def _branch(**kw):
    return lambda d: d["branch"].update(kw)


SIDECAR_CORRUPTIONS = [   # on sr.json: 18 faces, zeros [2, 6, 9, 17], branch [1, 3, 4, 7, 11, 13, 14, 16]
    ("zero-face-minus-1", _zeros(faces=[-1, 6, 9, 17]), "zeros.faces[0] = -1 is outside 0 .. 17"),
    ("zero-face-past", _zeros(faces=[2, 6, 9, 18]), "zeros.faces[3] = 18 is outside 0 .. 17"),
    ("zero-faces-text", _zeros(faces="2 6 9 17"), "zeros.faces must be a list of integers, got the string"),
    ("zero-faces-float", _zeros(faces=[2.5, 6, 9, 17]), "zeros.faces must hold integers"),
    ("zero-faces-twice", _zeros(faces=[2, 6, 6, 17]), "zeros.faces names face 6 twice"),
    ("zero-index-short", _zeros(index=[-1, 1]), "zeros.index must have shape (4,)"),
    ("zero-index-0", _zeros(index=[-1, 0, 1, 1]), "zeros.index[1] = 0"),
    ("zero-index-null", _zeros(index=[-1, None, 1, 1]), "zeros.index must be a rectangular array of integers"),
    ("zero-points-shape", _zeros(points=[[0, 0]] * 4), "zeros.points must have shape (4, 3)"),
    ("branch-u_m-nan", _branch(u_m=[float("nan")] + [0.0] * 7), "branch.u_m[0] is not finite (nan)"),
    ("branch-and-zero", _branch(faces=[2, 3, 4, 7, 11, 13, 14, 16]), "face 2 is in zeros.faces and in branch.faces"),
    ("branch-u_l-short", _branch(u_l=[0.0]), "branch.u_l must have shape (8,)"),
    ("zeros-list", lambda d: d.update(zeros=[]), "zeros must be an object, got a list of 0 items"),
    ("zeros-missing", lambda d: d.pop("zeros"), "the sidecar has no 'zeros'"),
    ("n-3", lambda d: d.update(n=3), "n must be between 1 and 2, got 3"),
    ("n-text", lambda d: d.update(n="2"), "n must be an integer, got the string '2'"),
    ("n-1-branch", lambda d: d.update(n=1), "branch faces belong to line fields"),
    ("frequency-list", lambda d: d.update(frequency=[1, 2]), "frequency must be an object"),
    ("frequency-text", lambda d: d["frequency"].update(min="x"), "frequency.min must be a number or null"),
    ("n_vertices-other", lambda d: d.update(n_vertices=12), "n_vertices = 12, but sr.obj has 13 vertices"),
    ("vertex_rows-negative", lambda d: d["vertex_rows"].__setitem__(0, -1), "vertex_rows[0] = -1 is below 0"),
    ("vertex_rows-short", lambda d: d["vertex_rows"].pop(), "vertex_rows must have shape (13,)"),
    ("face_rows-text", lambda d: d.update(face_rows="all"), "face_rows must be a list of integers"),
    ("repairs-text", lambda d: d.update(repairs="split"), "repairs must be a list, got the string 'split'"),
    ("repairs-no-count", lambda d: d["repairs"][0].pop("count"), "repairs[0] has no 'count'"),
    ("repairs-faces-negative", lambda d: d["repairs"][1].update(faces=[-6]), "repairs[1].faces[0] = -6 is below 0"),
    ("edge_lengths-nan", lambda d: d["edge_lengths"].__setitem__(3, float("nan")), "edge_lengths[3] is not finite"),
    ("edge_lengths-negative", lambda d: d["edge_lengths"].__setitem__(3, -1.0), "edge_lengths[3] = -1.0 is not a"),
    ("edge_lengths-short", lambda d: d["edge_lengths"].pop(), "the mesh and the sidecar's edge_lengths do not fit"),
    ("edge_lengths-text", lambda d: d.update(edge_lengths="1 2 3"), "edge_lengths must be a list of real numbers"),
    ("expanded-text", lambda d: d.update(expanded="yes"), "expanded must be an integer or null"),
    ("expanded-2", lambda d: d.update(expanded=2), "the OBJ holds the subdivision (expand=2)"),
    ("version-2", lambda d: d.update(version=2), "version 2 of the stripes sidecar"),
    ("format-other", lambda d: d.update(format="x"), "not the sidecar of a dhlb stripe pattern"),
]


@pytest.mark.parametrize("name, change, fragment", SIDECAR_CORRUPTIONS, ids=[c[0] for c in SIDECAR_CORRUPTIONS])
def test_a_stripes_sidecar_with_bad_values_is_a_parse_error(made, tmp_path, name, change, fragment):
    _, side = _copy(made, tmp_path, "sr.obj", "sr.json")
    _edit_json(side, change)
    _raises(MeshParseError, fragment, read_stripes, tmp_path / "sr", names="sr.json")


def test_a_stripes_obj_written_another_valid_way_reads_the_same(made, tmp_path):
    obj, _ = _copy(made, tmp_path, "s.obj", "s.json")
    res = read_stripes(obj).texture
    lines = obj.read_text().splitlines()
    nv, nt = sum(ln.startswith("v ") for ln in lines), sum(ln.startswith("vt ") for ln in lines)

    def relative(ln):   # f a/ta ... -> negative indices counted back from the end of the v and vt lists
        if not ln.startswith("f "):
            return ln
        corners = (c.split("/") for c in ln.split()[1:])
        return "f " + " ".join(f"{int(a) - nv - 1}/{int(t) - nt - 1}/1" for a, t in corners)

    text = "\r\n".join(["# edited", "g pattern", "vn 0 0 1", *(relative(ln) for ln in lines), ""])
    obj.write_bytes(text.encode())
    back = read_stripes(obj).texture
    assert np.array_equal(back.mesh.faces, res.mesh.faces) and np.array_equal(back.corner_alpha, res.corner_alpha)
    assert np.array_equal(back.zero_faces, res.zero_faces) and np.array_equal(back.branch_faces, res.branch_faces)


def test_read_uv_obj_names_the_line(tmp_path):
    p = tmp_path / "u.obj"
    p.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0\nvt 1\nf 1/1 2/2 3/3\n")
    _raises(MeshParseError, "line 6: refers to texture coordinate 3 but the file has only 2", read_uv_obj, p)
    p.write_bytes(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0\nvt 1\nvt 2\n\xff\xfe f 1/1 2/2 3/3\n")
    _raises(MeshParseError, "line 7: bytes that are not UTF-8 text", read_uv_obj, p, names="u.obj")


# ----------------------------------------------------------------------------------------- write_stripes_obj(expand=)
def test_a_huge_expand_is_refused_before_the_work(made, tmp_path):
    tex = made[1]["stripes"].texture
    msg = _raises(ResourceLimitError, "expand = 1000000 needs about", write_stripes_obj, tmp_path / "e.obj", tex,
                  expand=10**6)
    largest = int(msg.split("allowed: expand 0 to ")[1].split()[0])
    assert "of memory (estimate)" in msg and largest >= 1 and not (tmp_path / "e.obj").exists()
    assert _check_expand(tex, largest, None) == largest                    # the largest that fits fits
    with pytest.raises(ResourceLimitError):
        _check_expand(tex, largest + 1, None)
    small = (tex.mesh.n_faces + 10) * BYTES_PER_OBJ_SUBTRIANGLE
    _raises(ResourceLimitError, "allowed: expand = 0 for this pattern", write_stripes_obj, tmp_path / "e.obj", tex,
            expand=1, max_bytes=small)
    assert write_stripes_obj(tmp_path / "e.obj", tex, expand=2)[0].endswith("e.obj")


@pytest.mark.parametrize("bad", [-1, 1.5, 2.0, "3", True, None])
def test_an_expand_that_is_no_count_is_refused(made, tmp_path, bad):
    with pytest.raises(InvalidParameterError) as info:
        write_stripes_obj(tmp_path / "e.obj", made[1]["stripes"].texture, expand=bad)
    assert not isinstance(info.value, ResourceLimitError) and "expand must be an integer" in str(info.value)
    assert not (tmp_path / "e.obj").exists()


# ----------------------------------------------------------------------------------------- vortex filaments
def _filament(k, **kw):
    return lambda d: d["filaments"][k].update(kw)


VORTEX_JSON_CORRUPTIONS = [
    ("nan-point", lambda d: d["filaments"][0]["points"][2].__setitem__(1, float("nan")),
     "filaments[0].points[2, 1] is not finite (nan)"),
    ("points-text", _filament(0, points="0 0 0"), "filaments[0].points must be a list of real numbers"),
    ("points-ragged", _filament(1, points=[[0, 0, 0], [1, 1]]), "filaments[1].points must be a rectangular array"),
    ("points-flat", _filament(1, points=[0, 0, 0, 1, 1, 1]), "filaments[1].points must have shape (m, 3)"),
    ("points-empty", _filament(1, points=[]), "filaments[1].points must have shape (m, 3)"),
    ("closed-text", _filament(0, closed="false"), "filaments[0].closed must be true or false, got the string"),
    ("closed-two-points", _filament(1, closed=True, points=[[0, 0, 0], [1, 0, 0]]), "too few for a closed filament"),
    ("no-closed", lambda d: d["filaments"][1].pop("closed"), "filaments[1] has no 'closed'"),
    ("filaments-object", lambda d: d.update(filaments={"points": []}), "filaments must be a list, got an object"),
    ("filament-list", lambda d: d["filaments"].__setitem__(0, [1, 2]), "filaments[0] must be an object"),
    ("linking-shape", lambda d: d.update(linking_numbers=[[0]]), "linking_numbers must have shape (2, 2)"),
    ("linking-text", lambda d: d.update(linking_numbers="0"), "linking_numbers must be a list of integers"),
    ("linking-float", lambda d: d.update(linking_numbers=[[0, 0.5], [0.5, 0]]), "linking_numbers must hold integers"),
    ("eigenvalue-text", lambda d: d.update(eigenvalue="small"), "eigenvalue must be a number or null"),
    ("mesh-number", lambda d: d.update(mesh=5), "mesh must be a string or null, got 5"),
    ("mesh-box-0", lambda d: d.update(mesh="box 0"), "mesh = 'box 0' names no usable domain"),
    ("mesh-huge-box", lambda d: d.update(mesh="box 100000"), "mesh = 'box 100000' names no usable domain"),
]


@pytest.mark.parametrize("name, change, fragment", VORTEX_JSON_CORRUPTIONS,
                         ids=[c[0] for c in VORTEX_JSON_CORRUPTIONS])
def test_a_vortex_json_with_bad_values_is_a_parse_error(made, tmp_path, name, change, fragment):
    _, side = _copy(made, tmp_path, "v.obj", "v.json")
    _edit_json(side, change)
    _raises(MeshParseError, fragment, read_result, tmp_path / "v", names="v.json")


def test_a_vortex_json_reads_back(made, tmp_path):
    _copy(made, tmp_path, "v.obj", "v.json")
    back = read_result(tmp_path / "v.json")
    assert [f.closed for f in back.filaments] == [True, False] and back.eigenvalue == 0.25
    assert back.mesh is not None and len(back.mesh.points) == 27 and back.linking_numbers.shape == (2, 2)


VORTEX_OBJ_CORRUPTIONS = [   # wo.obj: 9 vertices (lines 2..10), 'l 1 2 3 4 5 6 1' (line 11), 'l 7 8 9' (line 12)
    ("past-the-vertices", _replace_first("l 7", "l 7 8 99999"), MeshParseError,
     "line 12: refers to vertex 99999 but the file has only 9 vertices"),
    ("index-0", _replace_first("l 7", "l 0 8 9"), MeshParseError, "line 12: vertex index 0 is invalid"),
    ("relative-too-far", _replace_first("l 7", "l -10 8 9"), MeshParseError,
     "line 12: relative vertex index -10 points before the first vertex"),
    ("no-index", _replace_first("l 7", "l"), MeshParseError, "line 12: a polyline 'l' needs at least one vertex"),
    ("bad-index", _replace_first("l 7", "l 7 x 9"), MeshParseError, "line 12: cannot read 'x' as an integer"),
    ("vertex-nan", _replace_first("v ", "v 0 nan 0"), NonFiniteError, "line 2: vertex 1 (0-based 0)"),
    ("vertex-short", _replace_first("v ", "v 0 0"), MeshParseError, "line 2: a vertex needs 3 coordinates"),
    ("truncated-vertices", lambda ls: ls[:6], MeshParseError, "holds 5 vertices but no polylines"),
    ("truncated-lines", lambda ls: ls[:11], MeshParseError, "vertex 7 is on no polyline"),
    ("faces", lambda ls: ls[:4] + ["f 1 2 3"], MeshParseError, "holds 1 faces and no polylines"),
    ("unknown", lambda ls: ["ply"] + ls, MeshParseError, "line 1: unknown OBJ statement 'ply'"),
]


@pytest.mark.parametrize("name, change, kind, fragment", VORTEX_OBJ_CORRUPTIONS,
                         ids=[c[0] for c in VORTEX_OBJ_CORRUPTIONS])
def test_a_broken_vortex_obj_is_a_parse_error(made, tmp_path, name, change, kind, fragment):
    [obj] = _copy(made, tmp_path, "wo.obj")
    _obj_lines(change)(obj)
    _raises(kind, fragment, read_vortex, obj, names="wo.obj")


def test_random_bytes_in_an_obj_are_a_parse_error(tmp_path):
    p = tmp_path / "r.obj"
    p.write_bytes(np.random.default_rng(3).bytes(5000))
    _raises(MeshParseError, "not a text OBJ file", read_polylines_obj, p, names="r.obj")
    _raises(MeshParseError, "not a text OBJ file", read_vortex, p, names="r.obj")
    p.write_bytes(b"v 0 0 0\n\xc3\x28 1 2\n")
    _raises(MeshParseError, "line 2: bytes that are not UTF-8 text", read_polylines_obj, p)


def test_a_vortex_obj_written_another_valid_way_reads_the_same(made, tmp_path):
    [obj] = _copy(made, tmp_path, "wo.obj")
    lines = obj.read_text().splitlines()
    lines = [ln.replace("l 7 8 9", "l -3/1 -2/2 -1/3") for ln in lines] + ["g rest", "# end"]
    obj.write_bytes("\r\n".join(lines).encode())
    back = read_vortex(obj)
    for f, (P, closed) in zip(back.filaments, made[1]["curves"]):
        assert f.closed == closed and np.array_equal(f.points, P)


def _ply_lines(change):
    return _obj_lines(change)


PLY_CORRUPTIONS = [   # wp.ply: header of 12 lines, 9 vertices (lines 13..21), 8 edges (lines 22..29)
    ("truncated", lambda ls: ls[:25], "truncated: the header announces 9 vertices and 8 edges"),
    ("extra", lambda ls: ls + ["0 1"], "line 30: 1 line of values after the last of the 9 vertices and 8 edges"),
    ("binary", lambda ls: [ls[0], "format binary_little_endian 1.0"] + ls[2:], "line 2: a filament PLY of dhlb is"),
    ("count-text", lambda ls: ls[:3] + ["element vertex many"] + ls[4:], "line 4: expected 'element NAME COUNT'"),
    ("faces", lambda ls: [ln.replace("element edge", "element face") for ln in ls], "expected the elements 'vertex'"),
    ("short-vertex", lambda ls: ls[:12] + ["0 0 0"] + ls[13:], "line 13: a vertex needs 4 values"),
    ("no-filament", lambda ls: [ln for ln in ls if "filament" not in ln], "has no property filament"),
    ("filament-half", lambda ls: ls[:12] + ["0 0 0 0.5"] + ls[13:], "line 13: the filament number 0.5 is not"),
    ("vertex-inf", lambda ls: ls[:13] + ["inf 0 0 0"] + ls[14:], "line 14: vertex 1 has a non-finite"),
    ("edge-past", lambda ls: ls[:21] + ["0 99"] + ls[22:], "line 22: edge (0 99) refers to a vertex outside 0 .. 8"),
    ("edge-negative", lambda ls: ls[:21] + ["-1 1"] + ls[22:], "line 22: edge (-1 1) refers to a vertex outside"),
    ("edge-skips", lambda ls: ls[:21] + ["0 2"] + ls[22:], "line 22: edge (0, 2) does not join consecutive"),
    ("edge-missing", lambda ls: [ln.replace("element edge 8", "element edge 7") for ln in ls[:27]] + ls[28:],
     "the edge (6, 7) of filament 1 is missing"),
    ("edge-twice", lambda ls: ls[:22] + ls[21:22] + ls[23:],
     "the edge (0, 1) of filament 0 is twice"),
]


@pytest.mark.parametrize("name, change, fragment", PLY_CORRUPTIONS, ids=[c[0] for c in PLY_CORRUPTIONS])
def test_a_broken_vortex_ply_is_a_parse_error(made, tmp_path, name, change, fragment):
    [ply] = _copy(made, tmp_path, "wp.ply")
    _ply_lines(change)(ply)
    kind = NonFiniteError if name == "vertex-inf" else MeshParseError
    _raises(kind, fragment, read_vortex, ply, names="wp.ply")


def test_a_vortex_ply_written_another_valid_way_reads_the_same(made, tmp_path):
    [ply] = _copy(made, tmp_path, "wp.ply")
    lines = ply.read_text().splitlines()
    head = lines[:12]
    head = head[:4] + ["property int filament", "property double x", "property double y", "property double z"] \
        + head[8:]
    verts = [" ".join(ln.split()[3:] + ln.split()[:3]) for ln in lines[12:21]]
    edges = lines[21:][::-1]
    ply.write_text("\n".join(head[:2] + ["comment reordered"] + head[2:] + verts + edges) + "\n\n")
    for (P, closed), (Q, c) in zip(read_polylines_ply(ply), made[1]["curves"]):
        assert closed == c and np.array_equal(P, Q)


# ----------------------------------------------------------------------------------------- conformal maps
CONFORMAL_NPZ_CORRUPTIONS = [   # c.npz: ball 1, 16 points and 42 tets
    ("distortion-3", {"distortion": np.full(3, 1.5)}, "distortion must have shape (42,)"),
    ("distortion-below-1", {"distortion": _set("distortion", 7, 0.5)}, "distortion[7] = 0.5 is not σ_max/σ_min"),
    ("distortion-nan", {"distortion": _set("distortion", 0, np.nan)}, "distortion[0] = nan is not"),
    ("scale_error-short", {"scale_error": np.zeros(5)}, "scale_error must have shape (42,)"),
    ("tets-negated", {"tets": _negate("tets")}, "tets[0, 1] = -1 is outside 0 .. 15"),
    ("tets-past", {"tets": _set("tets", (5, 2), 16)}, "tets[5, 2] = 16 is outside 0 .. 15"),
    ("tets-float", {"tets": lambda d: d["tets"].astype(float)}, "tets must hold integers"),
    ("tets-3", {"tets": lambda d: d["tets"][:, :3]}, "tets must have shape (k, 4)"),
    ("tets-repeat", {"tets": _set("tets", (0, 1), 0)}, "the input_points and tets are not a valid tetrahedral mesh"),
    ("points-nan", {"points": _set("points", (3, 0), np.nan)}, "points[3, 0] is not finite"),
    ("input_points-short", {"input_points": lambda d: d["input_points"][:-1]}, "input_points must have shape (16, 3)"),
    ("phi-rows", {"phi": lambda d: d["phi"][:-1]}, "phi must have one row per row of points (16)"),
    ("u-inf", {"u": _set("u", 4, np.inf)}, "u[4] is not finite"),
    ("eigenvalue-text", {"eigenvalue": np.array("small")}, "eigenvalue must be a single number"),
    ("tets-pickled", {"tets": lambda d: d["tets"].astype(object)}, "'tets' holds pickled Python objects"),
    ("points-dropped", {"points": DROP}, "not a conformal deformation of dhlb: no points"),
]


@pytest.mark.parametrize("name, changes, fragment", CONFORMAL_NPZ_CORRUPTIONS,
                         ids=[c[0] for c in CONFORMAL_NPZ_CORRUPTIONS])
def test_a_conformal_archive_with_bad_values_is_a_parse_error(made, tmp_path, name, changes, fragment):
    [npz] = _copy(made, tmp_path, "c.npz")
    _resave(npz, **changes)
    _raises(MeshParseError, fragment, read_result, tmp_path / "c", names="c.npz")


@pytest.mark.parametrize("name, change, fragment", FILE_CORRUPTIONS[:7], ids=[c[0] for c in FILE_CORRUPTIONS[:7]])
def test_a_broken_conformal_archive_is_a_parse_error(made, tmp_path, name, change, fragment):
    [npz] = _copy(made, tmp_path, "c.npz")
    change(npz)
    _raises(MeshParseError, fragment, read_conformal, npz, names="c.npz")


def test_a_conformal_archive_without_tets_is_named(made, tmp_path):
    [npz] = _copy(made, tmp_path, "c.npz")
    _resave(npz, tets=DROP)
    _raises(MeshParseError, "not a field (directions, u, ...) nor a conformal", read_result, npz, names="c.npz")
    _raises(MeshParseError, "not a conformal deformation of dhlb: no tets", read_conformal, npz)


CONFORMAL_JSON_CORRUPTIONS = [   # cj.json: to_json() of the result
    ("distortion-3", lambda d: d.update(distortion=[1.5] * 3), "distortion must have shape (42,)"),
    ("points-text", lambda d: d.update(points="0 0 0"), "points must be a list of real numbers"),
    ("tets-ragged", lambda d: d["tets"].__setitem__(0, [0, 1, 2]), "tets must be a rectangular array of integers"),
    ("tets-negative", lambda d: d["tets"][2].__setitem__(3, -1), "tets[2, 3] = -1 is outside 0 .. 15"),
    ("eigenvalue-text", lambda d: d.update(eigenvalue="x"), "eigenvalue must be a number or null"),
    ("statistics-list", lambda d: d.update(statistics=[1]), "statistics must be an object or null"),
    ("statistics-count", lambda d: d["statistics"].update(n_tets=41), "statistics.n_tets = 41, but cj.json has 42"),
    ("nan-point", lambda d: d["points"][0].__setitem__(0, float("nan")), "points[0, 0] is not finite"),
]


@pytest.mark.parametrize("name, change, fragment", CONFORMAL_JSON_CORRUPTIONS,
                         ids=[c[0] for c in CONFORMAL_JSON_CORRUPTIONS])
def test_a_conformal_json_with_bad_values_is_a_parse_error(made, tmp_path, name, change, fragment):
    [side] = _copy(made, tmp_path, "cj.json")
    _edit_json(side, change)
    _raises(MeshParseError, fragment, read_result, side, names="cj.json")


CONFORMAL_SUMMARY_CORRUPTIONS = [   # cm.mesh + cm.json naming "ball 1"
    ("other-mesh", lambda d: d.update(mesh="ball 2"), "mesh = 'ball 2' is not the mesh deformed in cm.mesh"),
    ("mesh-number", lambda d: d.update(mesh=7), "mesh must be a string or null, got 7"),
    ("mesh-ball-0", lambda d: d.update(mesh="ball 0"), "mesh = 'ball 0' names no usable input mesh"),
    ("count", lambda d: d["statistics"].update(n_vertices=17), "statistics.n_vertices = 17, but cm.mesh has 16"),
    ("count-text", lambda d: d["statistics"].update(n_tets="42"), "statistics.n_tets must be an integer"),
]


@pytest.mark.parametrize("name, change, fragment", CONFORMAL_SUMMARY_CORRUPTIONS,
                         ids=[c[0] for c in CONFORMAL_SUMMARY_CORRUPTIONS])
def test_a_conformal_summary_that_does_not_fit_is_a_parse_error(made, tmp_path, name, change, fragment):
    _, side = _copy(made, tmp_path, "cm.mesh", "cm.json")
    _edit_json(side, change)
    _raises(MeshParseError, fragment, read_result, tmp_path / "cm", names="cm.json")


def test_conformal_files_saved_another_valid_way_read_the_same(made, tmp_path):
    npz, _, _ = _copy(made, tmp_path, "c.npz", "cm.mesh", "cm.json")
    _resave(npz, compressed=True, tets=lambda d: d["tets"].astype(np.int32))
    res = made[1]["conformal"]
    back = read_result(npz)
    assert back.input_known and np.array_equal(back.distortion, res.distortion)
    assert np.array_equal(back.mesh.tets, res.mesh.tets) and back.eigenvalue == float(res.eigenvalue)
    back = read_result(tmp_path / "cm.mesh")
    assert back.input_known and np.allclose(back.distortion, res.distortion, rtol=1e-9)


@pytest.mark.parametrize("reader, names", [
    (read_field, ["c.npz"]), (read_stripes, ["v.obj", "v.json"]), (read_stripes, ["wo.obj", "s.json"]),
    (read_vortex, ["s.obj", "s.json"]), (read_vortex, ["cm.json"]), (read_conformal, ["f.npz"]),
    (read_conformal, ["v.json"]), (read_polylines_ply, ["cm.mesh"]), (read_uv_obj, ["wo.obj"]),
], ids=lambda x: x.__name__ if callable(x) else "+".join(x))
def test_a_file_of_another_kind_is_a_typed_error(made, tmp_path, reader, names):
    """Each reader given the files of another kind of result (renamed to its base): one typed error."""
    stem = {".obj": "x", ".json": "x", ".npz": "x", ".mesh": "x"}
    for name in names:
        shutil.copy(made[0] / name, tmp_path / (stem[os.path.splitext(name)[1]] + os.path.splitext(name)[1]))
    ext = {read_field: ".npz", read_conformal: ".npz" if names[0].endswith(".npz") else "",
           read_polylines_ply: ".mesh", read_uv_obj: ".obj"}.get(reader, "")
    with pytest.raises(DhlbError) as info:
        reader(tmp_path / ("x" + ext))
    assert f"{tmp_path}/x" in str(info.value)


def test_paraview_files_are_not_read_back(tmp_path):
    (tmp_path / "x.vtu").write_text("<VTKFile/>")
    _raises(InvalidParameterError, "ParaView files are not read back", read_result, tmp_path / "x.vtu")


def test_no_reader_lets_a_raw_error_through(made, tmp_path):
    """Every file of the outputs, cut at several lengths or filled with random bytes: a result or a DhlbError."""
    rng = np.random.default_rng(4)
    names = ["f.npz", "f.json", "fr.npz", "s.obj", "s.json", "v.json", "wo.obj", "wp.ply", "c.npz", "cj.json",
             "cm.mesh", "cm.json"]
    for name in names:
        data = (made[0] / name).read_bytes()
        for k, cut in enumerate([*rng.integers(1, len(data), 4), None]):
            folder = tmp_path / f"{name}-{k}"
            folder.mkdir()
            for other in os.listdir(made[0]):
                shutil.copy(made[0] / other, folder / other)
            (folder / name).write_bytes(data[:cut] if cut is not None else rng.bytes(len(data)))
            try:
                read_result(folder / name)
            except DhlbError:
                pass


def test_the_long_fuzz_run_findings_are_typed_errors():
    # DHLB_FUZZ_LONG=7200 of tests/test_fuzz_results.py (50,400 inputs) found these two: a JSON integer
    # beyond every machine type (np.isfinite raised TypeError) and the area of a degenerate face in a
    # mesh with coordinates near 1e308 (scale**2 raised OverflowError while the message was written)
    import numpy as np

    from dhlb.errors import DegenerateSimplexError, MeshParseError
    from dhlb.io._text import check_number
    from dhlb.mesh import validate_surface

    with pytest.raises(MeshParseError, match="too large"):
        check_number(10**30, "f.json", "n_vertices", integer=True)
    V = np.array([[0.0, 0, 0], [1e308, 0, 0], [2e307, 0, 0], [0, 1e308, 0]])
    with pytest.raises(DegenerateSimplexError, match="zero area"):
        validate_surface(V, [[0, 1, 2], [0, 1, 3]])
