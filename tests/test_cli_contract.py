"""One CLI contract everywhere (issue 39, point 4): usage and value errors exit 2 with one line naming the
option, before any work, with nothing created; no stray files; an output never replaces an input."""

from __future__ import annotations

import importlib.util
import json
import os
import subprocess
import sys

import pytest

from dhlb.cli import main
from dhlb.io import example_path

TORUS = example_path("torus.obj")


def _run(argv, capsys):
    code = main(argv)
    return code, capsys.readouterr().err


def test_info_output_in_a_missing_folder_is_a_usage_error(tmp_path, capsys):
    code, err = _run(["info", "-o", str(tmp_path / "missing" / "x.txt")], capsys)
    assert code == 2 and "the folder" in err and "does not exist" in err and err.count("\n") == 1
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("argv", [
    ["field", TORUS, "-o", "{d}/f"], ["stripes", TORUS, "--spacing", "5", "-o", "{d}/s"],
    ["conformal", "--ball", "2", "-o", "{d}/c"], ["vortex", "--box", "4", "-o", "{d}/v"], ["demo", "-o", "{d}/demo"],
])
def test_an_unknown_backend_exits_2_before_any_work_and_creates_nothing(argv, tmp_path, capsys):
    code, err = _run([a.format(d=tmp_path) for a in argv] + ["--backend", "supelu"], capsys)
    assert code == 2, err
    assert "argument --backend: unknown backend 'supelu'" in err and "did you mean superlu" in err
    assert list(tmp_path.iterdir()) == []                      # no empty demo folder, no partial output


def test_a_singular_face_outside_the_mesh_is_a_usage_error(tmp_path, capsys):
    code, err = _run(["field", TORUS, "--n", "1", "--singularity", "99999:1", "-o", str(tmp_path / "f")], capsys)
    assert code == 2 and "argument --singularity: 99999:1: face 99999 is out of range" in err and "576 faces" in err
    assert list(tmp_path.iterdir()) == []


def test_the_view_help_example_reads_back(tmp_path):
    # dhlb view --help: "dhlb conformal --ball 6 -o ball && dhlb view ball ..."
    pytest.importorskip("plotly")
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    run = lambda *a: subprocess.run([sys.executable, "-m", "dhlb", *a], capture_output=True, text=True,  # noqa: E731
                                    cwd=tmp_path, env=env, timeout=300)
    help_text = run("view", "--help").stdout
    assert "dhlb conformal --ball 6 -o ball && dhlb view ball" in help_text
    assert run("conformal", "--ball", "2", "-o", "ball", "--no-png", "-q").returncode == 0
    out = run("view", "ball", "--html", "ball.html")
    assert out.returncode == 0, out.stderr
    assert (tmp_path / "ball.html").stat().st_size > 0


def test_a_screenshot_leaves_no_imgui_ini(tmp_path):
    pytest.importorskip("polyscope")
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    run = lambda *a: subprocess.run([sys.executable, "-m", "dhlb", *a], capture_output=True, text=True,  # noqa: E731
                                    cwd=tmp_path, env=env, timeout=300)
    assert run("field", TORUS, "--n", "2", "-o", "t", "--no-png", "-q").returncode == 0
    shot = run("view", "t", "--screenshot", "t.png")
    if shot.returncode != 0:
        pytest.skip(f"no headless OpenGL here: {shot.stderr.strip()[-200:]}")
    assert (tmp_path / "t.png").exists() and not (tmp_path / "imgui.ini").exists()


def test_json_on_stdout_is_json_alone(tmp_path):
    """Issue 42, point 5: polyscope's log lines go to stderr; `field --json` without -o prints the summary."""
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    run = lambda *a: subprocess.run([sys.executable, "-m", "dhlb", *a], capture_output=True, text=True,  # noqa: E731
                                    cwd=tmp_path, env=env, timeout=300)
    field = run("field", TORUS, "--n", "4", "--json")              # no -o: the summary alone, no files
    assert field.returncode == 0, field.stderr
    summary = json.loads(field.stdout)
    assert summary["files"] == {} and summary["index_sum"] == 0 and list(tmp_path.iterdir()) == []
    missing = run("field", str(tmp_path / "torsu.obj"), "--n", "4", "--json")   # the missing file, not the -o
    assert missing.returncode == 2 and "no such file" in missing.stderr and "give the output" not in missing.stderr
    nothing = run("field", TORUS, "--n", "4")                          # neither -o nor --json: said what to give
    assert nothing.returncode == 2 and "-o OUT" in nothing.stderr and "--json" in nothing.stderr
    if importlib.util.find_spec("polyscope") is None:
        return
    assert run("field", TORUS, "--n", "2", "-o", "t", "--no-png", "-q").returncode == 0
    shot = run("view", "t", "--screenshot", "t.png", "--json")
    if shot.returncode != 0:
        pytest.skip(f"no headless OpenGL here: {shot.stderr.strip()[-200:]}")
    written = json.loads(shot.stdout)["written"]                       # stdout parses: nothing else is on it
    assert len(written) == 1 and written[0].endswith("t.png") and "[polyscope]" not in shot.stdout


def test_view_of_a_damaged_output_is_one_line_not_an_internal_error(tmp_path, capsys):
    pytest.importorskip("plotly")
    code, err = _run(["field", TORUS, "--n", "2", "-o", str(tmp_path / "t"), "--no-png", "-q"], capsys)
    assert code == 0, err
    npz = tmp_path / "t.npz"
    npz.write_bytes(npz.read_bytes()[:3000])                   # a bad copy
    code, err = _run(["view", str(tmp_path / "t"), "--html", str(tmp_path / "t.html")], capsys)
    assert code in (1, 2) and "internal error" not in err and "t.npz" in err and err.count("\n") == 1, err
    assert not (tmp_path / "t.html").exists()


def test_a_result_read_from_files_is_never_written_over(tmp_path, capsys):
    from dhlb.errors import OverwriteError
    from dhlb.io import read_result

    assert _run(["field", TORUS, "--n", "2", "-o", str(tmp_path / "t"), "--no-png", "-q"], capsys)[0] == 0
    before = {p.name: p.read_bytes() for p in tmp_path.iterdir()}
    res = read_result(str(tmp_path / "t.json"))
    for path in (tmp_path / "t.json", tmp_path / "t.npz", tmp_path / "t.ply"):
        with pytest.raises(OverwriteError, match="read from"):
            res.save(path)
    if pytest.importorskip("plotly"):
        with pytest.raises(OverwriteError, match="read from"):
            res.to_html(tmp_path / "t.json")
    assert {p.name: p.read_bytes() for p in tmp_path.iterdir()} == before
    assert res.save(tmp_path / "copy.json") == [str(tmp_path / "copy.json")]
