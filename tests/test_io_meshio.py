"""dhlb.io.meshio_bridge and dhlb.io.paraview: .vtu/.vtp output of results, meshio input; read back with meshio."""

import itertools
import os
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

meshio = pytest.importorskip("meshio")

from dhlb.errors import (  # noqa: E402
    InvalidParameterError,
    MeshParseError,
    NonFiniteError,
    OutputError,
    ShapeError,
)
from dhlb.io import example_path, read_ply, read_surface, read_vtk  # noqa: E402
from dhlb.io.meshio_bridge import (  # noqa: E402
    MESHIO_EXTRA,
    read_with_meshio,
    write_vtp_curves,
    write_vtu_surface,
    write_vtu_volume,
)
from dhlb.io.paraview import field_to_vtu, stripes_to_vtu, vortex_to_vtu  # noqa: E402
from dhlb.stripes import SectionOptions, StripeOptions  # noqa: E402

DATA = Path(__file__).parent / "data"


def _read_vtp(path):
    """(points, list of point-index lists, cell arrays) of a .vtp: with VTK when installed, else ElementTree."""
    try:
        from vtkmodules.util.numpy_support import vtk_to_numpy
        from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
    except ImportError:
        piece = ET.parse(path).getroot().find("PolyData/Piece")
        arr = {a.get("Name"): np.array((a.text or "").split(), float) for a in piece.iter("DataArray")}
        X = arr["Points"].reshape(-1, 3)
        conn, off = arr["connectivity"].astype(int), arr["offsets"].astype(int)
        cells = [conn[a:b].tolist() for a, b in zip(np.r_[0, off[:-1]], off)]
        cd = {a.get("Name"): arr[a.get("Name")] for a in piece.find("CellData")}
        return X, cells, cd
    r = vtkXMLPolyDataReader()
    r.SetFileName(str(path))
    r.Update()
    out = r.GetOutput()
    X = vtk_to_numpy(out.GetPoints().GetData()) if out.GetNumberOfPoints() else np.zeros((0, 3))
    lines = out.GetLines()
    conn = vtk_to_numpy(lines.GetConnectivityArray())
    off = vtk_to_numpy(lines.GetOffsetsArray())
    cells = [conn[a:b].tolist() for a, b in itertools.pairwise(off)]
    cd = {out.GetCellData().GetArrayName(i): vtk_to_numpy(out.GetCellData().GetArray(i))
          for i in range(out.GetCellData().GetNumberOfArrays())}
    return X, cells, cd


# ---------------------------------------------------------------------------- plain meshes
@pytest.mark.parametrize("binary", [True, False])
def test_surface_round_trip_with_arrays(tmp_path, binary):
    V, F = read_surface(example_path("torus.obj"))
    rng = np.random.default_rng(1)
    h, vec, z, k = rng.normal(size=len(V)), rng.normal(size=(len(V), 3)), rng.normal(size=len(V)) * 1j + 2, \
        rng.integers(-3, 4, len(F))
    p = write_vtu_surface(tmp_path / "t.vtu", V, F, point_data={"h": h, "vec": vec, "z": z},
                          cell_data={"k": k, "flag": k > 0}, binary=binary)
    m = meshio.read(p)
    same = np.array_equal if binary else lambda a, b: np.allclose(a, b, rtol=1e-11, atol=0)  # ASCII: 12 digits
    assert same(m.points, V) and np.array_equal(m.cells_dict["triangle"], F)
    assert same(m.point_data["h"], h) and same(m.point_data["vec"], vec)
    assert same(m.point_data["z"], np.column_stack([z.real, z.imag]))
    assert np.array_equal(m.cell_data["k"][0], k) and np.array_equal(m.cell_data["flag"][0], (k > 0).astype(np.uint8))
    assert [f for f in os.listdir(tmp_path)] == ["t.vtu"]   # no temporary file left


@given(n=st.integers(3, 40), m=st.integers(1, 60), seed=st.integers(0, 2**32 - 1))
def test_random_triangle_meshes_round_trip_bitwise(n, m, seed):
    import tempfile

    rng = np.random.default_rng(seed)
    V = rng.normal(size=(n, 3)) * 10.0 ** rng.integers(-8, 8)
    F = rng.integers(0, n, size=(m, 3))
    with tempfile.TemporaryDirectory() as d:
        V2, F2 = read_with_meshio(write_vtu_surface(os.path.join(d, "r.vtu"), V, F))
    assert np.array_equal(V2, V) and np.array_equal(F2, F)


