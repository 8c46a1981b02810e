"""Bad input to the mesh readers: every case raises a typed error naming the file and the line
(or, for binary data, the element), never an IndexError, a numpy warning or a wrong answer."""

from __future__ import annotations

import os
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb.errors import DhlbError, MeshParseError, NonFiniteError
from dhlb.io import load, read_cells, read_ply, read_surface, read_volume, write_ply

DATA = os.path.join(os.path.dirname(__file__), "data")

TRI_OBJ = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"
TET_MESH = "MeshVersionFormatted 1\nDimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n" \
           "Tetrahedra\n1\n1 2 3 4 0\nEnd\n"  # fmt: skip
MSH22 = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n" \
        "$Elements\n1\n1 2 0 1 2 3\n$EndElements\n"  # fmt: skip
MSH41 = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 3 1 3\n2 1 0 3\n1\n2\n3\n0 0 0\n1 0 0\n0 1 0\n" \
        "$EndNodes\n$Elements\n1 1 1 1\n2 1 2 1\n1 1 2 3\n$EndElements\n"  # fmt: skip
VTK = "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 3 float\n0 0 0\n1 0 0\n0 1 0\n" \
      "CELLS 1 4\n3 0 1 2\nCELL_TYPES 1\n5\n"  # fmt: skip
PLY = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n" \
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"  # fmt: skip
OFF = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"

