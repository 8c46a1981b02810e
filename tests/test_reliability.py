"""Regression tests of issue 19 (reliability): each case here failed (or was silently wrong) before.

Outputs (atomic writes, never over an input, disk full → one line), readers (declared counts,
trailing data, BOM, CRLF in every format), CLI values (NaN/inf, ranges, empty lists, memory
estimates), Python inputs (ragged, huge, complex, strings), extreme scales, and the
unreferenced-vertex mask of outputs.
"""

from __future__ import annotations

import argparse
import errno
import os
import warnings

import numpy as np
import pytest

from dhlb import SimplicialComplex
from dhlb.cli import main
from dhlb.errors import (
    InvalidParameterError,
    InvalidSimplexError,
    InvalidTypeError,
    MeshParseError,
    OutputError,
    OverwriteError,
    RaggedInputError,
    ResourceLimitError,
    differing_digits,
)
from dhlb.io import load, read_ply, read_volume, write_obj, write_off, write_ply, write_volume
from dhlb.io.atomic import atomic_write, refuse_overwrite

OCT_V = np.array([[1.0, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]])
OCT_F = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])
BALL_V = np.vstack([OCT_V, [[0.0, 0, 0]]])
BALL_T = np.array([[6, *f] for f in OCT_F])


def run_cli(argv, capsys):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def one_error_line(err: str) -> str:
    lines = [s for s in err.splitlines() if s.strip()]
    assert lines and ": error: " in lines[-1], err
    assert "internal error" not in err and "Traceback" not in err
    return lines[-1]


# ------------------------------------------------------------------------------------- outputs
def test_atomic_write_keeps_the_old_file_when_interrupted(tmp_path):
    target = tmp_path / "out.obj"
    target.write_text("old\n")
    with pytest.raises(RuntimeError), atomic_write(target) as fh:
        fh.write("half a mesh")
        raise RuntimeError("stopped")
    assert target.read_text() == "old\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.obj"]  # no temporary file left


def test_disk_full_is_a_one_line_output_error_naming_the_path(tmp_path, monkeypatch):
    target = tmp_path / "m.obj"
    real_replace = os.replace

    def full(src, dst):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(os, "replace", full)
    with pytest.raises(OutputError) as info:
        write_obj(target, OCT_V, OCT_F)
    monkeypatch.setattr(os, "replace", real_replace)
    msg = str(info.value)
    assert str(target) in msg and "disk is full" in msg and "\n" not in msg
    assert not target.exists() and list(tmp_path.iterdir()) == []


def test_file_size_limit_in_a_subprocess_gives_an_output_error(tmp_path):
    """A real write failure (RLIMIT_FSIZE, EFBIG) during write_obj: a typed error, no partial file."""
    import subprocess
    import sys

    code = (
        "import resource, signal, numpy as np\n"
        "signal.signal(signal.SIGXFSZ, signal.SIG_IGN)\n"
        "resource.setrlimit(resource.RLIMIT_FSIZE, (200, 200))\n"
        "from dhlb.io import write_obj\nfrom dhlb.errors import OutputError\n"
        "V = np.random.default_rng(0).random((100, 3)); F = np.array([[0, 1, 2]])\n"
        f"try:\n    write_obj({str(tmp_path / 'big.obj')!r}, V, F)\n"
        "except OutputError as e:\n    print('OutputError', e)\n"
    )
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert res.stdout.startswith("OutputError cannot write") and "big.obj" in res.stdout, res.stderr
    assert list(tmp_path.iterdir()) == []


def test_missing_folder_is_an_output_error(tmp_path):
    with pytest.raises(OutputError, match="folder does not exist"):
        write_ply(tmp_path / "no" / "such" / "m.ply", OCT_V, OCT_F)


def test_refuse_overwrite_follows_symlinks_and_dotdots(tmp_path):
    mesh = tmp_path / "spot.obj"
    mesh.write_text("x")
    link = tmp_path / "link.obj"
    link.symlink_to(mesh)
    for out in (mesh, link, tmp_path / "sub" / ".." / "spot.obj"):
        with pytest.raises(OverwriteError, match="refusing to write"):
            refuse_overwrite([out], [mesh])
    refuse_overwrite([tmp_path / "other.obj"], [mesh])