def test_volume_round_trip(tmp_path):
    from dhlb.mesh import box_tet_mesh

    mesh = box_tet_mesh(3, lower=-1, upper=1)
    p = write_vtu_volume(tmp_path / "b.vtu", mesh.points, mesh.tets, point_data={"x": mesh.points[:, 0]},
                         cell_data={"vol": mesh.volumes})
    m = meshio.read(p)
    assert np.array_equal(m.cells_dict["tetra"], mesh.tets)
    assert np.array_equal(m.point_data["x"], mesh.points[:, 0])
    assert m.cell_data["vol"][0].sum() == pytest.approx(8.0, rel=1e-14)


def test_curves_as_vtp_and_as_line_cells(tmp_path):
    ring = (np.array([[1.0, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0]]), True)
    chain = np.array([[0.0, 0, -1], [0, 0, 0], [0, 0, 1]])
    X, cells, cd = _read_vtp(write_vtp_curves(tmp_path / "c.vtp", [ring, chain]))
    assert np.array_equal(X, np.vstack([ring[0], chain]))
    assert cells == [[0, 1, 2, 3, 0], [4, 5, 6]]
    assert cd["closed"].tolist() == [1, 0] and cd["curve"].tolist() == [0, 1]
    m = meshio.read(write_vtp_curves(tmp_path / "c.vtu", [ring, chain]))
    assert m.cells_dict["line"].tolist() == [[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6]]
    assert m.cell_data["closed"][0].tolist() == [1, 1, 1, 1, 0, 0]
    assert m.point_data["curve"].tolist() == [0, 0, 0, 0, 1, 1, 1]


# ---------------------------------------------------------------------------- reading
def test_read_with_meshio_agrees_with_the_strict_readers():
    V, F = read_with_meshio(DATA / "meshio-tri-binary.ply")
    V2, F2 = read_ply(DATA / "meshio-tri-binary.ply")[:2]
    assert np.array_equal(V, V2) and np.array_equal(F, F2)
    for name in ("meshio-mixed.vtk", "meshio-mixed-v22.msh", "meshio-mixed.mesh"):   # tets beside: ignored
        V3, F3 = read_with_meshio(DATA / name)
        assert np.allclose(V3, V) and np.array_equal(F3, F), name
    Vk, cells = read_vtk(DATA / "meshio-mixed.vtk")
    assert np.array_equal(cells[2], F) and np.allclose(Vk, V)


def test_read_with_meshio_errors(tmp_path):
    with pytest.raises(MeshParseError, match=r"meshio-tet-v41\.msh.*no triangle cells.*read_volume"):
        read_with_meshio(DATA / "meshio-tet-v41.msh")
    bad = tmp_path / "garbage.vtu"
    bad.write_text("<VTKFile> not really </VTKFile>")
    with pytest.raises(MeshParseError, match=r"garbage\.vtu: meshio cannot read it"):
        read_with_meshio(bad)
    with pytest.raises(FileNotFoundError, match=r"nothing\.vtu"):
        read_with_meshio(tmp_path / "nothing.vtu")
    q = tmp_path / "quads.vtu"
    meshio.write(q, meshio.Mesh(np.eye(4, 3), [("triangle", [[0, 1, 2]]), ("quad", [[0, 1, 2, 3]])]))
    with pytest.raises(MeshParseError, match="quad"):
        read_with_meshio(q)
    n = tmp_path / "nan.vtu"
    meshio.write(n, meshio.Mesh(np.array([[0, 0, 0], [1, np.nan, 0], [0, 1, 0]]), [("triangle", [[0, 1, 2]])]))
    with pytest.raises(NonFiniteError, match="vertex 1"):
        read_with_meshio(n)


def test_writer_errors_name_the_file_and_the_array(tmp_path):
    V, F = np.eye(3), np.array([[0, 1, 2]])
    with pytest.raises(ShapeError, match=r"s\.vtu: point data 'h' needs one row per point \(3\)"):
        write_vtu_surface(tmp_path / "s.vtu", V, F, point_data={"h": [1.0, 2.0]})
    with pytest.raises(ShapeError, match=r"face 0 .* outside the points \(rows 0 \.\. 2\)"):
        write_vtu_surface(tmp_path / "s.vtu", V, [[0, 1, 3]])
    with pytest.raises(NonFiniteError, match="point 2"):
        write_vtu_surface(tmp_path / "s.vtu", [[0, 0, 0], [1, 0, 0], [0, np.inf, 0]], F)
    with pytest.raises(NonFiniteError, match="curve 1"):
        write_vtp_curves(tmp_path / "c.vtp", [np.eye(3), [[0, 0, np.nan]]])
    with pytest.raises(OutputError, match="missing"):
        write_vtu_surface(tmp_path / "missing" / "s.vtu", V, F)
    with pytest.raises(InvalidParameterError, match="field_to_vtu needs the result of"):
        field_to_vtu(object(), tmp_path / "f.vtu")
    assert not list(tmp_path.iterdir())


