"""Mesh I/O: exact round trips, real files, compact_mesh, load.

The syntax variants of each format are in tests/test_io_formats.py, bad-input cases (every error
names the file and line) in tests/test_io_errors.py.
"""

from __future__ import annotations

import os
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from dhlb.errors import InvalidSimplexError, NonFiniteError, UnreferencedVertexWarning
from dhlb.io import (
    compact_mesh,
    example_path,
    load,
    read_cells,
    read_medit,
    read_simplices,
    read_surface,
    read_volume,
    write_cells,
    write_gmsh,
    write_obj,
    write_off,
    write_ply,
    write_simplices,
    write_surface,
    write_volume,
)

DATA = os.path.join(os.path.dirname(__file__), "data")


def write(tmp_path, name: str, text: str) -> str:
    p = tmp_path / name
    p.write_text(text)
    return str(p)


def unique_edges(F: np.ndarray) -> int:
    k = F.shape[1]
    e = np.concatenate([F[:, [i, j]] for i in range(k) for j in range(i + 1, k)])
    return len(np.unique(np.sort(e, axis=1), axis=0))


# ----------------------------------------------------------------------------------- strategies
finite = st.floats(allow_nan=False, allow_infinity=False, width=64)


@st.composite
def meshes(draw, corners: int = 3, max_cells: int = 12):
    """Random (V, F): finite float64 vertices, cells of ``corners`` distinct vertex rows."""
    n = draw(st.integers(corners, 10))
    V = draw(hnp.arrays(np.float64, (n, 3), elements=finite))
    m = draw(st.integers(1, max_cells))
    F = np.array([draw(st.permutations(range(n)))[:corners] for _ in range(m)], dtype=np.int64)
    return V, F


# ----------------------------------------------------------------------------------- round trips
@settings(max_examples=15, deadline=None)
@given(mesh=meshes())
def test_surface_round_trips_are_exact(tmp_path_factory, mesh):
    V, F = mesh
    d = tmp_path_factory.mktemp("rt")
    cases = [("a.obj", {}), ("a.off", {}), ("a.ply", {}), ("b.ply", {"binary": True}),
             ("c.ply", {"binary": True, "byteorder": ">"})]  # fmt: skip
    for name, kw in cases:
        write_surface(d / name, V, F, **kw)
        V2, F2 = read_surface(d / name)
        assert V2.dtype == np.float64 and F2.dtype == np.int64
        np.testing.assert_array_equal(V2, V)  # bit-exact, including -0.0 vs 0.0 via equality
        np.testing.assert_array_equal(F2, F)
        assert np.array_equal(np.signbit(V2), np.signbit(V))


@settings(max_examples=15, deadline=None)
@given(mesh=meshes(corners=4), tris=st.booleans())
def test_volume_round_trips_are_exact(tmp_path_factory, mesh, tris):
    V, T = mesh
    d = tmp_path_factory.mktemp("rt")
    cells = {3: T, 2: T[:, :3]} if tris else {3: T}
    for name, kw in [("a.mesh", {}), ("a.msh", {}), ("b.msh", {"version": "4.1"}), ("a.vtk", {})]:
        write_cells(d / name, V, cells, **kw)
        V2, cells2 = read_cells(d / name)
        np.testing.assert_array_equal(V2, V)
        assert sorted(k for k, c in cells2.items() if len(c)) == sorted(cells)
        for k in cells:
            np.testing.assert_array_equal(cells2[k], cells[k])
        np.testing.assert_array_equal(read_volume(d / name)[1], T)


def test_volume_round_trip_with_points_and_edges(tmp_path):
    V = np.eye(3)
    cells = {0: np.array([[2]]), 1: np.array([[0, 1], [1, 2]]), 2: np.array([[0, 1, 2]])}
    for name in ("a.msh", "a.vtk"):
        write_cells(tmp_path / name, V, cells)
        _, got = read_cells(tmp_path / name)
        assert {k: v.tolist() for k, v in got.items()} == {k: v.tolist() for k, v in cells.items()}
    write_volume(tmp_path / "t.mesh", np.vstack([V, [1, 1, 1]]), [[0, 1, 2, 3]])
    assert read_medit(tmp_path / "t.mesh")[1][3].tolist() == [[0, 1, 2, 3]]


