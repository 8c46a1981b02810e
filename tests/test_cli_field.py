"""``dhlb field``: outputs (PLY with directions, npz, JSON, PNG), --json, alignment files, errors."""

from __future__ import annotations

import json
import os
import re

import numpy as np
import pytest

import dhlb.cli.field as field_cmd
from dhlb.cli import main
from dhlb.fields import direction_field
from dhlb.io import read_ply, write_obj
from tests.surface_meshes import ellipsoid, grid

DATA = os.path.join(os.path.dirname(__file__), "data")


def cli(argv, capsys):
    code = main([field_cmd.NAME] + [str(a) for a in argv])  # parse-time checks exit 2 too (issue 28)
    out, err = capsys.readouterr()
    return code, out, err


def test_cross_field_on_the_rounded_cube_writes_everything(tmp_path, capsys):
    out = tmp_path / "cube"
    code, text, err = cli([os.path.join(DATA, "rounded_cube.obj"), "--n", 4, "-o", out, "--json"], capsys)
    assert code == 0, err
    summary = json.loads(text)
    assert summary["index_sum"] == 8 == summary["euler_characteristic"] * 4 and summary["poincare_hopf"] == 8
    assert [s["index"] for s in summary["singularities"]] == [1] * 8
    assert {"setup", "solve", "indices", "io", "output", "end_to_end"} <= set(summary["timings"])
    assert summary["eigenvalue"] > 0
    assert json.loads((tmp_path / "cube.json").read_text())["index_sum"] == 8
    # the npz and the PLY carry the same directions, in the input numbering
    z = np.load(tmp_path / "cube.npz")
    assert z["directions"].shape[1:] == (4, 3) and z["face_index"].sum() == 8
    assert z["singular_faces"].tolist() == [s["face"] for s in summary["singularities"]]
    data = (tmp_path / "cube.ply").read_bytes()
    header = data[: data.index(b"end_header")].decode()
    assert "property double d3z" in header and "binary_little_endian" in header
    V, _ = read_ply(tmp_path / "cube.ply")
    nv = len(V)
    body = np.frombuffer(data[data.index(b"end_header") + 11:][: nv * 15 * 8], dtype="<f8").reshape(nv, 15)
    assert np.allclose(body[:, 3:].reshape(nv, 4, 3), z["directions"])
    assert (tmp_path / "cube.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_singularity_faces_are_input_rows_and_unreferenced_vertices_are_dropped(tmp_path, capsys):
    V, F = ellipsoid(2)  # distinct axes: a simple smallest eigenvalue, so the field is unique
    W = np.vstack([[[5.0, 5, 5]], V])
    path = tmp_path / "s.obj"
    write_obj(path, W, F + 1)
    code, text, err = cli([path, "--n", 1, "-o", tmp_path / "s", "--json", "--no-png"], capsys)
    assert code == 0 and "used by no face" in err
    summary = json.loads(text)
    ref = direction_field(V, F, n=1).singularities
    assert [s["face"] for s in summary["singularities"]] == ref.input_faces.tolist()
    assert np.allclose([s["position"] for s in summary["singularities"]], ref.points)
    z = np.load(tmp_path / "s.npz")
    assert np.isnan(z["directions"][0]).all() and np.isfinite(z["directions"][1:]).all()
    assert not (tmp_path / "s.png").exists()


def test_alignment_from_files(tmp_path, capsys):
    V, F = grid(5, 4)
    path = tmp_path / "g.obj"
    write_obj(path, V, F)
    vec = tmp_path / "v.npy"
    np.save(vec, np.tile([0.0, 1.0, 0.0], (len(V), 1)))
    code, text, err = cli([path, "--align", vec, "--lambda", -1, "-o", tmp_path / "g", "--json"], capsys)
    assert code == 0, err
    z = np.load(tmp_path / "g.npz")
    assert np.allclose(z["directions"][:, 0], [0, 1, 0], atol=1e-12)
    assert json.loads(text)["alignment"] == "user"
    np.save(vec, np.ones(len(V), complex))  # complex values in the frames
    assert cli([path, "--n", 2, "--align", vec, "--lambda", -1, "-o", tmp_path / "g", "--json"], capsys)[0] == 0
    code, text, err = cli([path, "--n", 2, "--align", "curvature", "-o", tmp_path / "h", "--quiet"], capsys)
    assert code == 0 and err == "" and text == ""
    code, text, err = cli([path, "--n", 2, "--align", "curvature", "-o", tmp_path / "h"], capsys)
    assert code == 0 and "flat" in err and "Σ index" in text


@pytest.mark.parametrize("argv, code, message", [
    (["moebius-160-10.ply", "--n", 2], 1, "not orientable"),
    (["rounded_cube.obj", "--n", 1, "--align", "curvature"], 1, "even n"),
    (["rounded_cube.obj", "--align", "sideways"], 2, "--align must be one of"),
    (["rounded_cube.obj", "--align", "missing.npy"], 2, "no such file"),
    (["nothere.obj"], 2, "no such file"),
    (["octopus-low-tet.mesh"], 1, "volume mesh"),
])
def test_errors(tmp_path, capsys, argv, code, message):
    argv = [os.path.join(DATA, argv[0]) if os.path.exists(os.path.join(DATA, argv[0])) else argv[0]] + argv[1:]
    got, _, err = cli(argv + ["-o", tmp_path / "x"], capsys)
    assert got == code
    assert len(err.strip().splitlines()) == 1
    assert re.search(message, err), err


def test_output_is_required(capsys):
    code, _, err = cli([os.path.join(DATA, "rounded_cube.obj")], capsys)
    assert code == 2 and "-o OUT" in err


def test_prescribed_singularities_by_face_and_by_point(tmp_path, capsys):
    from dhlb.io import example_path, read_surface

    V, F = read_surface(example_path("spot.obj"))
    c = V[F[3000]].mean(axis=0)
    point = ",".join(f"{x:.9f}" for x in c)
    code, text, err = cli([example_path("spot.obj"), "--n", 1, "--singularity", "0:1",
                           f"--singularity={point}:1", "-o", tmp_path / "p", "--json", "--no-png"], capsys)
    assert code == 0, err
    summary = json.loads(text)
    assert sorted((s["face"], s["index"]) for s in summary["singularities"]) == [(0, 1), (3000, 1)]
    assert summary["prescribed"] == [{"face": 0, "index": 1}, {"face": 3000, "index": 1}]
    assert summary["delta_norm"] > 0 and summary["index_sum"] == 2
    z = np.load(tmp_path / "p.npz")
    assert sorted(z["singular_faces"].tolist()) == [0, 3000]


@pytest.mark.parametrize("argv, code, message", [
    (["--singularity", "0:1"], 1, r"sum to 1.*n·χ = 1·2 = 2"),
    (["--singularity", "0:x"], 2, "must be an integer"),
    (["--singularity", "1,2:1"], 2, "face number or three finite"),
    (["--singularity", "0:1", "--singularity", "5:1", "--align", "curvature"], 2, "does not combine"),
])
def test_prescribed_singularity_errors(argv, code, message, tmp_path, capsys):
    from dhlb.io import example_path

    got, _, err = cli([example_path("spot.obj"), *argv, "-o", tmp_path / "e", "--no-png"], capsys)
    assert got == code and re.search(message, err), err


def test_npz_documents_unreferenced_vertices_and_vtu_output(tmp_path):
    """Issue 19 point 9 and issue 23: the .npz says which rows are NaN; -o OUT.vtu writes a ParaView file."""
    meshio = pytest.importorskip("meshio")
    from dhlb.cli import main

    V = np.array([[1.0, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1], [5, 5, 5]])
    F = [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]]
    src = tmp_path / "oct.obj"
    src.write_text("".join(f"v {x} {y} {z}\n" for x, y, z in V) + "".join(f"f {a+1} {b+1} {c+1}\n" for a, b, c in F))
    assert main(["field", str(src), "--n", "1", "-o", str(tmp_path / "out.vtu"), "--no-png", "-q"]) == 0
    assert main(["field", str(src), "--n", "1", "-o", str(tmp_path / "out.npz"), "--no-png", "-q"]) == 0
    data = np.load(tmp_path / "out.npz")
    assert data["vertex_used"].tolist() == [True] * 6 + [False]
    assert np.isnan(data["directions"][6]).all() and "NaN" in str(data["note"])
    m = meshio.read(tmp_path / "out.vtu")
    assert m.points.shape[0] >= 6 and "index" in m.cell_data


@pytest.mark.parametrize("ext", [".stl", ".vtu", ".mesh", ".vtk"])
def test_every_triangle_surface_format_is_accepted(tmp_path, ext):
    """Issues 17 and 23: dhlb field reads triangle surfaces in Medit/VTK and every format meshio reads."""
    meshio = pytest.importorskip("meshio")
    from dhlb.cli import main
    from dhlb.io import example_path, read_surface

    V, F = read_surface(example_path("torus.obj"))
    path = tmp_path / f"torus{ext}"
    meshio.write(path, meshio.Mesh(V, [("triangle", F)]), **({"binary": False} if ext == ".vtk" else {}))
    assert main(["field", str(path), "--n", "2", "-o", str(tmp_path / "out"), "--no-png", "-q"]) == 0
    assert json.loads((tmp_path / "out.json").read_text())["index_sum"] == 0
