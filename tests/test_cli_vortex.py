"""``dhlb vortex``: outputs (PLY/OBJ polylines, JSON, PNG), demo fields, mesh files, exit codes.

The command is not registered in :mod:`dhlb.commands` by these tests: the parser is built from
``argparse`` and :func:`dhlb.cli.vortex.register`.
"""

from __future__ import annotations

import argparse
import json

import numpy as np
import pytest

from dhlb.cli import vortex
from dhlb.cli._common import run_command
from dhlb.mesh import box_tet_mesh
from dhlb.vortex import linking_number, vortex_ring


def dhlb_vortex(argv, capsys):
    parser = argparse.ArgumentParser(prog="dhlb")
    sub = parser.add_subparsers(dest="command")
    vortex.register(sub)
    try:
        code = run_command(parser.parse_args(["vortex", *argv]))
    except SystemExit as exc:  # a usage error found by argparse (bad value): exit 2, one line
        code = exc.code
    out, err = capsys.readouterr()
    err = "\n".join(line for line in err.splitlines() if not line.startswith(("usage:", " ")))
    return code, out, err


def read_ply_polylines(path):
    with open(path) as fh:
        lines = fh.read().splitlines()
    end = lines.index("end_header")
    nv = int(next(s for s in lines if s.startswith("element vertex")).split()[-1])
    ne = int(next(s for s in lines if s.startswith("element edge")).split()[-1])
    V = np.array([[float(x) for x in s.split()] for s in lines[end + 1:end + 1 + nv]])
    E = np.array([[int(x) for x in s.split()] for s in lines[end + 1 + nv:end + 1 + nv + ne]])
    return V, E


