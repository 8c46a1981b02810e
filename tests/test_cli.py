"""The ``dhlb`` command line: ``dhlb info`` reports, its JSON schema, exit codes and error messages."""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import warnings

import numpy as np
import pytest

from dhlb.cli import main
from dhlb.cli._common import run_command
from dhlb.errors import MeshParseError
from tests.strategies import klein_bottle, rp2

DATA = os.path.join(os.path.dirname(__file__), "data")


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def info_json(capsys, *argv) -> dict:
    code, out, err = run(capsys, "info", "--json", *argv)
    assert code == 0, err
    return json.loads(out)


def simplex_file(tmp_path, simplices, name="x.txt") -> str:
    p = tmp_path / name
    p.write_text("".join(" ".join(map(str, s)) + "\n" for s in simplices))
    return str(p)


def groups(info) -> list[tuple[int, list[int]]]:
    return [(h["rank"], h["torsion"]) for h in info["homology"]]


# ---------------------------------------------------------------------------------------- schema
def check_schema(info: dict) -> None:
    for key in ("counts", "euler_characteristic", "orientable", "manifold", "homology", "boundary", "dim"):
        assert key in info
    counts = info["counts"]
    assert isinstance(counts, list) and all(isinstance(c, int) for c in counts)
    assert info["dim"] == len(counts) - 1
    assert info["euler_characteristic"] == sum((-1) ** k * c for k, c in enumerate(counts))
    assert info["orientable"] in (True, False, None) and info["manifold"] in (True, False, None)
    assert isinstance(info["homology"], list) and len(info["homology"]) == len(counts)
    for h in info["homology"]:
        assert set(h) == {"rank", "torsion"} and isinstance(h["rank"], int)
        assert isinstance(h["torsion"], list) and all(isinstance(t, int) and t > 1 for t in h["torsion"])
    # Euler-Poincaré: chi is the alternating sum of the Betti numbers
    assert info["euler_characteristic"] == sum((-1) ** k * h["rank"] for k, h in enumerate(info["homology"]))


def test_info_on_the_bundled_torus_text(capsys):
    code, out, err = run(capsys, "info")
    assert code == 0 and err == ""
    lines = {line[:21].strip(): line[22:] for line in out.splitlines()}  # "key<padding> value"
    assert lines["simplices"] == "288 vertices, 864 edges, 576 triangles"
    assert lines["Euler characteristic"] == "0"
    assert lines["manifold"] == "yes" and lines["orientable"] == "yes"
    assert lines["boundary"] == "none"
    assert lines["homology"] == "H0 = Z, H1 = Z^2, H2 = Z"


def test_info_json_on_the_bundled_examples(capsys):
    torus = info_json(capsys)
    check_schema(torus)
    assert torus["counts"] == [288, 864, 576] and groups(torus) == [(1, []), (2, []), (1, [])]
    assert torus["boundary"] == {"faces": 0, "components": 0} and torus["connected_components"] == 1
    solid = info_json(capsys, "--example", "solid-torus.mesh")
    check_schema(solid)
    assert solid["counts"] == [144, 656, 896, 384] and solid["kind"] == "volume"
    assert groups(solid) == [(1, []), (1, []), (0, []), (0, [])]
    assert solid["boundary"] == {"faces": 256, "components": 1}
    assert solid["manifold"] is True and solid["orientable"] is True


def test_info_real_files(capsys):
    moebius = info_json(capsys, os.path.join(DATA, "moebius.obj"))
    check_schema(moebius)
    assert moebius["orientable"] is False and moebius["manifold"] is True
    assert moebius["boundary"] == {"faces": 112, "components": 1}  # SOURCES.md: 112 edges, 1 loop
    assert groups(moebius) == [(1, []), (1, []), (0, [])]
    octopus = info_json(capsys, os.path.join(DATA, "octopus-low-tet.mesh"))
    check_schema(octopus)
    assert octopus["counts"] == [452, 2040, 2729, 1140] and octopus["euler_characteristic"] == 1
    assert octopus["boundary"] == {"faces": 898, "components": 1}
    assert groups(octopus) == [(1, []), (0, []), (0, []), (0, [])]


def test_info_torsion_from_simplex_lists(capsys, tmp_path):
    p = info_json(capsys, simplex_file(tmp_path, rp2(), "rp2.txt"))
    check_schema(p)
    assert groups(p) == [(1, []), (0, [2]), (0, [])] and p["orientable"] is False and p["kind"] == "complex"
    k = info_json(capsys, simplex_file(tmp_path, klein_bottle(), "kb.simplices"))
    assert groups(k) == [(1, []), (1, [2]), (0, [])] and k["euler_characteristic"] == 0
    code, out, _ = run(capsys, "info", str(tmp_path / "kb.simplices"))
    assert code == 0 and "H1 = Z + Z/2" in out