def test_missing_meshio_names_the_extra(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "meshio", None)
    with pytest.raises(ImportError, match=r'pip install meshio .*"\.\[meshio\]"') as info:
        write_vtu_surface(tmp_path / "s.vtu", np.eye(3), [[0, 1, 2]])
    assert str(info.value) == MESHIO_EXTRA
    with pytest.raises(ImportError, match=r'pip install meshio .*"\.\[meshio\]"'):
        read_with_meshio(DATA / "meshio-tri-binary.ply")


# ---------------------------------------------------------------------------- results
def test_field_to_vtu_holds_the_directions_and_indices(tmp_path):
    from dhlb.fields import direction_field

    V, F = read_surface(example_path("spot.obj"))
    res = direction_field(V, F, n=4)
    m = meshio.read(field_to_vtu(res, tmp_path / "spot.vtu"))
    for k in range(4):
        assert np.array_equal(m.point_data[f"d{k}"], res.directions[:, k])
    assert np.array_equal(m.point_data["u"][:, 0] + 1j * m.point_data["u"][:, 1], res.u)
    idx = m.cell_data["index"][0]
    assert idx.sum() == 4 * 2 == res.index_sum                     # Poincaré–Hopf on the sphere
    assert np.count_nonzero(idx) == len(res.singularities.faces)
    assert int(m.field_data["n"][0]) == 4 and int(m.field_data["euler_characteristic"][0]) == 2


def test_stripes_to_vtu(tmp_path):
    from dhlb.fields import direction_field
    from dhlb.stripes import stripe_pattern

    V, F = read_surface(example_path("torus.obj"))
    res = stripe_pattern(V, F, direction_field(V, F, n=2), spacing=6.0,
                         options=StripeOptions(section=SectionOptions(kind="eigenvector")))
    m = meshio.read(stripes_to_vtu(res, tmp_path / "s.vtu"))
    assert np.array_equal(m.cell_data["corner_alpha"][0], res.corner_alpha)
    assert np.array_equal(m.cell_data["branch"][0].astype(bool), res.texture.is_branch)
    assert m.cell_data["zero_index"][0].sum() == res.zero_index.sum()


def test_vortex_to_vtu_ring(tmp_path):
    from dhlb.mesh import box_tet_mesh
    from dhlb.vortex import FilamentField, vortex_filaments, vortex_ring

    mesh = box_tet_mesh(8, lower=(-1, -1, -1), upper=(1, 1, 1))
    field = FilamentField([vortex_ring(0.6, center=(0.01, 0.005, 0.01))], circulation=2 * np.pi, core_radius=0.1)
    res = vortex_filaments(mesh, None, field, hbar=1.0)
    paths = vortex_to_vtu(res, tmp_path / "ring.vtu", field)
    assert [os.path.basename(p) for p in paths] == ["ring.vtu", "ring-filaments.vtp"]
    m = meshio.read(paths[0])
    assert np.array_equal(m.cells_dict["tetra"], mesh.tets)
    psi = m.point_data["psi"][:, 0] + 1j * m.point_data["psi"][:, 1]
    assert np.array_equal(psi, res.psi) and np.array_equal(m.point_data["psi_abs"], np.abs(res.psi))
    assert np.allclose(m.point_data["velocity"], field(mesh.points), rtol=1e-14, atol=0)
    X, cells, _ = _read_vtp(paths[1])
    assert len(cells) == len(res.filaments) == 1
    f = res.filaments[0]
    assert np.array_equal(X, f.points) and cells[0] == list(range(len(f.points))) + [0]
    assert m.field_data["n_filaments"][0] == 1
    arr = field(mesh.points)[np.argsort(mesh.complex.vertex_labels)]    # per input row (identity here)
    m2 = meshio.read(vortex_to_vtu(res, tmp_path / "ring2.vtu", arr, filaments=None)[0])
    assert np.array_equal(m2.point_data["velocity"], m.point_data["velocity"])
    with pytest.raises(ShapeError, match="velocity"):
        vortex_to_vtu(res, tmp_path / "bad.vtu", np.zeros((3, 3)))
