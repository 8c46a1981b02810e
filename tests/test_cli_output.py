"""One ``-o`` convention for ``dhlb field``, ``stripes``, ``vortex`` and ``conformal`` (issue 29, point 4).

A base name writes the command's default set, a name with an extension that format only, any other
extension is a usage error before any work; a missing optional package (meshio, matplotlib) is a usage
error with the install command, before any work, never an "internal error"; the files appear together
or not at all. Commands run in-process on small meshes (the bundled torus, ``--box 3``, ``--ball 2``).
"""

from __future__ import annotations

import sys

import pytest

from dhlb.cli import main
from dhlb.errors import OutputError
from dhlb.io import example_path

TORUS = example_path("torus.obj")

#: command → (its arguments before -o, the library call that does the work)
COMMANDS = {
    "field": ([TORUS, "--n", "2"], "dhlb.fields.direction_field"),
    "stripes": ([TORUS, "--spacing", "4"], "dhlb.stripes.stripe_pattern"),
    "vortex": (["--box", "3"], "dhlb.vortex.vortex_filaments"),
    "conformal": (["--ball", "2"], "dhlb.conformal.conformal_deformation"),
}

#: (command, -o name) → the files written (a base name: the default set)
WRITES = {
    ("field", "out"): ["out.json", "out.npz", "out.ply", "out.png"],
    ("field", "out.ply"): ["out.ply"],
    ("field", "out.npz"): ["out.npz"],
    ("field", "out.json"): ["out.json"],
    ("field", "out.png"): ["out.png"],
    ("field", "out.vtu"): ["out.vtu"],
    ("stripes", "out"): ["out-isolines.obj", "out.json", "out.obj", "out.png"],
    ("stripes", "out.obj"): ["out.json", "out.obj"],  # the OBJ and its sidecar
    ("stripes", "out.png"): ["out.png"],
    ("stripes", "out.vtu"): ["out.vtu"],
    ("vortex", "out"): ["out.json", "out.obj", "out.png"],
    ("vortex", "out.obj"): ["out.obj"],
    ("vortex", "out.ply"): ["out.ply"],
    ("vortex", "out.json"): ["out.json"],
    ("vortex", "out.png"): ["out.png"],
    ("vortex", "out.vtu"): ["out-filaments.vtp", "out.vtu"],
    ("conformal", "out"): ["out.json", "out.mesh", "out.png", "out.vtk"],
    ("conformal", "out.mesh"): ["out.mesh"],
    ("conformal", "out.msh"): ["out.msh"],
    ("conformal", "out.vtk"): ["out.vtk"],
    ("conformal", "out.vtu"): ["out.vtu"],
    ("conformal", "out.npz"): ["out.npz"],
    ("conformal", "out.json"): ["out.json"],
    ("conformal", "out.png"): ["out.png"],
}

#: names no command writes; each is a usage error (stripes: an OBJ's sidecar is no format of its own)
UNKNOWN = [(c, name) for c in COMMANDS for name in ("out.txt", "out.stl", "out.vtu.xyz")] + [
    ("stripes", "out.json"), ("field", "out.obj"), ("vortex", "out.mesh"), ("conformal", "out.ply")]


def dhlb(capsys, command, out, *extra):
    args, _ = COMMANDS[command]
    code = main([command, *args, "-o", str(out), "-q", *extra])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def files(folder) -> list[str]:
    return sorted(p.name for p in folder.iterdir())  # hidden temporaries too


def boom(*args, **kwargs):
    raise AssertionError("the computation started")


@pytest.fixture
def no_work(monkeypatch):
    """Make the computation of ``command`` fail loudly: a usage error must come before it."""

    def patch(command):
        monkeypatch.setattr(COMMANDS[command][1], boom)

    return patch