@settings(max_examples=20, deadline=None)
@given(st.lists(st.lists(st.integers(0, 2**40), min_size=1, max_size=5, unique=True).map(tuple), min_size=1))
def test_simplex_list_round_trip(tmp_path_factory, simplices):
    p = tmp_path_factory.mktemp("s") / "x.txt"
    write_simplices(p, simplices)
    assert read_simplices(p) == simplices


def test_polygons_are_fan_triangulated_in_order(tmp_path):
    V = np.array([[0.0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0]])
    quads = np.array([[0, 1, 2, 3], [1, 4, 2, 0]])
    expected = [[0, 1, 2], [0, 2, 3], [1, 4, 2], [1, 2, 0]]
    for name in ("q.obj", "q.off", "q.ply"):
        write_surface(tmp_path / name, V, quads)
        assert read_surface(tmp_path / name)[1].tolist() == expected


def test_writers_refuse_bad_arrays(tmp_path):
    with pytest.raises(NonFiniteError, match="vertex 1"):
        write_obj(tmp_path / "a.obj", [[0, 0, 0], [np.inf, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    with pytest.raises(InvalidSimplexError, match=r"0 .. 2"):
        write_off(tmp_path / "a.off", np.eye(3), [[0, 1, 3]])
    with pytest.raises(InvalidSimplexError, match="shape"):
        write_ply(tmp_path / "a.ply", np.eye(3)[:, :2], [[0, 1, 2]])
    with pytest.raises(InvalidSimplexError, match=r"\(m, 4\)"):
        write_volume(tmp_path / "a.mesh", np.eye(3), [[0, 1, 2]])
    with pytest.raises(InvalidSimplexError, match="integers"):
        write_gmsh(tmp_path / "a.msh", np.eye(3), np.array([[0.0, 1.0, 2.0]]))
    with pytest.raises(InvalidSimplexError):
        write_simplices(tmp_path / "a.txt", [(0, -1)])


# ------------------------------------------------------------------------------------ real files
@pytest.mark.parametrize(
    "name, nv, nf, ne",
    [
        ("moebius.obj", 280, 448, 728),  # 224 quads -> 448 triangles, 504 + 224 diagonals
        ("moebius-160-10.ply", 1600, 2880, 4480),  # binary little endian, double xyz, int list
        ("3holes.off", 3596, 7200, 10800),
        ("rounded_cube.obj", 864, 1724, 2586),  # v/vt/vn syntax
    ],
)
def test_real_surfaces(name, nv, nf, ne):
    V, F = read_surface(os.path.join(DATA, name))
    assert V.shape == (nv, 3) and F.shape == (nf, 3) and np.isfinite(V).all()
    assert F.min() == 0 and F.max() == nv - 1
    assert unique_edges(F) == ne  # the statistics of shared/meshes/SOURCES.md


def test_real_tet_mesh():
    V, cells = read_medit(os.path.join(DATA, "octopus-low-tet.mesh"))
    T = cells[3]
    assert V.shape == (452, 3) and T.shape == (1140, 4) and cells[2].shape == (898, 3)
    e = V[T[:, 1:]] - V[T[:, :1]]
    assert (np.linalg.det(e) > 0).all()  # all tets positively oriented (SOURCES.md)
    faces = np.sort(np.concatenate([T[:, [1, 2, 3]], T[:, [0, 2, 3]], T[:, [0, 1, 3]], T[:, [0, 1, 2]]]), axis=1)
    u, c = np.unique(faces, axis=0, return_counts=True)
    assert len(u) == 2729 and unique_edges(T) == 2040
    np.testing.assert_array_equal(np.unique(np.sort(cells[2], axis=1), axis=0), u[c == 1])  # file boundary


def test_files_written_by_meshio_read_back_identically():
    """A third-party writer (meshio 5.3.5, see tests/data/SOURCES.md): Gmsh 2.2 and 4.1, VTK, Medit, PLY."""
    V, cells = read_cells(os.path.join(DATA, "meshio-mixed.mesh"))
    assert V.shape == (30, 3) and cells[2].shape == (25, 3) and cells[3].shape == (20, 4)
    for name in ("meshio-mixed-v22.msh", "meshio-mixed.vtk", "meshio-tet-v41.msh"):
        V2, cells2 = read_cells(os.path.join(DATA, name))
        np.testing.assert_array_equal(V2, V)
        np.testing.assert_array_equal(cells2[3], cells[3])
        if "tet" not in name:
            np.testing.assert_array_equal(cells2[2], cells[2])
    V2, F2 = read_surface(os.path.join(DATA, "meshio-tri-binary.ply"))
    np.testing.assert_array_equal(V2, V)
    np.testing.assert_array_equal(F2, cells[2])


def test_bundled_examples():
    V, F = read_surface(example_path("torus.obj"))
    assert V.shape == (288, 3) and F.shape == (576, 3) and len(V) - unique_edges(F) + len(F) == 0
    m = load(example_path("solid-torus.mesh"))
    assert m.kind == "volume" and m.top_cells.shape == (384, 4) and m.to_complex().euler_characteristic == 0
    with pytest.raises(FileNotFoundError, match=r"torus.obj"):
        example_path("nope.obj")


# ---------------------------------------------------------------------------------- compact_mesh
@settings(max_examples=25, deadline=None)
@given(mesh=meshes(max_cells=4), extra=st.integers(0, 3))
def test_compact_mesh_maps_back_to_the_input(mesh, extra):
    V, F = mesh
    V = np.vstack([V, np.zeros((extra, 3))])
    used = np.unique(F)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        V2, F2, kept = compact_mesh(V, F)
    np.testing.assert_array_equal(kept, used)
    np.testing.assert_array_equal(kept[F2], F)
    np.testing.assert_array_equal(V2, V[kept])
    n_dropped = len(V) - len(used)
    warned = [w for w in caught if issubclass(w.category, UnreferencedVertexWarning)]
    assert len(warned) == (1 if n_dropped else 0)
    if n_dropped:
        assert f"{n_dropped} of {len(V)} vertices" in str(warned[0].message)


def test_compact_mesh_rejects_bad_cells():
    with pytest.raises(InvalidSimplexError, match=r"cell 1 \(0, 1, 9\)"):
        compact_mesh(np.zeros((4, 3)), np.array([[0, 1, 2], [0, 1, 9]]))
    with pytest.raises(InvalidSimplexError, match="integer"):
        compact_mesh(np.zeros((4, 3)), np.array([[0.0, 1.0, 2.0]]))


def test_load_dispatch_and_kinds(tmp_path):
    m = load(os.path.join(DATA, "moebius.obj"))
    assert (m.format, m.kind, m.dim) == ("obj", "surface", 2)
    m = load(os.path.join(DATA, "octopus-low-tet.mesh"))
    assert m.kind == "volume" and sorted(m.cells) == [2, 3]
    assert m.to_complex().counts == (452, 2040, 2729, 1140)
    write(tmp_path, "c.dat", "0 1\n1 2\n")
    assert load(tmp_path / "c.dat", fmt="simplices").kind == "complex"
    write_cells(tmp_path / "curve.vtk", np.eye(3), np.array([[0, 1], [1, 2]]))
    assert load(tmp_path / "curve.vtk").kind == "curve"
    # a tet and a dangling edge: the complex is generated by all cells, not just the top ones
    write_cells(tmp_path / "mixed.msh", np.eye(5, 3), {3: np.array([[0, 1, 2, 3]]), 1: np.array([[3, 4]])})
    assert load(tmp_path / "mixed.msh").to_complex().counts == (5, 7, 4, 1)