def test_info_mixed_dimensions_and_unreferenced_vertices(capsys, tmp_path):
    mixed = info_json(capsys, simplex_file(tmp_path, [(0, 1, 2), (2, 3), (9,)]), "--no-homology")
    assert mixed["counts"] == [5, 4, 1] and mixed["pure"] is False and mixed["homology"] is None
    assert mixed["connected_components"] == 2
    (tmp_path / "u.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 5 5\nf 1 2 3\n")
    code, out, _err = run(capsys, "info", str(tmp_path / "u.obj"))
    assert code == 0 and "1 vertices of the file are in no cell" in out
    assert info_json(capsys, str(tmp_path / "u.obj"))["unreferenced_vertices"] == 1


def test_output_option_and_format_option(capsys, tmp_path):
    target = tmp_path / "report.json"
    code, out, err = run(capsys, "info", "--json", "-o", str(target))
    assert code == 0 and out == "" and err == ""
    check_schema(json.loads(target.read_text()))
    simplex_file(tmp_path, rp2(), "rp2.dat")
    assert groups(info_json(capsys, str(tmp_path / "rp2.dat"), "--format", "simplices"))[1] == (0, [2])


# ----------------------------------------------------------------------------- errors and usage
def one_line_error(err: str) -> str:
    lines = err.strip().splitlines()
    assert "Traceback" not in err
    return lines[-1]


@pytest.mark.parametrize(
    "argv, code, pattern",
    [
        (["info", "missing.obj"], 2, "dhlb info: error: missing.obj: no such file"),
        (["info", "--no-such-option"], 2, "unrecognized arguments: --no-such-option"),
        (["info", "--example", "nope"], 2, "invalid choice"),
        (["frobnicate"], 2, "invalid choice: 'frobnicate'"),
        ([], 2, "a command is required"),
    ],
)
def test_usage_errors_exit_2_with_one_line(capsys, argv, code, pattern):
    got, out, err = run(capsys, *argv)
    assert got == code and out == ""
    assert pattern in one_line_error(err)


def test_unparsable_and_bad_input_exit_1_with_one_line(capsys, tmp_path):
    bad = tmp_path / "bad.off"
    bad.write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 x\n")
    code, out, err = run(capsys, "info", str(bad))
    assert code == 1 and out == "" and len(err.strip().splitlines()) == 1
    assert one_line_error(err) == f"dhlb info: error: {bad}, line 6: cannot read 'x' as an integer vertex index"
    nan = tmp_path / "nan.obj"
    nan.write_text("v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n")
    code, out, err = run(capsys, "info", str(nan))
    assert code == 1 and "line 2: vertex 2 (0-based 1) has a non-finite coordinate" in one_line_error(err)
    (tmp_path / "a.xyz").write_text("solid\n")
    code, out, err = run(capsys, "info", str(tmp_path / "a.xyz"))
    assert code == 2 and "unknown file extension '.xyz'" in one_line_error(err) and "--format" in err
    code, out, err = run(capsys, "info", str(tmp_path))
    assert code == 2 and "is a directory" in one_line_error(err)
    code, out, err = run(capsys, "info", "--example", "torus.obj", str(bad))
    assert code == 2 and "either FILE or --example" in one_line_error(err)


def test_debug_shows_the_traceback(tmp_path):
    bad = tmp_path / "bad.txt"
    bad.write_text("0 1 x\n")
    with pytest.raises(MeshParseError, match="line 1"):
        main(["info", "--debug", str(bad)])


def test_help_lists_examples_and_exit_codes(capsys):
    code, out, _ = run(capsys, "--help")
    assert code == 0 and "info" in out and "exit codes" in out
    code, out, _ = run(capsys, "info", "--help")
    assert code == 0
    for needle in ("examples:", "dhlb info --example solid-torus.mesh", "--json", "-o FILE", "--quiet", "--debug",
                   "bundled", "exit codes"):  # fmt: skip
        assert needle in out


def test_warnings_are_one_line_and_quiet_silences_them(capsys):
    def noisy(args):
        warnings.warn("something\nodd", UserWarning, stacklevel=1)
        return 0

    args = argparse.Namespace(command="fake", func=noisy, quiet=False, debug=False)
    assert run_command(args) == 0
    assert capsys.readouterr().err == "dhlb fake: warning: something odd\n"
    args.quiet = True
    assert run_command(args) == 0
    assert capsys.readouterr().err == ""


def test_internal_errors_are_one_line_too(capsys):
    args = argparse.Namespace(command="fake", func=lambda a: np.zeros(2)[5], quiet=False, debug=False)
    assert run_command(args) == 1
    err = capsys.readouterr().err
    assert "Traceback" not in err and err.count("\n") == 1 and "internal error: IndexError" in err


def test_python_dash_m_entry_point():
    proc = subprocess.run([sys.executable, "-m", "dhlb", "info", "--json"], capture_output=True, text=True,
                          timeout=120, env={**os.environ, "OPENBLAS_NUM_THREADS": "1"})  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    check_schema(json.loads(proc.stdout))
    proc = subprocess.run([sys.executable, "-m", "dhlb", "info", "nope.off"], capture_output=True, text=True,
                          timeout=120)  # fmt: skip
    assert proc.returncode == 2 and proc.stderr.strip() == "dhlb info: error: nope.off: no such file"