def test_ring_writes_ply_json_png(tmp_path, capsys):
    code, text, err = dhlb_vortex(["--box", "8", "-o", str(tmp_path / "ring")], capsys)  # the default set
    assert code == 0, err
    assert "filaments      1 (1 closed, 0 open" in text and "wrote" in text
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ring.json", "ring.obj", "ring.png"]
    out = tmp_path / "ring.ply"
    code, text, err = dhlb_vortex(["--box", "8", "-o", str(out)], capsys)  # one format
    assert code == 0, err
    data = json.loads((tmp_path / "ring.json").read_text())
    assert {"filaments", "linking_numbers", "timings", "statistics", "hbar", "mesh", "velocity"} <= set(data)
    assert len(data["filaments"]) == 1 and data["filaments"][0]["closed"] is True
    V, E = read_ply_polylines(out)
    P = np.array(data["filaments"][0]["points"])
    assert np.array_equal(V[:, :3], P) and np.all(V[:, 3] == 0)
    m = len(P)
    assert E.tolist() == [[i, (i + 1) % m] for i in range(m)]  # a closed polyline, in filament order
    assert (tmp_path / "ring.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_json_linked_rings_and_obj(tmp_path, capsys):
    out = tmp_path / "rings.obj"
    code, text, err = dhlb_vortex(["--box", "12", "--velocity", "linked-rings", "--json", "-o", str(out), "--no-png"],
                                  capsys)
    assert code == 0, err
    data = json.loads(text)
    assert len(data["filaments"]) == 2 and all(f["closed"] for f in data["filaments"])
    assert data["linking_numbers"] == [[0, 1], [1, 0]]
    assert set(data["timings"]) >= {"mesh", "omega", "assembly", "solve", "extraction"}
    assert not (tmp_path / "rings.png").exists()
    lines = out.read_text().splitlines()
    v = [s for s in lines if s.startswith("v ")]
    ls = [s.split()[1:] for s in lines if s.startswith("l ")]
    assert len(v) == sum(len(f["points"]) for f in data["filaments"]) and len(ls) == 2
    assert all(idx[0] == idx[-1] for idx in ls)  # closed polylines repeat their first vertex
    first = np.array([[float(x) for x in s.split()[1:]] for s in v])[[int(i) - 1 for i in ls[0][:-1]]]
    assert np.allclose(first, data["filaments"][0]["points"], rtol=0, atol=1e-15)


def test_trefoil_filament_winds_three_times_around_its_core(capsys):
    code, text, err = dhlb_vortex(["--box", "12", "--velocity", "trefoil", "--json"], capsys)
    assert code == 0, err
    data = json.loads(text)
    assert len(data["filaments"]) == 1 and data["filaments"][0]["closed"]
    core = vortex_ring(0.55, center=(0.013, 0.007, 0.011), n=200)  # the core circle of the torus
    assert linking_number(np.array(data["filaments"][0]["points"]), core) == -3  # as the input (2, 3) torus knot


def test_mesh_file_and_npy_velocity(tmp_path, capsys):
    from dhlb.io import write_volume

    mesh = box_tet_mesh(6, lower=-1.0, upper=1.0)
    path = tmp_path / "box.mesh"
    write_volume(path, mesh.points, mesh.tets)
    code, text, err = dhlb_vortex([str(path), "--json"], capsys)
    assert code == 0, err
    code2, text2, _ = dhlb_vortex(["--box", "6", "--json"], capsys)
    assert code2 == 0
    a, b = json.loads(text), json.loads(text2)
    assert len(a["filaments"]) == len(b["filaments"]) == 1
    assert np.allclose(a["filaments"][0]["points"], b["filaments"][0]["points"], atol=1e-9)
    vel = tmp_path / "v.npy"
    np.save(vel, np.tile([0.3, -1.0, 2.0], (mesh.points.shape[0], 1)))  # uniform flow: no filament
    code, text, err = dhlb_vortex([str(path), "--velocity", str(vel), "--json"], capsys)
    assert code == 0, err
    assert json.loads(text)["filaments"] == []


def test_errors_and_exit_codes(tmp_path, capsys):
    bad = tmp_path / "bad.npy"
    np.save(bad, np.zeros((5, 3)))
    nan = tmp_path / "nan.npy"
    arr = np.zeros((27, 3))
    arr[4, 2] = np.nan
    np.save(nan, arr)
    cases = [
        (["--box", "2", "--velocity", str(bad)], 1, "shape (27, 3)"),
        (["--box", "2", "--velocity", str(nan)], 1, "vertex 4"),
        (["--box", "2", "--hbar", "0"], 2, "--hbar: '0' is out of range"),  # usage errors (issue 19)
        (["--box", "2", "--hbar", "-1"], 2, "hbar"),
        (["--box", "2", "-o", str(tmp_path / "out.txt")], 2, "does not write .txt files"),
        (["--box", "2", "--velocity", "vortex-street"], 2, "--velocity must be"),
        (["--box", "2", "--velocity", str(tmp_path / "missing.npy")], 2, "no such file"),
        (["--box", "0"], 2, "--box: 0 is out of range"),
        ([str(tmp_path / "missing.mesh")], 2, "no such file"),
        ([str(tmp_path / "x.mesh"), "--box", "3"], 2, "either TETMESH or --box"),
    ]
    for argv, want, msg in cases:
        code, _, err = dhlb_vortex(argv, capsys)
        assert code == want and msg in err, (argv, code, err)
        assert "Traceback" not in err and len(err.strip().splitlines()) == 1


def test_unresolved_core_warning_on_stderr(capsys):
    code, _, err = dhlb_vortex(["--box", "4", "--core", "0.01"], capsys)
    assert code == 0
    assert "warning:" in err and "> π" in err and "on the triangle (" in err
    code, _, err = dhlb_vortex(["--box", "4", "--core", "0.01", "-q"], capsys)
    assert code == 0 and err == ""


@pytest.mark.parametrize("name", vortex.DEMOS)
def test_demo_fields_are_centred_in_the_box(name):
    P = np.array([[0.0, -1, 2], [4, 3, 4]])  # box [0, 4] x [-1, 3] x [2, 4]: rho = 1
    field, curves = vortex.demo_velocity(name, P)
    allc = np.concatenate(curves)
    assert np.all(allc > P[0]) and np.all(allc < P[1])
    assert field.core_radius == pytest.approx(0.08)


def test_vtu_output_opens_with_meshio(tmp_path):
    """Issue 23: dhlb vortex -o OUT.vtu writes the tet mesh with ψ, |ψ|, the velocity, and the filaments beside it."""
    meshio = pytest.importorskip("meshio")
    from dhlb.cli import main

    assert main(["vortex", "--box", "8", "-o", str(tmp_path / "v.vtu"), "--no-png", "-q"]) == 0
    m = meshio.read(tmp_path / "v.vtu")
    assert {"psi", "psi_abs", "velocity"} <= set(m.point_data) and "tetra" in m.cells_dict
    assert (tmp_path / "v-filaments.vtp").exists()


def test_progress_on_stderr_and_quiet_silences_it(tmp_path):
    """Issue 23: a run expected to take seconds reports its phases on stderr; -q silences it."""
    import subprocess
    import sys

    pytest.importorskip("tqdm")
    cmd = [sys.executable, "-m", "dhlb", "vortex", "--box", "24", "--no-png", "-o", str(tmp_path / "r.ply")]
    loud = subprocess.run(cmd, capture_output=True, text=True, check=True)
    assert "vortex filaments" in loud.stderr
    quiet = subprocess.run([*cmd, "-q"], capture_output=True, text=True, check=True)
    assert "vortex filaments" not in quiet.stderr


def test_png_title_counts_one_filament_in_the_singular(tmp_path, capsys, monkeypatch):
    """Issue 42, point 9: the ring's picture said "1 filaments"."""
    import dhlb.render.filaments_png as fp

    titles = []
    real = fp.render_filaments_png
    monkeypatch.setattr(fp, "render_filaments_png", lambda *a, **k: titles.append(k.get("title")) or real(*a, **k))
    code, _, err = dhlb_vortex(["--box", "8", "-o", str(tmp_path / "ring.png")], capsys)
    assert code == 0, err
    assert len(titles) == 1 and titles[0].endswith(": 1 filament"), titles
