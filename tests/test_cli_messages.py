"""Command-line messages in the user's terms (issue 29, points 5 and 7).

A misspelt option or command gets a "did you mean"; a warning is printed once, naming the input file
and its rows rather than the library's arrays; the index sum of a field on a mesh with boundary is
labelled (ΣΩ + rotation)/2π, as the demo labels it, not nχ.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from dhlb.cli import main
from dhlb.io import example_path

TORUS = example_path("torus.obj")


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


@pytest.mark.parametrize("argv, words", [
    (["stripes", TORUS, "--spacnig", "6"], "unrecognized arguments: --spacnig; did you mean --spacing?"),
    (["field", TORUS, "--algin", "curvature", "-o", "x"], "unrecognized arguments: --algin; did you mean --align?"),
    (["vortex", "--hbr=0.5"], "unrecognized arguments: --hbr; did you mean --hbar?"),
    (["feild", TORUS], "unknown command 'feild'; did you mean field?"),
    (["vortex", "--box", "2", "--velocity", "linked-ring"], "got 'linked-ring'; did you mean linked-rings?"),
])
def test_misspellings_get_a_did_you_mean(tmp_path, capsys, monkeypatch, argv, words):
    monkeypatch.chdir(tmp_path)
    code, _, err = run(capsys, *argv)
    assert code == 2 and words in err, err
    assert "is required" not in err  # not another complaint first
    assert list(tmp_path.iterdir()) == []


def test_an_unambiguous_prefix_is_still_accepted(tmp_path, capsys):
    code, _, err = run(capsys, "stripes", TORUS, "--spac", "4", "--no-png", "-q", "-o", tmp_path / "s")
    assert code == 0, err


OCTAHEDRON = ([[1.0, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1], [5, 5, 5]],
              [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])


@pytest.mark.parametrize("command", [["stripes", "--spacing", "2"], ["field", "--n", "1"]])
def test_an_unreferenced_vertex_is_reported_once_in_file_rows(tmp_path, capsys, command):
    V, F = OCTAHEDRON
    src = tmp_path / "oct.obj"
    src.write_text("".join(f"v {x} {y} {z}\n" for x, y, z in V) + "".join(f"f {a+1} {b+1} {c+1}\n" for a, b, c in F))
    code, _, err = run(capsys, command[0], src, *command[1:], "--no-png", "-o", tmp_path / "out")
    assert code == 0, err
    warnings = [line for line in err.splitlines() if "warning:" in line]
    assert warnings == [f"dhlb {command[0]}: warning: 1 vertex of oct.obj is used by no face and was dropped "
                        "(first: row 6)"], err
    assert "vertex_labels" not in err and "of V" not in err


def test_field_labels_the_index_sum_with_boundary_as_the_demo_does(tmp_path, capsys):
    code, out, err = run(capsys, "field", example_path("saddle.obj"), "--n", "4", "--no-png", "-o", tmp_path / "s")
    assert code == 0, err
    assert "Σ index = 0 = (ΣΩ + rotation)/2π = 0.000000" in out  # the saddle has boundary: not nχ = 4
    assert "Poincare-Hopf" not in out and "nχ" not in out
    code, out, err = run(capsys, "field", TORUS, "--n", "4", "--no-png", "-o", tmp_path / "t")
    assert code == 0, err
    assert "Σ index = 0 = nχ = 4·0" in out and "rotation" not in out


@pytest.mark.parametrize("command, data, names", [
    ("field", "octopus-low-tet.mesh", ("dhlb vortex", "dhlb conformal")),
    ("stripes", "octopus-low-tet.mesh", ("dhlb vortex", "dhlb conformal")),
    ("vortex", "moebius.obj", ("dhlb field", "dhlb stripes")),
    ("conformal", "moebius.obj", ("dhlb field", "dhlb stripes")),
])
def test_the_wrong_kind_of_mesh_names_the_commands_that_take_it(tmp_path, capsys, command, data, names):
    """Issue 42, point 6: at the command line a tet mesh given to `dhlb field` names commands, not read_volume."""
    path = Path(__file__).parent / "data" / data
    extra = ["--spacing", "6"] if command == "stripes" else []
    code, _, err = run(capsys, command, path, *extra, "-o", tmp_path / "out")
    assert code == 1 and all(name in err for name in names), err
    assert "read_volume" not in err and "read_surface" not in err and "dhlb.io" not in err
    assert data in err and err.count("\n") == 1


def test_the_help_of_o_says_what_each_command_writes(tmp_path, capsys):
    """Issue 42, point 6: `view` writes nothing but its screenshot (no -o); `demo -o` is a folder, not stdout."""
    code, out, _ = run(capsys, "view", "--help")
    assert code == 0 and "usage: dhlb view" in out and "--output" not in out
    code, out, _ = run(capsys, "demo", "--help")
    assert code == 0 and "-o DIR" in out and "folder" in out and "instead of stdout" not in out
    code, _, err = run(capsys, "view", tmp_path / "nothing", "-o", tmp_path / "x")
    assert code == 2 and "unrecognized arguments: -o" in err
