"""Mesh I/O: the syntax variants each reader accepts (comments, optional fields, extra properties,
sparse tags, alternative layouts)."""

from __future__ import annotations

import numpy as np
import pytest

from dhlb.errors import MeshParseError
from dhlb.io import load, read_gmsh, read_medit, read_obj, read_off, read_ply, read_simplices, read_vtk


def write(tmp_path, name: str, text: str) -> str:
    p = tmp_path / name
    p.write_text(text)
    return str(p)


def test_obj_syntax_variants(tmp_path):
    text = """# comment
mtllib x.mtl
o thing
v 0 0 0
v 1 0 0 1.0
v 1 1 0 0.5 0.5 0.5
vt 0 0
vn 0 0 1
g group
usemtl red
s off
f 1/1/1 2/1/1 3/1/1
v 0 1 0
f -4//1 -2//1 -1//1   # relative indices
f 2/1 3/1 4/1 1/1
l 1 2
"""
    V, F = read_obj(write(tmp_path, "a.obj", text))
    assert V.tolist() == [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]
    assert F.tolist() == [[0, 1, 2], [0, 2, 3], [1, 2, 3], [1, 3, 0]]


def test_off_syntax_variants(tmp_path):
    text = "COFF 4 2 0\n# comment\n0 0 0 255 0 0 255\n1 0 0 1 1 1 1\n1 1 0 0 0 0 0\n\n0 1 0 0 0 0 0\n" \
           "3 0 1 2 0.5 0.5 0.5\n3 0 2 3\n"
    V, F = read_off(write(tmp_path, "a.off", text))
    assert V.shape == (4, 3) and F.tolist() == [[0, 1, 2], [0, 2, 3]]


PLY_ASCII = """ply
format ascii 1.0
comment extra properties and an extra element between vertex and face
element vertex 4
property float x
property float y
property float z
property uchar red
property list uchar float weights
element edge 1
property int vertex1
property int vertex2
element face 2
property uchar flags
property list uchar uint vertex_index
property float quality
end_header
0 0 0 255 2 0.5 0.5
1 0 0 0 0
1 1 0 0 1 1.0

0 1 0 7 0
0 1
1 3 0 1 2 0.25
0 4 0 1 2 3 1.5
"""


def test_ply_ascii_with_extra_properties_and_elements(tmp_path):
    V, F = read_ply(write(tmp_path, "a.ply", PLY_ASCII))
    assert V.tolist() == [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]
    assert F.tolist() == [[0, 1, 2], [0, 1, 2], [0, 2, 3]]


@pytest.mark.parametrize("order", ["<", ">"])
def test_ply_binary_mixed_polygons_and_extra_properties(tmp_path, order):
    """Variable list lengths take the slow path; extra scalar and list properties are skipped."""
    V = np.array([[0.0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0]], dtype=np.float32)
    head = ("ply\nformat binary_%s_endian 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
            "property float z\nproperty short extra\nelement face 2\nproperty list uchar int vertex_indices\n"
            "property list ushort double uv\nend_header\n") % ("little" if order == "<" else "big")  # fmt: skip
    vert = np.zeros(5, dtype=[("p", order + "f4", 3), ("e", order + "i2")])
    vert["p"] = V
    body = vert.tobytes()
    body += np.array([3], "u1").tobytes() + np.array([0, 1, 2], order + "i4").tobytes()
    body += np.array([1], order + "u2").tobytes() + np.array([0.5], order + "f8").tobytes()
    body += np.array([4], "u1").tobytes() + np.array([1, 4, 2, 3], order + "i4").tobytes()
    body += np.array([0], order + "u2").tobytes()
    p = tmp_path / "b.ply"
    p.write_bytes(head.encode() + body)
    V2, F = read_ply(p)
    np.testing.assert_array_equal(V2, V.astype(np.float64))
    assert F.tolist() == [[0, 1, 2], [1, 4, 2], [1, 2, 3]]


def test_medit_syntax_variants(tmp_path):
    text = """MeshVersionFormatted
1
Dimension 2
# comment
Vertices 4
0 0 1
1 0 1
0 1
1 1 1
Corners
1
3
Triangles
2
1 2 3 0
2 4 3 0
End

# a comment after End is fine
"""
    V, cells = read_medit(write(tmp_path, "a.mesh", text))
    assert V.tolist() == [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]
    assert cells[2].tolist() == [[0, 1, 2], [1, 3, 2]]
    # data after End is an error (issue 19: it usually means a wrong declared count)
    with pytest.raises(MeshParseError, match="line 20: unexpected data after 'End'"):
        read_medit(write(tmp_path, "b.mesh", text + "trailing text\n"))


