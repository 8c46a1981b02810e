"""dhlb.render.web: the interactive views agree with the PNG pictures and open offline (without a browser).

The browser itself (WebGL pixels, rotation, hover) is tested in tests/test_web_browser.py.
"""
import base64
import json
import os
import re
import sys
from collections import Counter

import numpy as np
import pytest

pytest.importorskip("plotly")

from dhlb.cli import main
from dhlb.errors import InvalidParameterError, OutputError
from dhlb.fields import direction_field
from dhlb.io import example_path, read_result, read_surface
from dhlb.render import Camera
from dhlb.render import web as rw
from dhlb.render._figure import mean_edge_length
from dhlb.render.registry import show
from dhlb.render.scene import scene_of

URL = re.compile(r"""https?://[^\s"'<>)]+""")


def _trace(spec, name):
    found = [t for t in spec["data"] if t["name"] == name]
    assert len(found) == 1, [t["name"] for t in spec["data"]]
    return found[0]


def _decode(page):
    """The figure inside a page written by to_html, with its typed arrays decoded."""
    text = re.search(r"var fig = (\{.*?\}); var gd", page, re.S).group(1).replace("<\\/", "</")

    def hook(d):
        if set(d) == {"dtype", "bdata"}:
            return np.frombuffer(base64.b64decode(d["bdata"]), dtype=np.dtype(d["dtype"]))
        return d

    return json.loads(text, object_hook=hook)


@pytest.fixture(scope="module")
def torus():
    return read_surface(example_path("torus.obj"))


@pytest.fixture(scope="module")
def demo(tmp_path_factory):
    out = tmp_path_factory.mktemp("demo")
    assert main(["demo", "-o", str(out), "-q", "--json"]) == 0
    return out


def test_the_demo_writes_a_view_beside_every_picture_sharing_one_script(demo):
    pngs = sorted(f for f in os.listdir(demo) if f.endswith(".png") and not f.endswith("-back.png") and "-3d-" not in f)
    assert len(pngs) == 17                                          # every result of every step
    index = (demo / "index.html").read_text()
    for png in pngs:
        page = demo / (png[:-4] + ".html")
        assert page.is_file(), png
        text = page.read_text()
        assert '<script src="plotly.min.js"></script>' in text      # the one shared copy, relative
        assert not URL.findall(text), (page, URL.findall(text))     # nothing from the network
        assert f'data-view="{page.name}"' in index
    assert index.count('class="dhlb-rotate"') == 17
    assert (demo / "plotly.min.js").stat().st_size == os.path.getsize(rw.plotlyjs_path())
    assert not URL.findall(index)


def test_every_demo_output_writes_a_self_contained_page(demo, tmp_path):
    import plotly.graph_objects as go

    kinds = set()
    for f in sorted(os.listdir(demo)):
        if os.path.splitext(f)[1] not in (".npz", ".obj") or f.endswith("-3d.obj"):
            continue
        res = read_result(demo / f)
        kinds.add(type(res).__name__)
        page = rw.to_html(res, tmp_path / (f + ".html"))
        text = open(page).read()
        script_end = text.index("</script>", text.index("window.define = undefined"))
        script_end = text.index("</script>", script_end + 1)              # plotly's own script, inline
        assert not URL.findall(text[script_end:]), f                      # the rest names no URL
        fig = _decode(text)
        go.Figure(fig)                                                    # plotly's validator accepts it
        assert fig["layout"]["scene"]["camera"]["projection"]["type"] == "orthographic"
    assert kinds == {"DirectionField", "LoadedStripes", "LoadedVortex", "LoadedConformal"}


