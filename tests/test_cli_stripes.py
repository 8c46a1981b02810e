"""``dhlb stripes``: files written, the --json object, errors and exit codes."""

from __future__ import annotations

import json

import numpy as np
import pytest

from dhlb.cli import main
from dhlb.fields import direction_field
from dhlb.io import example_path, read_surface
from dhlb.stripes import stripe_pattern

TORUS = example_path("torus.obj")


def run(argv):
    return main(["stripes", *argv])  # parse-time checks exit 2 too (issue 28)


def parse_obj(path):
    v, vt, f, lines = [], [], [], []
    for line in open(path):
        k, *rest = line.split()
        if k == "v":
            v.append([float(x) for x in rest])
        elif k == "vt":
            vt.append(float(rest[0]))
        elif k == "f":
            f.append([[int(x) for x in c.split("/")] for c in rest])
        elif k == "l":
            lines.append([int(x) for x in rest])
    return np.array(v), np.array(vt), np.array(f), lines


def test_json_summary_and_files(tmp_path, capsys):
    out = tmp_path / "torus-stripes"
    assert run([TORUS, "--spacing", "4", "--n", "2", "-o", str(out), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert {"zero_faces", "branch_faces", "timings", "eigenvalue", "files"} <= set(data)
    assert all(set(z) >= {"face", "index"} and z["index"] != 0 for z in data["zero_faces"])
    assert set(data["timings"]) >= {"setup", "solve", "texture"}
    # the same pattern through the API: same singular faces, UVs u = α/2π per face corner
    V, F = read_surface(TORUS)
    res = stripe_pattern(V, F, direction_field(V, F, n=2), spacing=4.0)
    assert data["branch_faces"] == res.to_json()["branch_faces"]
    assert [(z["face"], z["index"]) for z in data["zero_faces"]] == \
        [(z["face"], z["index"]) for z in res.to_json()["zero_faces"]]
    _P, vt, f, _ = parse_obj(data["files"]["obj"])
    assert np.array_equal(f[:, :, 0] - 1, res.mesh.faces) and vt.size == 3 * len(f)
    # (the smoothest line field of this torus is degenerate: compare the pattern, not the phase)
    c = np.cos(2 * np.pi * vt)  # per corner; no zero or branch face here, so equal at every vertex
    assert not data["zero_faces"] and not data["branch_faces"]
    vert = f[:, :, 0].ravel() - 1
    lo = np.full(vert.max() + 1, np.inf)
    hi = np.full(vert.max() + 1, -np.inf)
    np.minimum.at(lo, vert, c)
    np.maximum.at(hi, vert, c)
    assert np.allclose(lo, hi, atol=1e-9)
    side = json.load(open(data["files"]["sidecar"]))
    assert side["branch"]["faces"] == res.branch_faces.tolist() and side["n"] == 2
    _Q, _, _, lines = parse_obj(data["files"]["isolines"])
    assert data["files"]["n_isolines"] == len(lines) > 0 and all(len(p) >= 2 for p in lines)
    assert (tmp_path / "torus-stripes.png").stat().st_size > 1000


def test_field_file_orthogonal_and_text_report(tmp_path, capsys):
    V, F = read_surface(TORUS)
    X = np.stack([-V[:, 1], V[:, 0], 0 * V[:, 0]], 1)  # around the axis
    np.savetxt(tmp_path / "dirs.txt", X)
    out = tmp_path / "t.obj"
    assert run([TORUS, "--frequency", "0.6", "--field", str(tmp_path / "dirs.txt"), "-o", str(out),
                "--orthogonal", "--no-png"]) == 0
    text = capsys.readouterr().out
    assert "zeros:" in text and "t-orthogonal.obj" in text
    assert not (tmp_path / "t.png").exists() and (tmp_path / "t-orthogonal.json").exists()
    res = stripe_pattern(V, F, X, 0.6)
    _, vt, _, _ = parse_obj(out)
    assert np.allclose(vt, res.corner_alpha.ravel() / (2 * np.pi), atol=1e-9)


@pytest.mark.parametrize("argv,code,msg", [
    (["--frequency=-1"], 2, "argument --frequency: '-1' is out of range: give a finite number > 0"),
    (["--spacing", "0"], 2, "argument --spacing: '0' is out of range: give a finite number > 0"),
    (["--spacing", "3", "--field", "nosuchfile.txt"], 2, "nosuchfile"),
    (["--spacing", "3", "--field", "curvature", "--n", "1"], 2, "--n 2"),
])
def test_errors(tmp_path, capsys, argv, code, msg):
    assert run([TORUS, *argv, "-o", str(tmp_path / "x")]) == code
    assert msg in capsys.readouterr().err


def test_bad_inputs_exit_codes(tmp_path, capsys):
    assert run([str(tmp_path / "missing.obj"), "--spacing", "3"]) == 2
    bad = tmp_path / "dirs.txt"
    V, _ = read_surface(TORUS)
    X = np.tile([0.0, 0.0, 0.0], (len(V), 1))
    np.savetxt(bad, X)
    assert run([TORUS, "--spacing", "3", "--field", str(bad), "-o", str(tmp_path / "y")]) == 1
    assert "zero" in capsys.readouterr().err  # a typed SectionZeroError, one line, naming the vertex
    assert run([TORUS, "--spacing", "3", "--frequency", "2"]) == 2  # mutually exclusive


# ---------------------------------------------------------------------- issue 18 / 19: --section, budgets, overwriting
def test_section_option_reaches_the_json(tmp_path, capsys):
    for section in ("unit", "eigenvector", "power"):
        out = tmp_path / section
        assert run([TORUS, "--spacing", "4", "--section", section, "--no-png", "-o", str(out), "--json"]) == 0
        data = json.loads(capsys.readouterr().out)
        assert data["section"] == section and data["unit_energy"] >= data["eigenvalue"] - 1e-12
        assert (data["iteration"] is None) == (section == "eigenvector")
    assert run([TORUS, "--spacing", "4", "--section", "power", "--iterations", "0", "-o", str(out)]) == 2


def test_refuses_to_overwrite_the_input_mesh(tmp_path, capsys, monkeypatch):
    mesh = tmp_path / "spot.obj"
    mesh.write_bytes(open(TORUS, "rb").read())
    before = mesh.read_bytes()
    monkeypatch.chdir(tmp_path)
    assert run(["spot.obj", "--spacing", "5", "-o", "spot"]) == 2
    err = capsys.readouterr().err
    assert "refusing to write spot.obj" in err and "input mesh" in err
    assert mesh.read_bytes() == before and sorted(p.name for p in tmp_path.iterdir()) == ["spot.obj"]
    assert run(["spot.obj", "--spacing", "5", "-o", "./sub/../spot.obj"]) == 2        # the same file, spelled otherwise
    assert mesh.read_bytes() == before


def test_outputs_are_written_whole_and_no_temporary_file_is_left(tmp_path):
    out = tmp_path / "t"
    assert run([TORUS, "--spacing", "4", "--no-png", "-o", str(out)]) == 0
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == ["t-isolines.obj", "t.json", "t.obj"]
    assert run([TORUS, "--spacing", "4", "--no-png", "-o", str(tmp_path / "missing" / "t")]) == 2  # before the work


@pytest.mark.parametrize("argv,words", [
    (["--frequency", "1e4"], ["--frequency = 10000", "allowed: 0 < --frequency <="]),
    (["--spacing", "1e-4"], ["--spacing = 0.0001", "allowed: --spacing >="]),
    (["--spacing", "4", "--size", "60000"], ["argument --size: 60000 is out of range", "[16, 8192]"]),
    (["--spacing", "4", "--size", "8000"], ["--size = 8000", "allowed: --size 16 to"])])
def test_parameters_that_scale_the_work_are_refused_before_it_starts(tmp_path, capsys, argv, words):
    import resource
    import time

    t0 = time.perf_counter()
    rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    assert run([TORUS, *argv, "-o", str(tmp_path / "x")]) == 2
    err = capsys.readouterr().err
    assert all(w in err for w in words), err
    assert "needs about" in err or "argument --size" in err
    assert time.perf_counter() - t0 < 5 and resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - rss0 < 200_000
    assert list(tmp_path.iterdir()) == []


def test_the_summary_says_why_the_unit_section_stopped(tmp_path, capsys):
    """Issue 42 point 3: ``dhlb stripes kitten.obj --spacing 6`` used to end in "step limit, not converged:
    raise --iterations"; now it stops on the flat unit energy and says so, and --energy-tol 0 converges."""
    from pathlib import Path

    kitten = str(Path(__file__).parent / "data" / "kitten.obj")
    base = ["--spacing", "6", "--no-png", "--no-isolines", "-o", str(tmp_path / "k.obj")]
    assert run([kitten, *base]) == 0
    out = capsys.readouterr().out
    assert "(stopped: the unit energy changed by less than --energy-tol over the last 5 steps" in out
    assert "step limit" not in out
    assert run([kitten, *base[:-2], "-o", str(tmp_path / "k2.obj"), "--energy-tol", "0", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["iteration"]["stopped"] == "converged" and data["iteration"]["converged"]
    assert run([kitten, *base, "--energy-tol", "-1"]) == 2
    assert "--energy-tol" in capsys.readouterr().err