# (file name, text, exception, regex the message must match). Every text is a valid file with one
# defect; the valid versions are checked to parse in test_the_valid_fixtures_parse.
CASES = [
    # non-finite coordinates name the vertex and its line
    ("nan.obj", TRI_OBJ.replace("v 1 0 0", "v 1 nan 0"), NonFiniteError, r"line 2: vertex 2 \(0-based 1\)"),
    ("inf.off", OFF.replace("1 0 0\n", "1 inf 0\n", 1), NonFiniteError, r"line 4: vertex 1 "),
    ("nan.ply", PLY.replace("0 1 0\n", "0 NaN 0\n"), NonFiniteError, r"line 12: vertex 2 "),
    ("nan.mesh", TET_MESH.replace("0 1 0 0\n", "0 nan 0 0\n"), NonFiniteError, r"line 7: vertex 3 "),
    ("inf.msh", MSH22.replace("2 1 0 0", "2 1 -inf 0"), NonFiniteError, r"line 7: vertex 1 "),
    ("nan.vtk", VTK.replace("1 0 0", "1 0 nan"), NonFiniteError, r"line 7: vertex 1 "),
    # indices out of range name the line (binary PLY: the face number, see below)
    ("range.obj", TRI_OBJ.replace("f 1 2 3", "f 1 2 4"), MeshParseError, r"line 4: face refers to vertex 4 .* only 3"),
    ("zero.obj", TRI_OBJ.replace("f 1 2 3", "f 0 1 2"), MeshParseError, r"line 4: vertex index 0 is invalid"),
    ("neg.obj", TRI_OBJ.replace("f 1 2 3", "f -1 -2 -4"), MeshParseError, r"line 4: relative index -4"),
    ("range.off", OFF.replace("3 0 1 2", "3 0 1 3"), MeshParseError, r"line 6: face refers to vertex 3"),
    ("neg.off", OFF.replace("3 0 1 2", "3 0 -1 2"), MeshParseError, r"line 6: face refers to vertex -1"),
    ("range.ply", PLY.replace("3 0 1 2", "3 0 1 7"), MeshParseError, r"line 13: face refers to vertex 7"),
    ("range.mesh", TET_MESH.replace("1 2 3 4 0", "1 2 3 5 0"), MeshParseError, r"line 11: tetrahedron refers"),
    ("tag.msh", MSH22.replace("1 2 0 1 2 3", "1 2 0 1 2 9"), MeshParseError, r"line 12: .*node tag 9"),
    ("tag.msh", MSH41.replace("1 1 2 3\n$End", "1 1 2 8\n$End"), MeshParseError, r"line 17: .*node tag 8"),
    ("range.vtk", VTK.replace("3 0 1 2", "3 0 1 3"), MeshParseError, r"line 10: cell refers to vertex 3"),
    # unparsable tokens name the line
    ("tok.obj", TRI_OBJ.replace("v 0 1 0", "v 0 1x 0"), MeshParseError, r"line 3: cannot read '1x'"),
    ("tok2.obj", TRI_OBJ.replace("f 1 2 3", "f 1 2 3.5"), MeshParseError, r"line 4: cannot read '3.5'"),
    ("kw.obj", TRI_OBJ + "vertex 1 2 3\n", MeshParseError, r"line 5: unknown OBJ statement 'vertex'"),
    ("tok.off", OFF.replace("3 0 1 2", "3 0 one 2"), MeshParseError, r"line 6: cannot read 'one'"),
    ("tok.ply", PLY.replace("1 0 0\n", "1 0 zero\n"), MeshParseError, r"line 11: cannot read 'zero'"),
    ("frac.ply", PLY.replace("3 0 1 2", "3 0 1 2.5"), MeshParseError, r"line 13: cannot read '2.5' as an integer"),
    ("tok.mesh", TET_MESH.replace("1 0 0 0", "1 0 O 0"), MeshParseError, r"line 6: cannot read 'O'"),
    ("tok.msh", MSH22.replace("1 2 0 1 2 3", "1 2 0 1 2 three"), MeshParseError, r"line 12: cannot read 'three'"),
    ("tok.vtk", VTK.replace("3 0 1 2", "3 0 1 #"), MeshParseError, r"line 10: cannot read '#'"),
    ("tok.txt", "0 1 2\n1 2 3\n\n3 4 five\n", MeshParseError, r"line 4: cannot read 'five'"),
    ("neg.txt", "0 1 2\n1 -2 3\n", MeshParseError, r"line 2: vertex labels must be non-negative"),
    ("float.txt", "0 1 2\n1 2.0 3\n", MeshParseError, r"line 2: cannot read '2.0'"),
    # empty files
    ("empty.obj", "", MeshParseError, r"empty.obj: no vertices and no faces"),
    ("empty.off", "\n\n", MeshParseError, r"empty.off: the file is empty"),
    ("empty.ply", "", MeshParseError, r"empty.ply: the file is empty"),
    ("empty.mesh", "# nothing\n", MeshParseError, r"empty.mesh: the file is empty"),
    ("empty.msh", "", MeshParseError, r"empty.msh: the file is empty"),
    ("empty.vtk", "", MeshParseError, r"empty.vtk: the file is empty"),
    ("empty.txt", "# only a comment\n", MeshParseError, r"empty.txt: no simplices found"),
    ("nofaces.obj", "v 0 0 0\n", MeshParseError, r"no faces"),
    # ragged / short lines where a fixed length is required
    ("short.obj", TRI_OBJ.replace("f 1 2 3", "f 1 2"), MeshParseError, r"line 4: a face needs at least 3 vertices"),
    ("short.off", OFF.replace("3 0 1 2", "3 0 1"), MeshParseError, r"line 6: the face declares 3 vertices but lists 2"),
    ("two.off", OFF.replace("3 0 1 2", "2 0 1"), MeshParseError, r"line 6: a face needs at least 3"),
    ("vshort.off", OFF.replace("1 0 0\n", "1 0\n", 1), MeshParseError, r"line 4: a vertex needs 3 coordinates"),
    ("ragged.ply", PLY.replace("1 0 0\n", "1 0 0 4\n"), MeshParseError, r"line 11: 'vertex' line has 4 values"),
    ("ragged.mesh", TET_MESH.replace("1 2 3 4 0", "1 2 3"), MeshParseError, r"line 11: a tetrahedron line needs 4"),
    ("ragged.msh", MSH41.replace("1 1 2 3\n$End", "1 1 2\n$End"), MeshParseError, r"line 17: .*needs a tag and 3"),
    ("ragged.vtk", VTK.replace("3 0 1 2", "4 0 1 2"), MeshParseError, r"cell 0 declares 4 points"),
    # wrong counts and layout
    ("few.off", OFF.replace("3 1 0", "4 1 0"), MeshParseError, r"the file ends after 0 of 1 faces"),
    ("extra.off", OFF + "3 0 2 1\n", MeshParseError, r"line 7: unexpected data after the 1 declared faces"),
    ("header.off", OFF.replace("OFF", "OOF"), MeshParseError, r"line 1: expected the header 'OFF'"),
    ("extra.ply", PLY + "3 0 2 1\n", MeshParseError, r"line 14: unexpected data"),
    ("few.ply", PLY.replace("element face 1", "element face 2"), MeshParseError, r"ends after 1 of 2 'face' lines"),
    ("head.ply", PLY.replace("property float y", "property flaot y"), MeshParseError, r"line 5: cannot understand"),
    ("noz.ply", PLY.replace("property float z\n", "property float w\n"), MeshParseError, r"no property 'z'"),
    ("few.mesh", TET_MESH.replace("Tetrahedra\n1", "Tetrahedra\n2"), MeshParseError,
     r"line 12: section 'Tetrahedra' \(line 9\) declares 2 rows, but keyword 'End' follows after 1"),
    ("twice.mesh", TET_MESH.replace("End", "Vertices\n0\nEnd"), MeshParseError,
     r"line 12: section 'Vertices' appears twice"),
    ("kw.mesh", TET_MESH.replace("Tetrahedra", "0.5 0.5"), MeshParseError, r"line 9: expected a keyword"),
    ("open.msh", MSH22.replace("$EndNodes\n", ""), MeshParseError, r"line 4: section \$Nodes is not closed"),
    ("bin.msh", MSH22.replace("2.2 0 8", "2.2 1 8"), MeshParseError, r"line 2: binary .msh files are not supported"),
    ("v40.msh", MSH22.replace("2.2 0 8", "4.0 0 8"), MeshParseError, r"line 2: MSH version 4.0 is not supported"),
    ("dup.msh", MSH22.replace("3 0 1 0", "2 0 1 0"), MeshParseError, r"line 8: node tag 2 appears twice"),
    ("bin.vtk", VTK.replace("ASCII", "BINARY"), MeshParseError, r"line 3: only ASCII"),
    ("poly.vtk", VTK.replace("UNSTRUCTURED_GRID", "POLYDATA"), MeshParseError, r"only UNSTRUCTURED_GRID"),
    ("types.vtk", VTK.replace("CELL_TYPES 1\n5", "CELL_TYPES 2\n5 5"), MeshParseError, r"1 CELLS but 2 CELL_TYPES"),
    # degenerate cells and non-simplicial elements
    ("rep.obj", TRI_OBJ.replace("f 1 2 3", "f 1 2 2"), MeshParseError, r"line 4: face \(1 2 2\) repeats a vertex"),
    ("rep.mesh", TET_MESH.replace("1 2 3 4 0", "1 2 3 3 0"), MeshParseError, r"line 11: tetrahedron .* repeats"),
    ("rep.txt", "0 1 2\n3 4 3\n", MeshParseError, r"line 2: simplex \(3, 4, 3\) repeats vertex 3"),
    ("hex.mesh", TET_MESH.replace("End", "Hexahedra\n1\n1 2 3 4 1 2 3 4 0\nEnd"), MeshParseError,
     r"line 12: .*1 Hexahedra"),
    ("quad.msh", MSH22.replace("1 2 0 1 2 3", "1 3 0 1 2 3 1"), MeshParseError, r"line 12: element type 3 \(4-node"),
    ("quad.vtk", VTK.replace("CELL_TYPES 1\n5", "CELL_TYPES 1\n9"), MeshParseError, r"line 12: cell type 9 \(quad\)"),
]