@pytest.mark.parametrize("command, name", sorted(WRITES), ids=[f"{c} -o {n}" for c, n in sorted(WRITES)])
def test_a_base_name_writes_the_default_set_and_an_extension_that_format(tmp_path, capsys, command, name):
    if name.endswith(".vtu"):
        pytest.importorskip("meshio")
    code, _, err = dhlb(capsys, command, tmp_path / name)
    assert code == 0, err
    assert files(tmp_path) == WRITES[command, name]
    assert "internal error" not in err


@pytest.mark.parametrize("command, name", UNKNOWN, ids=[f"{c} -o {n}" for c, n in UNKNOWN])
def test_an_unknown_extension_is_a_usage_error_before_any_work(tmp_path, capsys, no_work, command, name):
    no_work(command)
    code, _, err = dhlb(capsys, command, tmp_path / name)
    assert code == 2, err
    assert "does not write" in err and "give a base name OUT" in err and "internal error" not in err
    assert files(tmp_path) == []


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_missing_meshio_is_a_usage_error_before_any_work(tmp_path, capsys, monkeypatch, no_work, command):
    monkeypatch.setitem(sys.modules, "meshio", None)  # import meshio raises ImportError
    no_work(command)
    code, _, err = dhlb(capsys, command, tmp_path / "out.vtu")
    assert code == 2, err
    assert "needs meshio" in err and "pip install meshio" in err and 'pip install ".[meshio]"' in err
    assert "internal error" not in err and '"dhlb[' not in err          # what works from a clone (issue 42, point 7)
    assert files(tmp_path) == []


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_missing_matplotlib_is_a_usage_error_unless_no_png(tmp_path, capsys, monkeypatch, command):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    with monkeypatch.context() as m:
        m.setattr(COMMANDS[command][1], boom)
        code, _, err = dhlb(capsys, command, tmp_path / "out")
    assert code == 2, err
    assert "needs matplotlib" in err and "pip install matplotlib" in err and "--no-png" in err
    assert files(tmp_path) == []
    code, _, err = dhlb(capsys, command, tmp_path / "out.png")
    assert code == 2 and "needs matplotlib" in err and files(tmp_path) == []
    code, _, err = dhlb(capsys, command, tmp_path / "out", "--no-png")  # the rest needs no matplotlib
    assert code == 0, err
    assert files(tmp_path) == [f for f in WRITES[command, "out"] if not f.endswith(".png")]


RENDERERS = {
    "field": "dhlb.render.render_field_png",
    "stripes": "dhlb.render.render_stripes_png",
    "vortex": "dhlb.render.filaments_png.render_filaments_png",
    "conformal": "dhlb.cli.conformal.render_conformal_png",
}


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_outputs_are_all_or_nothing(tmp_path, capsys, monkeypatch, command):
    """A failure while writing (here: the picture, the disk full) leaves none of the set, nor a temporary."""

    def disk_full(path, *args, **kwargs):
        open(path, "wb").close()  # half written
        raise OutputError(str(path), "No space left on device (the disk is full)")

    monkeypatch.setattr(RENDERERS[command], disk_full)
    (tmp_path / "out.json").write_text("an older result")  # a target that exists is left as it was
    code, _, err = dhlb(capsys, command, tmp_path / "out")
    assert code == 1 and "the disk is full" in err and "internal error" not in err, err
    assert files(tmp_path) == ["out.json"] and (tmp_path / "out.json").read_text() == "an older result"


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_help_states_the_output_convention_and_the_exit_codes(capsys, command):
    assert main([command, "--help"]) == 0
    text = capsys.readouterr().out
    assert "a base name OUT writes" in text and "writes that format only" in text
    assert "any other extension is a usage error (exit 2) found before any work" in text
    assert "after a failure none of them is left" in text
    assert "exit codes: 0 success; 2 usage error, found before any work" in text
    assert "1 the input or the computation fails (the message says what to change)" in text


def test_a_missing_output_folder_is_a_usage_error_before_any_work(tmp_path, capsys, no_work):
    for command in COMMANDS:
        no_work(command)
        code, _, err = dhlb(capsys, command, tmp_path / "missing" / "out")
        assert code == 2 and "does not exist" in err, (command, err)
    assert files(tmp_path) == []