def test_info_never_overwrites_its_input(tmp_path, capsys):
    mesh = tmp_path / "m.obj"
    write_obj(mesh, OCT_V, OCT_F)
    before = mesh.read_bytes()
    code, _, err = run_cli(["info", mesh, "-o", mesh], capsys)
    assert code == 2 and "refusing to write" in one_error_line(err)
    assert mesh.read_bytes() == before


def test_vortex_refuses_derived_output_over_the_mesh(tmp_path, capsys):
    mesh = tmp_path / "ball.mesh"
    write_volume(mesh, BALL_V, BALL_T)
    before = mesh.read_bytes()
    # -o ball.obj would also write ball.json and ball.png; -o ball.mesh.ply writes ball.mesh.json ...
    code, _, err = run_cli(["vortex", mesh, "-o", tmp_path / "ball.mesh"], capsys)
    assert code == 2 and mesh.read_bytes() == before
    odd = tmp_path / "out.json"  # a Medit mesh under an odd name: -o out (the default set) would write out.json
    odd.write_bytes(before)
    code, _, err = run_cli(["vortex", odd, "--format", "mesh", "-o", tmp_path / "out"], capsys)
    assert code == 2 and "refusing to write" in one_error_line(err) and odd.read_bytes() == before
    # -o out.ply writes that file only (issue 29's -o convention), so the input stays untouched
    code, _, err = run_cli(["vortex", odd, "--format", "mesh", "-o", tmp_path / "out.ply", "--no-png"], capsys)
    assert code == 0 and odd.read_bytes() == before and (tmp_path / "out.ply").is_file()


# ------------------------------------------------------------------------------------- readers
def test_binary_ply_declaring_fewer_faces_than_it_holds_is_an_error(tmp_path):
    for order in ("<", ">"):
        p = tmp_path / "m.ply"
        write_ply(p, OCT_V, OCT_F, binary=True, byteorder=order)
        data = p.read_bytes().replace(b"element face 8", b"element face 7")
        p.write_bytes(data)
        with pytest.raises(MeshParseError, match=r"13 bytes of unexpected data .* \(from byte \d+\)"):
            read_ply(p)


def test_truncated_binary_ply_names_the_byte_offset(tmp_path):
    p = tmp_path / "m.ply"
    write_ply(p, OCT_V, OCT_F, binary=True)
    p.write_bytes(p.read_bytes()[:-5])
    with pytest.raises(MeshParseError, match=r"5 bytes missing at byte \d+ \(the header declares 8\)"):
        read_ply(p)


def _write_all(folder):
    out = {}
    for name, write in {
        "m.obj": lambda p: write_obj(p, OCT_V, OCT_F),
        "m.off": lambda p: write_off(p, OCT_V, OCT_F),
        "m-ascii.ply": lambda p: write_ply(p, OCT_V, OCT_F),
        "m-bin.ply": lambda p: write_ply(p, OCT_V, OCT_F, binary=True),
        "b.mesh": lambda p: write_volume(p, BALL_V, BALL_T),
        "b.msh": lambda p: write_volume(p, BALL_V, BALL_T),
        "b.vtk": lambda p: write_volume(p, BALL_V, BALL_T),
    }.items():
        write(folder / name)
        out[name] = folder / name
    return out


@pytest.mark.parametrize("name", ["m.obj", "m.off", "m-ascii.ply", "m-bin.ply", "b.mesh", "b.msh", "b.vtk"])
def test_utf8_bom_and_crlf_are_accepted_in_every_format(tmp_path, name):
    path = _write_all(tmp_path)[name]
    ref = load(path)
    data = path.read_bytes()
    variants = {"bom": b"\xef\xbb\xbf" + data}
    if not name.endswith("bin.ply"):
        variants["crlf"] = data.replace(b"\n", b"\r\n")
        variants["bom+crlf"] = b"\xef\xbb\xbf" + variants["crlf"]
    for kind, blob in variants.items():
        path.write_bytes(blob)
        got = load(path)
        assert np.array_equal(got.points, ref.points), kind
        assert all(np.array_equal(got.cells[k], ref.cells[k]) for k in ref.cells), kind


def test_utf16_file_is_a_parse_error_naming_the_encoding(tmp_path):
    p = tmp_path / "m.obj"
    write_obj(p, OCT_V, OCT_F)
    p.write_bytes(p.read_text().encode("utf-16"))
    with pytest.raises(MeshParseError, match="UTF-16"):
        load(p)