@pytest.mark.parametrize("name, text, error, pattern", CASES, ids=[c[0] for c in CASES])
def test_bad_input_raises_a_typed_error_naming_the_line(tmp_path, name, text, error, pattern):
    path = tmp_path / name
    path.write_text(text)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no numpy warning on the way
        with pytest.raises(error, match=pattern) as info:
            load(path)
    assert str(path) in str(info.value)


@pytest.mark.parametrize("name, text", [("a.obj", TRI_OBJ), ("a.off", OFF), ("a.ply", PLY), ("a.mesh", TET_MESH),
                                        ("a.msh", MSH22), ("b.msh", MSH41), ("a.vtk", VTK)])  # fmt: skip
def test_the_valid_fixtures_parse(tmp_path, name, text):
    (tmp_path / name).write_text(text)
    m = load(tmp_path / name)
    assert m.points.shape[0] in (3, 4) and len(m.top_cells) == 1


def test_binary_ply_errors_name_the_element(tmp_path):
    V = np.eye(3)
    write_ply(tmp_path / "ok.ply", V, [[0, 1, 2], [2, 1, 0]], binary=True)
    data = (tmp_path / "ok.ply").read_bytes()
    (tmp_path / "cut.ply").write_bytes(data[:-5])
    with pytest.raises(MeshParseError, match=r"cut.ply: the file is truncated inside element 'face'"):
        read_ply(tmp_path / "cut.ply")
    bad = bytearray(data)
    bad[-4:] = np.array([9], "<i4").tobytes()  # last index of face 1 -> 9
    (tmp_path / "range.ply").write_bytes(bytes(bad))
    with pytest.raises(MeshParseError, match=r"range.ply: face 1 refers to vertex 9"):
        read_ply(tmp_path / "range.ply")
    nan = bytearray(data)
    start = data.index(b"end_header\n") + len(b"end_header\n")
    nan[start + 8 : start + 16] = np.array([np.nan], "<f8").tobytes()  # y of vertex 0
    (tmp_path / "nan.ply").write_bytes(bytes(nan))
    with pytest.raises(NonFiniteError, match=r"nan.ply: vertex 0 has a non-finite coordinate"):
        read_ply(tmp_path / "nan.ply")


