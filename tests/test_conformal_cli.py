"""``dhlb conformal``: outputs (.mesh, .vtk, .json, .png), charges and u files, exit codes.

Runs through :func:`dhlb.cli.main`, so parse-time value checks count as the exit code 2 they give.
"""

from __future__ import annotations

import json

import numpy as np

from dhlb.cli import main
from dhlb.io import read_volume, write_volume
from dhlb.mesh import ball_tet_mesh, box_tet_mesh


def dhlb_conformal(argv, capsys):
    code = main(["conformal", *argv])  # parse-time checks exit 2 too (issue 28)
    out, err = capsys.readouterr()
    return code, out, err


def test_charges_write_mesh_vtk_json_png(tmp_path, capsys):
    mesh = ball_tet_mesh(3)
    src = tmp_path / "ball.mesh"
    write_volume(src, mesh.points, mesh.tets)
    out = tmp_path / "def.mesh"
    code, text, err = dhlb_conformal([str(src), "--charge", "0,0,2,1", "--charge", "1.8,0,0,-0.5", "-o",
                                      str(tmp_path / "def")], capsys)  # a base name: the default set
    assert code == 0, err
    assert "distortion" in text and "2 point charges" not in text  # the labels are listed
    assert "charge #1 (q = -0.5)" in text
    V, T = read_volume(out)
    V2, T2 = read_volume(tmp_path / "def.vtk")
    assert np.allclose(V, V2) and np.array_equal(T, T2) and T.shape == mesh.tets.shape
    assert not np.allclose(V, mesh.points)
    data = json.loads((tmp_path / "def.json").read_text())
    assert data["eigenvalue"] > 0 and data["statistics"]["inverted_tets"] == 0
    assert (tmp_path / "def.png").read_bytes()[:4] == b"\x89PNG"


def test_u_file_and_json(tmp_path, capsys):
    mesh = box_tet_mesh(2)
    src = tmp_path / "box.vtk"
    write_volume(src, mesh.points, mesh.tets)
    np.save(tmp_path / "u.npy", np.full(27, 0.3))
    code, text, err = dhlb_conformal([str(src), "--u", str(tmp_path / "u.npy"), "--json"], capsys)
    assert code == 0, err
    data = json.loads(text)
    assert abs(data["statistics"]["distortion_max"] - 1) < 1e-10 and abs(data["eigenvalue"]) < 1e-12


def test_errors_and_exit_codes(tmp_path, capsys):
    mesh = box_tet_mesh(2)
    src = tmp_path / "box.mesh"
    write_volume(src, mesh.points, mesh.tets)
    code, _, err = dhlb_conformal([str(src), "--charge", "0.5,0.5,0.5,1"], capsys)     # inside: refused
    assert code == 1 and "lies inside" in err and "nearest vertex" in err
    code, _, err = dhlb_conformal([str(src), "--charge", "1,2,3"], capsys)
    assert code == 2 and "four finite numbers" in err
    np.save(tmp_path / "bad.npy", np.zeros(5))
    code, _, err = dhlb_conformal([str(src), "--u", str(tmp_path / "bad.npy")], capsys)
    assert code == 2 and "(27,)" in err
    code, _, err = dhlb_conformal([str(src), "-o", str(tmp_path / "x.ply")], capsys)
    assert code == 2 and "does not write .ply files" in err and ".mesh, .msh, .vtk, .vtu" in err
    code, _, err = dhlb_conformal([str(tmp_path / "missing.mesh")], capsys)
    assert code == 2 and "no such file" in err


def test_default_ball(capsys):
    code, text, err = dhlb_conformal(["--ball", "2"], capsys)
    assert code == 0, err
    assert "ball 2" in text and "eigenvalue" in text


def test_derived_outputs_never_overwrite_the_input(tmp_path):
    """-o ball (a base name) writes ball.mesh: with ball.mesh as the input that is refused before any work."""
    from dhlb.cli import main
    from dhlb.io import write_volume
    from dhlb.mesh import ball_tet_mesh

    m = ball_tet_mesh(2)
    src = tmp_path / "ball.mesh"
    write_volume(src, m.points, m.tets)
    before = src.read_bytes()
    assert main(["conformal", str(src), "-o", str(tmp_path / "ball"), "--no-png", "-q"]) == 2
    assert src.read_bytes() == before
    assert main(["conformal", str(src), "-o", str(tmp_path / "out.vtu"), "--no-png", "-q"]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ball.mesh", "out.vtu"]