def test_medit_data_after_end_is_an_error_naming_the_line(tmp_path):
    p = tmp_path / "b.mesh"
    write_volume(p, BALL_V, BALL_T)
    text = p.read_text()
    n = len(text.splitlines())
    p.write_text(text + "Tetrahedra\n1\n1 2 3 4 0\n")
    with pytest.raises(MeshParseError, match=rf"line {n + 1}: unexpected data after 'End'"):
        read_volume(p)


@pytest.mark.parametrize("name", ["m.off", "m-ascii.ply", "b.mesh", "b.msh", "b.vtk"])
def test_declared_counts_larger_than_the_data_name_file_and_line(tmp_path, name):
    import re

    path = _write_all(tmp_path)[name]
    text = path.read_text()
    fixes = {"m.off": ("\n6 8 0\n", "\n6 9 0\n"), "m-ascii.ply": ("element face 8", "element face 9"),
             "b.mesh": ("Tetrahedra\n8", "Tetrahedra\n9")}
    if name in fixes:
        a, b = fixes[name]
        assert a in text
        text = text.replace(a, b)
    elif name == "b.msh":
        text = re.sub(r"\$Elements\n(\d+)", lambda m: f"$Elements\n{int(m.group(1)) + 1}", text)
    else:
        text = re.sub(r"CELLS (\d+) (\d+)", lambda m: f"CELLS {int(m.group(1)) + 1} {m.group(2)}", text)
    path.write_text(text)
    with pytest.raises(MeshParseError) as info:
        load(path)
    assert str(path) in str(info.value)


