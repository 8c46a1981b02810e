"""Every output of the commands and of ``dhlb demo`` reads back (dhlb.io.read_result) and draws as the result in memory.

One scene builder (dhlb.render.view.scene_of) and one picture registry serve the result in memory and the
result read back from its files; ``dhlb view`` goes through them.
"""

import json
import os

import numpy as np
import pytest

from dhlb.cli import main
from dhlb.io import example_path, read_result, read_surface
from dhlb.render.registry import picture
from dhlb.render.view import scene_of

DATA_EXTENSIONS = (".npz", ".obj", ".ply", ".json", ".mesh", ".vtk", ".msh")


def _has_screenshots(folder) -> bool:
    try:
        import polyscope  # noqa: F401
    except ImportError:
        return False
    from dhlb.errors import ViewerUnavailableError
    from dhlb.render.view import Scene, show

    s = Scene()
    s.add_points("p", [[0, 0, 0], [1, 1, 1]], (0, 0, 0))
    try:
        show(s, screenshot=os.path.join(folder, "probe.png"), size=(32, 32))
    except ViewerUnavailableError:
        return False
    return True


@pytest.fixture(scope="module")
def demo_dir(tmp_path_factory):
    """``dhlb demo -o DIR`` once (its polyscope views left out: they are not what is tested here)."""
    from dhlb.cli import _demo_steps

    d = tmp_path_factory.mktemp("demo")
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(_demo_steps, "_views", lambda res, out, name: None)
        assert main(["demo", "-o", str(d), "-q"]) == 0
    return d


def _view_args(base, screenshot=None):
    from dhlb.cli import build_parser

    argv = ["view", str(base), "--size", "160", "-q"] + (["--screenshot", str(screenshot)] if screenshot else [])
    return build_parser().parse_args(argv)


def _scene_of_cli(base):
    """The scene ``dhlb view BASE`` hands to polyscope (polyscope replaced by a recorder)."""
    import dhlb.render.view as rv
    from dhlb.cli import view

    seen = []
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(rv, "show", lambda scene, **kw: seen.append(scene) or kw.get("screenshot"))
        assert view.run(_view_args(base, "never.png")) == 0
    assert len(seen) == 1
    return seen[0]


def _expected_content(path, res):
    """(faces of the first drawn mesh or None, number of points drawn, number of curves) from the files themselves."""
    base = os.path.splitext(str(path))[0]
    kind = type(res).__name__
    if kind == "DirectionField":
        with np.load(base + ".npz") as z:
            return len(z["mesh_faces"]), len(z["singular_faces"]), 0
    if kind == "LoadedConformal":                                     # the deformed boundary, no points, no curves
        return len(res.mesh.boundary_faces), 0, 0
    side = json.load(open(base + ".json")) if os.path.exists(base + ".json") else {}
    if side.get("format") == "dhlb-stripes":
        return side["n_faces"], len(side["zeros"]["faces"]) + len(side["branch"]["faces"]), 1
    if "filaments" in side:                         # the domain the JSON names, its outline, and the filaments
        return len(res.mesh.boundary_faces), 0, 1 + len(side["filaments"])
    lines = open(base + ".obj").read().splitlines()
    return None, 0, sum(ln.startswith("l ") for ln in lines)


def test_every_demo_output_opens(demo_dir, tmp_path, monkeypatch):
    files = sorted(f for f in os.listdir(demo_dir) if os.path.splitext(f)[1] in DATA_EXTENSIONS)
    kinds = {type(read_result(demo_dir / f)).__name__ for f in files}
    assert {"DirectionField", "LoadedStripes", "LoadedVortex", "LoadedConformal"} <= kinds
    assert {"field-n4-s+0.npz", "vortex-linked.obj", "vortex-linked.json", "stripes.obj", "boundary-n4.npz",
            "conformal-mobius.npz", "conformal-spot.npz"} <= set(files)
    shots = _has_screenshots(tmp_path)
    monkeypatch.chdir(tmp_path)
    for f in files:
        path = demo_dir / f
        res = read_result(path)
        faces, n_points, n_curves = _expected_content(path, res)
        scene = scene_of(res)
        if faces is not None:
            assert scene.meshes[0].faces.shape == (faces, 3), f
        else:
            assert scene.meshes == [], f
        assert sum(len(p.points) for p in scene.points) == n_points, f
        assert len(scene.curves) == n_curves, f
        base = os.path.splitext(f)[0]
        if shots:
            assert main(["view", str(path), "--screenshot", f"{base}.png", "--size", "160", "-q"]) == 0
            assert os.path.getsize(f"{base}.png") > 1000
        else:
            assert _scene_of_cli(path).title == scene.title
        assert _scene_of_cli(demo_dir / base).title == scene.title  # the output base opens too