GMSH22 = """$MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
1
3 1 "solid # with hash"
$EndPhysicalNames
$Nodes
5
10 0 0 0
20 1 0 0
30 0 1 0
40 0 0 1
50 5 5 5
$EndNodes
$Elements
4
1 15 2 0 1 10
2 1 2 0 1 10 20
3 2 2 0 1 10 20 30
4 4 2 1 1 10 20 30 40
$EndElements
$NodeData
1
"ignored"
$EndNodeData
"""


def test_gmsh22_sparse_tags_and_all_simplex_types(tmp_path):
    V, cells = read_gmsh(write(tmp_path, "a.msh", GMSH22))
    assert V.shape == (5, 3)
    assert {k: c.tolist() for k, c in cells.items()} == {0: [[0]], 1: [[0, 1]], 2: [[0, 1, 2]], 3: [[0, 1, 2, 3]]}
    assert load(tmp_path / "a.msh").unreferenced_vertices().tolist() == [4]


GMSH41 = """$MeshFormat
4.1 0 8
$EndMeshFormat
$Entities
0 0 1 1
1 0 0 0 1 1 1 0 0
1 0 0 0 1 1 1 0 0
$EndEntities
$Nodes
2 5 3 9
2 1 1 2
7
3
0 0 0 0.1 0.2
1 0 0 0.3 0.4
3 1 0 3
9
4
5
0 1 0
0 0 1
2 2 2
$EndNodes
$Elements
2 2 1 2
2 1 2 1
1 7 3 9
3 1 11 1
2 7 3 9 4 5 5 5 5 5 5
$EndElements
"""


def test_gmsh41_blocks_parametric_nodes_and_second_order(tmp_path):
    V, cells = read_gmsh(write(tmp_path, "a.msh", GMSH41))
    assert V.tolist() == [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [2, 2, 2]]
    assert cells[2].tolist() == [[0, 1, 2]] and cells[3].tolist() == [[0, 1, 2, 3]]  # tet10: corners only


VTK_LEGACY = """# vtk DataFile Version 3.0
points wrapped over lines
ASCII

DATASET UNSTRUCTURED_GRID
POINTS 5 float
0 0 0 1 0 0 0 1 0
0 0 1 2 2 2
CELLS 3 12
4 0 1 2 3
3 0 1 2 2 1 3
CELL_TYPES 3
10
5
3
POINT_DATA 5
SCALARS s float
LOOKUP_TABLE default
1 2 3 4 5
"""

VTK51 = """# vtk DataFile Version 5.1
vtk output
ASCII
DATASET UNSTRUCTURED_GRID
POINTS 4 float
0 0 0 1 0 0 0 1 0 0 0 1
METADATA
INFORMATION 0

CELLS 3 7
OFFSETS vtktypeint64
0 4 7
CONNECTIVITY vtktypeint64
0 1 2 3 0 1 2
CELL_TYPES 2
10
5
"""


def test_vtk_legacy_and_51_layouts(tmp_path):
    V, cells = read_vtk(write(tmp_path, "a.vtk", VTK_LEGACY))
    assert V.shape == (5, 3) and V[4].tolist() == [2, 2, 2]
    assert {k: c.tolist() for k, c in cells.items()} == {1: [[1, 3]], 2: [[0, 1, 2]], 3: [[0, 1, 2, 3]]}
    V, cells = read_vtk(write(tmp_path, "b.vtk", VTK51))
    assert {k: c.tolist() for k, c in cells.items()} == {2: [[0, 1, 2]], 3: [[0, 1, 2, 3]]}


def test_simplex_list_comments_and_mixed_dimensions(tmp_path):
    text = "# header\n\n0 1 2   # a triangle\n  2 3\n7\n10 11 12 13\n"
    assert read_simplices(write(tmp_path, "x.txt", text)) == [(0, 1, 2), (2, 3), (7,), (10, 11, 12, 13)]
    m = load(tmp_path / "x.txt")
    assert m.kind == "complex" and m.points is None and m.dim == 3
    X = m.to_complex()
    assert X.counts == (9, 10, 5, 1)
    assert X.vertex_labels.tolist() == [0, 1, 2, 3, 7, 10, 11, 12, 13]