# ------------------------------------------------------------------------------------ CLI values
@pytest.mark.parametrize("argv", [
    ["vortex", "--hbar", "nan"], ["vortex", "--hbar", "inf"], ["vortex", "--hbar", "-1"], ["vortex", "--hbar", "0"],
    ["vortex", "--tol", "1e400"], ["vortex", "--core", "nan"], ["vortex", "--circulation", "-inf"],
    ["vortex", "--order", "60000"], ["vortex", "--order", "0"], ["vortex", "--box", "0"], ["vortex", "--box", "-5"],
    ["vortex", "--velocity", ""], ["field", "m.obj", "--s", "nan"], ["field", "m.obj", "--lambda", "inf"],
    ["demo", "--only", ""], ["demo", "--only", ","], ["demo", "--only", "fields,"],
])
def test_bad_values_are_usage_errors_with_one_line(argv, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    write_obj(tmp_path / "m.obj", OCT_V, OCT_F)
    code, _, err = run_cli(argv, capsys)
    assert code == 2
    one_error_line(err)
    assert not (tmp_path / "dhlb-demo").exists()  # refused before any work


def test_vortex_box_400_is_refused_with_the_memory_estimate(capsys, monkeypatch):
    monkeypatch.setenv("DHLB_MEMORY_LIMIT", "8G")
    code, _, err = run_cli(["vortex", "--box", "400"], capsys)
    line = one_error_line(err)
    assert code == 2 and "--box = 400" in line and "GB of memory (estimate)" in line and "at most" in line


def test_box_tet_mesh_checks_memory_before_allocating():
    from dhlb.mesh import box_tet_mesh
    from dhlb.mesh.tet import check_box_memory

    with pytest.raises(ResourceLimitError) as info:
        check_box_memory(400, available=8 * 10**9)
    assert info.value.estimate_bytes > 100 * info.value.limit_bytes / 8
    with pytest.raises(ResourceLimitError):
        box_tet_mesh(2000)  # 8e9 cells: refused at once, not a MemoryError
    with pytest.raises(InvalidParameterError):
        box_tet_mesh(0)


def test_vortex_demo_circulation_is_bounded(capsys):
    code, _, err = run_cli(["vortex", "--box", "2", "--circulation", "60000"], capsys)
    assert code == 2 and "filaments per demo curve" in one_error_line(err)


def test_int_in_range_for_pixel_sizes():
    from dhlb.cli._common import int_in_range

    size = int_in_range(16, 8192)
    for bad in ("0", "-5", "60000", "nan", "", "1e3"):
        with pytest.raises(argparse.ArgumentTypeError):
            size(bad)
    assert size("800") == 800


# --------------------------------------------------------------------------------- Python inputs
def test_ragged_face_lists_are_typed_errors():
    from dhlb.mesh import validate_surface

    with pytest.raises(RaggedInputError):
        validate_surface(OCT_V, [[0, 2, 4], [2, 1, 4, 5]])
    with pytest.raises(RaggedInputError):
        validate_surface(OCT_V, [[0, 2, 4], [2, 1]])


def test_vertex_index_2_to_the_70_is_a_typed_error():
    from dhlb.mesh import validate_surface

    for F in ([[0, 1, 2**70]], [[0, 1, 2.0**70]], np.array([[0, 1, 2**70]], dtype=object)):
        with pytest.raises(InvalidSimplexError, match="outside V"):
            validate_surface(OCT_V, F)
        with pytest.raises(InvalidSimplexError, match="too large"):
            SimplicialComplex(F)


def test_complex_or_text_coordinates_are_refused():
    from dhlb.mesh import validate_surface

    with pytest.raises(InvalidTypeError, match="complex"):
        validate_surface(OCT_V + 1e-3j, OCT_F)
    with pytest.raises(InvalidTypeError, match="complex"):
        validate_surface(OCT_V + 0j, OCT_F)
    with pytest.raises(InvalidTypeError, match="not numbers"):
        validate_surface(OCT_V.astype(str), OCT_F)
    with pytest.raises(InvalidTypeError):
        validate_surface(OCT_V, OCT_F + 0j)


def test_vortex_filaments_checks_hbar_orientation_and_options_first():
    from dhlb.linalg import SolverOptions
    from dhlb.mesh import box_tet_mesh
    from dhlb.vortex import VortexOptions, uniform_flow, vortex_filaments

    mesh = box_tet_mesh(1)
    flow = uniform_flow([0.1, 0.0, 0.0])
    for make in (lambda: VortexOptions(orientation="x"), lambda: VortexOptions(placement="y"),
                 lambda: VortexOptions(order=60000), lambda: VortexOptions(order=0),
                 lambda: SolverOptions(tol=float("nan")), lambda: SolverOptions(tol=-1.0)):
        with pytest.raises(InvalidParameterError):
            make()
    for hbar in ("1", 1 + 0j, b"1", True, None):
        with pytest.raises(InvalidParameterError, match="hbar must be a real number"):
            vortex_filaments(mesh, None, flow, hbar)


def test_huge_core_radius_is_a_typed_error():
    from dhlb.vortex import FilamentField, vortex_ring

    with pytest.raises(InvalidParameterError, match="core_radius"):
        FilamentField([vortex_ring(1.0, n=8)], core_radius=1e308)
    with pytest.raises(InvalidParameterError, match="core_radius"):
        FilamentField([vortex_ring(1.0, n=8)], core_radius="0.1")


# ---------------------------------------------------------------------------------------- scales
@pytest.mark.parametrize("scale", [1e-150, 1e150, 1e-300, 1e300])
def test_validate_surface_is_scale_free(scale):
    from dhlb.mesh import validate_surface

    ref = validate_surface(OCT_V, OCT_F)
    mesh = validate_surface(OCT_V * scale, OCT_F)
    assert np.array_equal(mesh.points, OCT_V * scale)  # results stay in the caller's units
    assert np.allclose(mesh.corner_angles, ref.corner_angles, rtol=0, atol=1e-15)
    assert np.allclose(mesh.unit_points * (mesh.length_scale / ref.length_scale) / scale, ref.unit_points,
                       rtol=1e-15, atol=0)


def test_degenerate_faces_are_still_found_at_extreme_scales():
    from dhlb.errors import DegenerateSimplexError
    from dhlb.mesh import validate_surface

    V = np.array([[0.0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0]])
    for scale in (1e-150, 1.0, 1e150):
        with pytest.raises(DegenerateSimplexError, match="zero area"):
            validate_surface(V * scale, [[0, 1, 2], [0, 1, 3]])


def test_differing_digits_shows_the_difference():
    a, b = 0.1 + 0.2, 0.3
    sa, sb = differing_digits(a, b)
    assert sa != sb and f"{a:.6g}" == f"{b:.6g}"
    assert differing_digits(1.0, 1.0) == ("1.0", "1.0")


# ---------------------------------------------------------------------------- unreferenced vertices
def test_input_vertex_mask_marks_the_nan_rows():
    from dhlb.mesh import validate_surface

    V = np.vstack([OCT_V, [[7.0, 7, 7]]])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        mesh = validate_surface(V, OCT_F)
    assert mesh.input_vertex_used.tolist() == [True] * 6 + [False]
    values = mesh.to_input(np.arange(6.0))
    assert np.array_equal(np.isnan(values), ~mesh.input_vertex_used)