def test_view_of_a_folder_names_the_outputs_in_it(demo_dir, capsys):
    assert main(["view", str(demo_dir)]) == 2
    err = capsys.readouterr().err
    assert "is a folder" in err and "boundary-n4" in err


def test_every_command_output_opens(tmp_path, monkeypatch):
    """What field, stripes, vortex and conformal write opens, as an output base and as each file."""
    monkeypatch.chdir(tmp_path)
    torus = example_path("torus.obj")
    assert main(["field", torus, "--n", "4", "-o", "f", "-q", "--no-png"]) == 0
    assert main(["stripes", torus, "--spacing", "4", "-o", "s", "-q", "--no-png"]) == 0
    assert main(["vortex", "--box", "6", "--velocity", "ring", "-o", "v", "--no-png", "-q"]) == 0
    assert main(["vortex", "--box", "6", "--velocity", "ring", "-o", "v.ply", "--no-png", "-q"]) == 0
    assert main(["conformal", "--ball", "3", "-o", "c", "--no-png", "-q"]) == 0
    F = read_surface(torus)[1]
    expect = {"f": ("DirectionField", len(F)), "s": ("LoadedStripes", len(F)), "v": ("LoadedVortex", None),
              "c": ("LoadedConformal", None)}
    for base, (kind, faces) in expect.items():
        files = sorted(p for p in os.listdir() if p.startswith(base + ".") and p.endswith(DATA_EXTENSIONS))
        assert files, base
        for path in [base, *files]:
            res = read_result(path)
            assert type(res).__name__ == kind, path
            scene = _scene_of_cli(path)
            if faces is not None:
                assert scene.meshes[0].faces.shape == (faces, 3)
    v = read_result("v")
    assert v.mesh is not None and len(v.mesh.points) == 7**3            # the JSON names the domain: box 6
    assert [m.name for m in scene_of(v).meshes] == ["domain"]
    assert [c.name for c in scene_of(v).curves] == ["outline"] + [f"filament {k}" for k in range(len(v.filaments))]
    assert len(v.filaments) > 0 and len(scene_of(v).curves[0].edges) == 12 * 6     # the box's 12 edges, 6 pieces each
    c = read_result("c.mesh")
    assert c.input_known and c.distortion.shape == (len(c.mesh.tets),) and c.distortion.min() >= 1.0 - 1e-9
    assert [(m.name, m.shown_scalar) for m in scene_of(c).meshes] == [("before", "distortion"),
                                                                       ("deformed", "distortion")]


@pytest.mark.parametrize("n", [1, 2])
def test_file_route_stripe_scene_is_the_memory_scene(tmp_path, monkeypatch, n):
    """``dhlb view`` of a stripe OBJ draws the texture of the pattern in memory (the file route once drew raw u)."""
    from dhlb.fields import direction_field
    from dhlb.stripes import stripe_pattern

    V, F = read_surface(example_path("torus.obj"))
    res = stripe_pattern(V, F, direction_field(V, F, n=n), spacing=4.0)
    monkeypatch.chdir(tmp_path)
    res.save("s.obj")
    mem, got = scene_of(res), _scene_of_cli("s")
    a, b = mem.meshes[0], got.meshes[0]
    assert np.array_equal(a.points, b.points) and np.array_equal(a.faces, b.faces)
    assert a.corner_uv.shape == b.corner_uv.shape == (len(F), 3, 2)
    assert np.allclose(a.corner_uv, b.corner_uv, rtol=0, atol=1e-12)   # u = α/2π through the file: last bits only
    assert np.array_equal(a.scalars["zero index"], b.scalars["zero index"])
    assert [(p.name, p.points.tolist(), p.colors.tolist()) for p in mem.points] == \
        [(p.name, p.points.tolist(), p.colors.tolist()) for p in got.points]
    assert [c.name for c in mem.curves] == [c.name for c in got.curves] == ["isolines"]
    assert mem.curves[0].edges.shape == got.curves[0].edges.shape
    assert np.allclose(mem.curves[0].nodes, got.curves[0].nodes, rtol=0, atol=1e-9)
    assert mem.title == got.title