def test_surface_and_volume_readers_refuse_the_other_kind(tmp_path):
    with pytest.raises(MeshParseError, match=r"contains no tetrahedra.*; read it with dhlb.io.read_surface") as info:
        read_volume(_surface_mesh(tmp_path))
    assert info.value.found == "surface"
    with pytest.raises(MeshParseError, match=r"volume mesh .1140 tetrahedra.*; read it with dhlb.io.read_vol") as info:
        read_surface(os.path.join(DATA, "octopus-low-tet.mesh"))
    assert info.value.found == "volume" and "read_volume" not in info.value.reason
    with pytest.raises(MeshParseError, match=r"hold surfaces.*read_surface") as info:
        read_volume(os.path.join(DATA, "moebius.obj"))
    assert info.value.found == "surface"


def _surface_mesh(tmp_path) -> str:
    p = tmp_path / "s.mesh"
    p.write_text("Vertices\n3\n0 0 0 1\n1 0 0 1\n0 1 0 1\nTriangles\n1\n1 2 3 1\n")
    assert read_surface(p)[1].tolist() == [[0, 1, 2]]
    return str(p)


def test_unknown_extension_missing_file_and_directory(tmp_path):
    with pytest.raises(MeshParseError, match=r"unknown file extension '.xyz'"):
        load(tmp_path / "a.xyz")
    with pytest.raises(FileNotFoundError):
        load(tmp_path / "missing.obj")
    with pytest.raises(IsADirectoryError):
        load(tmp_path, fmt="obj")
    with pytest.raises(MeshParseError, match="unknown format 'stl'"):
        read_cells(tmp_path / "a.mesh", fmt="stl")


def test_binary_garbage_is_a_parse_error_not_a_crash(tmp_path):
    rng = np.random.default_rng(0)
    for ext in ("obj", "off", "ply", "mesh", "msh", "vtk", "txt"):
        p = tmp_path / f"garbage.{ext}"
        p.write_bytes(rng.integers(0, 256, 2000, dtype=np.uint8).tobytes())
        with pytest.raises(MeshParseError, match=f"garbage.{ext}"):
            load(p)


# ------------------------------------------------------------------------------------ fuzzing
FIXTURES = {"a.obj": TRI_OBJ, "a.off": OFF, "a.ply": PLY, "a.mesh": TET_MESH, "a.msh": MSH22, "b.msh": MSH41,
            "a.vtk": VTK, "a.txt": "0 1 2\n1 2 3\n"}  # fmt: skip
TOKENS = ["x", "-1", "0", "1", "2", "3", "99", "nan", "-inf", "1e400", "3.5", "-0", "#", "$Nodes", "End", "f", "v"]


@st.composite
def mutated(draw):
    name = draw(st.sampled_from(sorted(FIXTURES)))
    lines = [line.split(" ") for line in FIXTURES[name].splitlines()]
    for _ in range(draw(st.integers(1, 3))):
        i = draw(st.integers(0, len(lines) - 1))
        action = draw(st.sampled_from(["replace", "delete_line", "duplicate_line", "insert", "drop_token"]))
        if action == "replace":
            lines[i][draw(st.integers(0, len(lines[i]) - 1))] = draw(st.sampled_from(TOKENS))
        elif action == "delete_line" and len(lines) > 1:
            del lines[i]
        elif action == "duplicate_line":
            lines.insert(i, list(lines[i]))
        elif action == "insert":
            lines[i].insert(draw(st.integers(0, len(lines[i]))), draw(st.sampled_from(TOKENS)))
        elif action == "drop_token" and len(lines[i]) > 1:
            del lines[i][draw(st.integers(0, len(lines[i]) - 1))]
    return name, "\n".join(" ".join(t) for t in lines) + "\n"


@settings(max_examples=150, deadline=None)
@given(case=mutated())
def test_mutated_files_parse_or_raise_a_dhlb_error(tmp_path_factory, case):
    """Random edits of valid files: either a consistent mesh or a DhlbError, nothing else."""
    name, text = case
    path = tmp_path_factory.mktemp("fuzz") / name
    path.write_text(text)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            m = load(path)
        except DhlbError as err:
            assert str(path) in str(err)
            return
    for k, c in m.cells.items():
        assert c.dtype == np.int64 and c.ndim == 2 and c.shape[1] == k + 1 and len(c)
        assert (np.sort(c, axis=1)[:, 1:] != np.sort(c, axis=1)[:, :-1]).all()
        if m.points is not None:
            assert c.min() >= 0 and c.max() < len(m.points)
    if m.points is not None:
        assert m.points.shape[1] == 3 and np.isfinite(m.points).all()