def test_field_view_has_the_singularities_of_the_picture():
    spot = read_surface(example_path("spot.obj"))                           # χ = 2: singularities for every n
    for n in (1, 2, 4):
        res = direction_field(*spot, n=n)
        spec = rw.figure_spec(res)
        sing = _trace(spec, "singularities")
        shown = Counter(re.search(r"index ([+-][\d/]+)", t).group(1) for t in sing["hovertext"])
        expected = Counter(label.split("index ")[1] for label in scene_of(res).points[0].labels)
        assert shown == expected and sum(shown.values()) == len(res.singularities.faces) > 0
        signs = Counter(np.sign(res.singularities.index).tolist())          # what the PNG colours red / blue
        colors = Counter(sing["marker"]["color"])
        assert colors == {c: k for c, k in (("rgb(217,31,26)", signs[1]), ("rgb(26,64,217)", signs[-1])) if k}
        faces = [int(re.search(r"face (\d+)", t).group(1)) for t in sing["hovertext"]]
        assert faces == res.singularities.input_faces.tolist()
        glyphs = _trace(spec, "mesh: glyphs")
        per_vertex = 7 if n == 1 else 4 * (n // 2)                # arrow: shaft + head; cross: n/2 lines of two arms
        assert len(glyphs["x"]) == per_vertex * min(res.mesh.n_vertices, rw.MAX_GLYPHS)


def test_cross_arms_are_the_directions_of_the_field(torus):
    res = direction_field(*torus, n=4)
    g = _trace(rw.figure_spec(res), "mesh: glyphs")
    X = np.stack([g["x"], g["y"], g["z"]], axis=1).astype(np.float64).reshape(-1, 8, 3)
    assert np.isnan(X[:, 3]).all() and np.isnan(X[:, 7]).all()
    assert np.array_equal(X[:, 1], X[:, 5])                                 # both lines pass through the vertex
    ell = 0.45 * mean_edge_length(res.mesh.points, res.mesh.faces)
    for col, k in ((2, 0), (6, 1), (0, 2), (4, 3)):                          # the arm of direction k
        assert np.allclose((X[:, col] - X[:, 1]) / ell, res.directions[:, k], atol=1e-5)
    lifted = X[:, 1] - res.mesh.points                                      # just above the surface
    assert np.allclose(np.linalg.norm(lifted, axis=1), 0.08 * ell, rtol=1e-4)


def test_stripe_view_carries_the_texture_per_corner():
    from dhlb.stripes import stripe_pattern

    V, F = read_surface(example_path("spot.obj"))                           # zeros and branch points
    res = stripe_pattern(V, F, direction_field(V, F, n=2), spacing=6.0)
    tex = res.texture
    spec = rw.figure_spec(res)
    mesh = _trace(spec, "mesh")
    X, T, alpha, face, bary = rw.stripe_surface(tex)
    assert np.array_equal(mesh["intensity"], np.cos(alpha).astype(np.float32))
    corner = np.isclose(bary, 1.0, rtol=0, atol=1e-15).any(axis=1)
    c = np.argmax(bary[corner], axis=1)
    regular = ~np.isin(face[corner], np.r_[tex.zero_faces, tex.branch_faces])
    # plain faces: exactly the stored per-corner α; every face: the texture's own value there
    assert np.array_equal(alpha[corner][regular], tex.corner_alpha[face[corner][regular], c[regular]])
    assert np.allclose(np.cos(alpha[corner]), np.cos(tex.evaluate(face[corner], np.eye(3)[c])), atol=1e-9)
    assert set(face[corner].tolist()) == set(range(len(F)))            # every face's corners are drawn
    assert np.allclose(X, np.einsum("kc,kcd->kd", bary, res.mesh.points[res.mesh.faces[face]]))
    assert (np.ptp(face[T], axis=1) == 0).all()                             # no triangle straddles two faces
    coarse = _trace(rw.figure_spec(res, max_faces=1000), "mesh")               # above the limit: decimated
    assert len(coarse["i"]) <= 1000 and len(coarse["intensity"]) == len(coarse["x"])
    assert np.abs(coarse["intensity"]).max() <= 1 and np.ptp(coarse["intensity"]) > 1   # stripes still there
    zeros = _trace(spec, "zeros")
    assert len(zeros["hovertext"]) == tex.zero_faces.size and all("index" in t for t in zeros["hovertext"])
    assert len(_trace(spec, "branch points")["x"]) == tex.branch_faces.size


def test_vortex_view_draws_every_filament_and_the_box():
    from dhlb.cli.vortex import demo_velocity
    from dhlb.mesh import box_tet_mesh
    from dhlb.vortex import vortex_filaments

    mesh = box_tet_mesh(12, lower=-1.0, upper=1.0)                     # the demo's cube
    res = vortex_filaments(mesh, None, demo_velocity("linked-rings", mesh.points)[0], 1.0)
    spec = rw.figure_spec(res)
    names = [t["name"] for t in spec["data"]]
    assert names.count("domain") == 1 and names.count("outline") == 1
    assert sorted(n for n in names if n.startswith("filament")) == [f"filament {k}" for k in range(len(res.filaments))]
    assert len(res.filaments) == 2                                     # as the PNG's title says
    for k, f in enumerate(res.filaments):
        t = _trace(spec, f"filament {k}")
        drawn = np.stack([t["x"], t["y"], t["z"]], axis=1)
        assert np.allclose(drawn[:len(f.points)], f.points, atol=1e-6)
        assert np.allclose(drawn[len(f.points)], f.points[0], atol=1e-6) == f.closed
        assert t["hovertext"] == f"filament {k}: {'closed' if f.closed else 'open'}, {len(f.points)} points"
    assert _trace(spec, "outline")["hoverinfo"] == "skip"
    assert len(_trace(spec, "domain")["i"]) == len(mesh.boundary_faces)


def test_conformal_view_before_and_after_with_one_colour_bar():
    from dhlb.conformal import conformal_deformation, point_charge_factor
    from dhlb.mesh import ball_tet_mesh
    from dhlb.render.conformal_png import boundary_distortion, distortion_range

    m = ball_tet_mesh(3)
    res = conformal_deformation(m.points, m.tets, point_charge_factor([(2.0, 0.0, 0.0, 0.5)]))
    spec = rw.figure_spec(res)
    before, after = _trace(spec, "before"), _trace(spec, "deformed")
    _, dF = boundary_distortion(res)
    for t in (before, after):
        assert np.array_equal(t["intensity"], dF.astype(np.float32)) and t["intensitymode"] == "cell"
        assert (t["cmin"], t["cmax"]) == distortion_range(dF)
    assert (before["showscale"], after["showscale"]) == (False, True)
    assert "distortion" in after["colorbar"]["title"]["text"]


def test_large_meshes_are_decimated_for_the_view_and_the_view_says_so():
    V, F = read_surface(example_path("spot.obj"))
    res = direction_field(V, F, n=2)
    spec = rw.figure_spec(res, max_faces=1000, max_glyphs=100)
    mesh = _trace(spec, "mesh")
    assert len(mesh["i"]) <= 1000
    assert "decimated to" in spec["layout"]["title"]["text"] and f"{len(F):,} faces" in spec["layout"]["title"]["text"]
    assert len(_trace(spec, "mesh: glyphs")["x"]) == 4 * 100
    assert len(_trace(spec, "singularities")["x"]) == len(res.singularities.faces)  # every singularity stays
    P, T, _ = rw.decimate(V, F, 1000)
    assert len(T) == len(np.unique(np.sort(T, axis=1), axis=0))            # no duplicate, no degenerate face
    assert (T[:, 0] != T[:, 1]).all() and (T[:, 1] != T[:, 2]).all() and (T[:, 0] != T[:, 2]).all()
    assert (np.ptp(P, axis=0) > 0.85 * np.ptp(V, axis=0)).all()              # the same shape, coarser
    assert (P.min(axis=0) >= V.min(axis=0)).all() and (P.max(axis=0) <= V.max(axis=0)).all()


def test_the_camera_is_the_pictures_camera(torus):
    res = direction_field(*torus, n=4)
    scene = scene_of(res)
    lo, hi = scene.bounds()
    cam = rw.figure_spec(res)["layout"]["scene"]["camera"]
    eye = np.array([cam["eye"][a] for a in "xyz"])
    fitted = np.asarray(Camera().fitted(np.vstack([lo, hi])).view)
    assert np.allclose(eye / np.linalg.norm(eye), fitted / np.linalg.norm(fitted))
    assert [cam["up"][a] for a in "xyz"] == [0.0, 1.0, 0.0]
    given = rw.figure_spec(res, camera=Camera(view=(0, 0, 1), up="z"))["layout"]["scene"]["camera"]
    assert given["eye"]["z"] > 0 and given["eye"]["x"] == given["eye"]["y"] == 0 and given["up"]["z"] == 1.0


def test_bad_input_gets_a_clear_error(torus, tmp_path):
    res = direction_field(*torus, n=1)
    with pytest.raises(InvalidParameterError, match="max_faces"):
        rw.figure_spec(res, max_faces=0)
    with pytest.raises(OutputError, match="folder does not exist"):
        rw.to_html(res, tmp_path / "missing" / "v.html")
    with pytest.raises(InvalidParameterError, match="backend"):
        res.show(backend="matplotlib")
    with pytest.raises(InvalidParameterError, match="to_html"):
        res.show(backend="web", screenshot="x.png")
    with pytest.raises(InvalidParameterError, match="cannot show"):
        rw.figure_spec(object())


def test_notebook_views_send_plotly_once(torus, monkeypatch):
    res = direction_field(*torus, n=4)
    monkeypatch.setattr(rw, "_SENT", {})
    monkeypatch.delenv("DHLB_WEB_SCRIPT", raising=False)
    first, second = res.show(backend="web"), res.show(backend="web")
    a, b = first._repr_mimebundle_()["text/html"], second._repr_mimebundle_()["text/html"]
    assert len(a) > 4_000_000 > 1_000_000 > len(b)                         # plotly's script: the first view only
    assert "window.define = undefined" in a and "Plotly.newPlot" in b
    assert re.search(r'id="(dhlb-view-\w+)"', a).group(1) != re.search(r'id="(dhlb-view-\w+)"', b).group(1)
    monkeypatch.setattr(rw, "_SENT", {})
    monkeypatch.setenv("DHLB_WEB_SCRIPT", "page")                          # the docs page provides plotly
    assert len(rw.notebook_view(res)) < 1_000_000


def test_a_web_view_outside_a_notebook_saves_or_opens_a_page(torus, tmp_path, monkeypatch):
    import webbrowser

    from dhlb.errors import ViewerUnavailableError

    view = direction_field(*torus, n=4).show(backend="web")
    assert ".open()" in repr(view)
    page = view.save(tmp_path / "v.html", plotlyjs="directory")
    assert _decode(open(page).read())["data"][0]["name"] == "mesh"
    opened = []
    monkeypatch.setattr(webbrowser, "open", lambda url: opened.append(url) or True)
    path = view.open()
    assert opened == ["file://" + path] and os.path.getsize(path) > 4_000_000   # self-contained
    monkeypatch.setattr(webbrowser, "open", lambda url: False)                  # no browser here
    with pytest.raises(ViewerUnavailableError, match=r"\.save\(path\)"):
        view.open()


def test_notebook_display_setting(torus, monkeypatch):
    from dhlb._result import set_notebook_display

    res = direction_field(*torus, n=2)
    monkeypatch.setenv("DHLB_WEB_SCRIPT", "page")
    assert "<img" in res._repr_html_()
    old = set_notebook_display("web")
    try:
        html = res._repr_html_()
        assert "dhlb-web-view" in html and "<table>" in html and "<img" not in html
    finally:
        set_notebook_display(old)
    with pytest.raises(ValueError, match="'png' or 'web'"):
        set_notebook_display("svg")


def test_without_plotly_the_web_view_is_the_picture_and_pages_name_the_extra(torus, tmp_path, monkeypatch):
    res = direction_field(*torus, n=2)
    monkeypatch.setitem(sys.modules, "plotly", None)
    view = res.show(backend="web")
    bundle = view._repr_mimebundle_()
    assert not view.interactive and bundle["image/png"][:8] == b"\x89PNG\r\n\x1a\n"
    assert 'pip install ".[web]"' in bundle["text/html"] and "pip install plotly" in bundle["text/html"]
    with pytest.raises(ImportError, match=re.escape('pip install ".[web]"')):
        res.to_html(tmp_path / "v.html")
    assert not (tmp_path / "v.html").exists()
    with pytest.raises(ImportError, match=re.escape('pip install ".[web]"')):   # a Scene has no picture
        show(scene_of(res), backend="web")


def test_dhlb_view_html(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    torus = example_path("torus.obj")
    assert main(["field", torus, "--n", "4", "-o", "f", "-q", "--no-png"]) == 0
    assert main(["view", "f", "--html", "f.html", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["written"] == ["f.html"] and out["bytes"] > 4_000_000           # self-contained
    fig = _decode(open("f.html").read())
    assert [t["name"] for t in fig["data"]] == ["mesh", "mesh: glyphs", "singularities"]
    assert main(["view", "f", "--html", "g.html", "--shared-script", "--view", "0,0,1", "-q"]) == 0
    assert os.path.isfile("plotly.min.js") and os.path.getsize("g.html") < 1_000_000
    assert _decode(open("g.html").read())["layout"]["scene"]["camera"]["eye"]["x"] == 0
    bad_calls = ((["--html", "f.png"], "must name a .html"), (["--shared-script"], "needs --html"),
                 (["--html", "a.html", "--screenshot", "a.png"], "not both"))
    for bad, message in bad_calls:
        assert main(["view", "f", *bad]) == 2
        assert message in capsys.readouterr().err