def _pixels(path):
    import matplotlib.image as mi

    return mi.imread(path)[..., :3]


def _same_picture(res, back, tmp_path):
    a = _pixels(picture(res, tmp_path / "memory.png", (200, 200)))
    b = _pixels(picture(back, tmp_path / "file.png", (200, 200)))
    assert a.shape == b.shape == (200, 200, 3)
    assert np.abs(a - 1).max(axis=2).mean() > 0.01                    # not an empty picture
    differ = np.abs(a - b).max(axis=2) > 2 / 255
    assert differ.mean() <= 1e-3, differ.mean()                        # identical up to a few anti-aliased pixels


def test_field_picture_from_file_is_the_memory_picture(tmp_path):
    from dhlb.fields import direction_field

    res = direction_field(*read_surface(example_path("torus.obj")), n=4)
    res.save(tmp_path / "f.npz")
    back = read_result(tmp_path / "f")
    assert back.index_sum == res.index_sum and np.array_equal(back.face_index, res.face_index)
    assert np.allclose(back.directions, res.directions, rtol=0, atol=1e-12)
    _same_picture(res, back, tmp_path)


@pytest.mark.parametrize("n", [1, 2])
def test_stripes_picture_from_file_is_the_memory_picture(tmp_path, n):
    from dhlb.fields import direction_field
    from dhlb.stripes import stripe_pattern

    V, F = read_surface(example_path("torus.obj"))
    res = stripe_pattern(V, F, direction_field(V, F, n=n), spacing=4.0)
    res.save(tmp_path / "s.obj")
    _same_picture(res, read_result(tmp_path / "s.obj"), tmp_path)


def test_vortex_picture_from_file_is_the_memory_picture(tmp_path):
    from dhlb.cli.vortex import demo_velocity
    from dhlb.mesh import box_tet_mesh
    from dhlb.vortex import vortex_filaments

    mesh = box_tet_mesh(6, lower=-1.0, upper=1.0)
    res = vortex_filaments(mesh, None, demo_velocity("ring", mesh.points)[0], 1.0)
    res.save(tmp_path / "v.obj")
    with open(tmp_path / "v.json", "w") as fh:                          # as dhlb vortex --box 6 writes it
        json.dump({"mesh": "box 6", **res.to_json()}, fh)
    back = read_result(tmp_path / "v.obj")
    assert [f.closed for f in back.filaments] == [f.closed for f in res.filaments]
    _same_picture(res, back, tmp_path)


def test_conformal_picture_from_file_is_the_memory_picture(tmp_path):
    from dhlb.conformal import conformal_deformation, point_charge_factor
    from dhlb.mesh import ball_tet_mesh

    res = conformal_deformation(ball_tet_mesh(3), None, point_charge_factor([(2.0, 0.0, 0.0, 0.5)]))
    res.save(tmp_path / "c.npz")
    back = read_result(tmp_path / "c.npz")
    assert back.input_known and np.array_equal(back.distortion, res.distortion)
    _same_picture(res, back, tmp_path)
    res.save(tmp_path / "d.json")                       # to_json: the deformed mesh and its distortion, no input
    back = read_result(tmp_path / "d.json")
    assert not back.input_known and np.array_equal(back.distortion, res.distortion)
    drawn = scene_of(res)                               # before and after, side by side
    assert [m.name for m in drawn.meshes] == ["before", "deformed"]
    a, b = drawn.meshes[1], scene_of(back).meshes[0]    # without the input: the deformed boundary alone, as computed
    assert np.array_equal(b.points, res.points) and np.array_equal(a.faces, b.faces)
    assert np.array_equal(a.scalars["distortion"], b.scalars["distortion"])
