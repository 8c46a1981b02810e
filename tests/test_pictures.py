"""What a reader notices in the pictures and views (issue 42, point 9): each test fails on the defect it names.

- titles count in the singular for one ("1 filament", not "1 filaments");
- a title never overlaps the drawn mesh, and a long title wraps instead of running off the picture;
- glyphs on a fine mesh are a bounded, evenly spread subset (one per vertex merged into a moiré), in the PNG,
  the web view and the polyscope viewer;
- the filaments' lines show no white notch at their own joints (the halo of the next segment covered them);
- the web view of a stripe pattern shades smoothly (its refined copy was unwelded and flat: every face showed),
  and markers and isolines on a surface sit above it (they were half buried);
- the conformal before/after pair of the web view cannot overlap however the view turns;
- polyscope is told not to keep its ``.polyscope.ini`` in the working folder.
"""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from tests.surface_meshes import icosphere


def _rgb(path) -> np.ndarray:
    return np.asarray(Image.open(path).convert("RGB"), dtype=np.float64) / 255.0


def _tangent_cross(P):
    """A cross field (4 unit directions per vertex) tangent to the unit sphere, zero at the poles."""
    n = P / np.linalg.norm(P, axis=1, keepdims=True)
    d = np.cross(n, [0.0, 0.0, 1.0])
    d /= np.maximum(np.linalg.norm(d, axis=1, keepdims=True), 1e-12)
    e = np.cross(n, d)
    return np.stack([d, e, -d, -e], axis=1)


# ---------------------------------------------------------------------------- counts in titles
def test_titles_say_one_filament_in_the_singular(monkeypatch, tmp_path):
    from dhlb.cli.vortex import demo_velocity
    from dhlb.mesh import box_tet_mesh
    from dhlb.render import registry
    from dhlb.render.scene import scene_of
    from dhlb.vortex import vortex_filaments

    try:
        from dhlb.render._figure import plural
    except ImportError:                                            # before the helper: the titles are checked first
        plural = None

    mesh = box_tet_mesh(8, lower=-1.0, upper=1.0)
    res = vortex_filaments(mesh, None, demo_velocity("ring", mesh.points)[0], 1.0)
    assert len(res.filaments) == 1
    assert scene_of(res).title == "1 filament"                     # the web view's title
    titles = []
    monkeypatch.setattr("dhlb.render.render_filaments_png", lambda *a, title=None, **k: titles.append(title))
    registry.picture(res, tmp_path / "v.png")                      # the notebook picture
    assert titles == ["1 filament"]
    assert plural is not None and (plural(0, "zero"), plural(1, "branch face"), plural(2, "branch face")) == \
        ("0 zeros", "1 branch face", "2 branch faces")


# ---------------------------------------------------------------------------- titles and layout
def _text_and_mesh_rows(img):
    """Rows with dark neutral pixels (text) and rows with green pixels (the mesh, drawn in pure green)."""
    r, g, b = img[..., 0], img[..., 1], img[..., 2]
    text = (np.abs(r - g) < 0.08) & (np.abs(g - b) < 0.08) & (g < 0.6)
    mesh = (g > r + 0.15) & (g > b + 0.15)
    return np.nonzero(text.any(axis=1))[0], np.nonzero(mesh.any(axis=1))[0]


def test_the_title_of_a_field_picture_stays_above_a_tall_mesh(tmp_path):
    from dhlb.render import Camera, FieldStyle, render_field_png

    V, F = icosphere(3)
    V = V * [1.0, 3.0, 1.0]                                        # tall, as the kitten seen from the front
    path = render_field_png(tmp_path / "t.png", V, F, camera=Camera(view=(0, 0, 1), size=(400, 400)),
                            style=FieldStyle(face_color=(0.0, 1.0, 0.0), ambient=1.0),
                            title="a tall mesh with a title of some length")
    text, mesh = _text_and_mesh_rows(_rgb(path))
    assert len(text) and len(mesh)
    assert text.max() < mesh.min(), f"the title (rows {text.min()}..{text.max()}) overlaps the mesh (from {mesh.min()})"
    assert mesh.max() - mesh.min() > 0.75 * 400                    # the mesh still fills the rest


def test_a_long_title_wraps_inside_the_picture(tmp_path):
    from dhlb.render import Camera, FieldStyle, render_field_png

    V, F = icosphere(2)
    title = "stripe pattern along the smoothest line field (spacing 6 mean edge lengths), seen from the back"
    path = render_field_png(tmp_path / "t.png", V, F, camera=Camera(view=(0, 0, 1), size=(240, 240)),
                            style=FieldStyle(face_color=(0.0, 1.0, 0.0), ambient=1.0), title=title)
    img = _rgb(path)
    text, mesh = _text_and_mesh_rows(img)
    band = img[:text.max() + 1]
    dark = (band.max(axis=2) < 0.6).any(axis=0)
    assert not dark[-3:].any(), "the title runs off the right edge"
    assert len(text) > 2 * 14 and text.max() < mesh.min()         # two lines or more, above the mesh


def test_the_conformal_title_stays_above_the_panels(tmp_path):
    from dhlb.mesh import ball_tet_mesh
    from dhlb.render.conformal_png import render_conformal_png

    m = ball_tet_mesh(3)
    F = m.boundary_faces
    path = render_conformal_png(tmp_path / "c.png", m.points * [1.0, 3.0, 1.0], m.points * [1.0, 3.0, 1.0], F,
                                np.linspace(1.0, 1.3, len(F)), title="a long title " * 20)
    img = _rgb(path)
    top = img[: img.shape[0] // 2]
    text = (top.max(axis=2) < 0.35).any(axis=1)                   # black text (the panels are viridis colours)
    coloured = ((top.max(axis=2) - top.min(axis=2)) > 0.25).any(axis=1)
    rows_text, rows_mesh = np.nonzero(text)[0], np.nonzero(coloured)[0]
    first_line = rows_text[rows_text < rows_mesh.min()]
    edges = np.concatenate([top[:, :3], top[:, -3:]], axis=1)
    assert len(first_line) and not (edges.max(axis=2) < 0.6).any()      # nothing runs off either side
    assert not np.intersect1d(rows_text[rows_text <= first_line.max() + 2], rows_mesh).size


# ---------------------------------------------------------------------------- glyphs on fine meshes
@pytest.fixture(scope="module")
def fine_sphere():
    V, F = icosphere(5)                                            # 10 242 vertices: several per 10 pixels
    return V, F


def test_glyph_sites_on_a_fine_mesh_are_bounded_and_even(fine_sphere):
    from scipy.spatial import cKDTree

    from dhlb.render._figure import mean_edge_length
    from dhlb.render.png import GLYPH_SPACING, glyph_sites

    V, F = fine_sphere
    seen = np.nonzero(V[:, 2] > 0)[0]
    sites, gap = glyph_sites(V, seen, mean_edge_length(V, F), V[:, :2], (400, 400), 100, 40000)
    pixels = 400 / (1.06 * 2)
    assert gap * pixels >= GLYPH_SPACING * 100 / 72 - 1e-9        # at least 10 pixels apart on the picture
    assert len(sites) <= (400 / (GLYPH_SPACING * 100 / 72)) ** 2  # a bounded number
    tree = cKDTree(V[sites])
    assert tree.query(V[sites], k=2)[0][:, 1].min() >= gap         # none closer than the spacing
    assert tree.query(V[seen])[0].max() <= (1 + np.sqrt(3)) * gap  # and no vertex far from a glyph
    few, gap_few = glyph_sites(V, seen, mean_edge_length(V, F), V[:, :2], (400, 400), 100, 300)
    assert len(few) <= 300 and cKDTree(V[few]).query(V[few], k=2)[0][:, 1].min() >= gap_few


def test_the_glyphs_of_a_fine_mesh_do_not_turn_it_grey(fine_sphere, tmp_path):
    from dhlb.render import Camera, FieldStyle, render_field_png

    V, F = fine_sphere
    path = render_field_png(tmp_path / "g.png", V, F, _tangent_cross(V), camera=Camera(view=(0.3, 0.4, 1.0),
                                                                                       size=(400, 400)),
                            style=FieldStyle(face_color=(1.0, 1.0, 1.0), ambient=1.0, glyph_color="black"))
    img = _rgb(path).min(axis=2)
    disk = np.add.outer((np.arange(400) - 200.0) ** 2, (np.arange(400) - 200.0) ** 2) < 150.0 ** 2
    dark = float((img[disk] < 0.5).mean())
    assert dark < 0.2, f"{dark:.2f} of the sphere is covered by glyphs (a moiré)"


def test_the_web_view_spreads_its_glyphs_evenly(fine_sphere):
    from scipy.spatial import cKDTree

    from dhlb.fields import direction_field
    from dhlb.render import web as rw

    pytest.importorskip("plotly")
    V, F = fine_sphere
    res = direction_field(V, F, n=4)
    g = next(t for t in rw.figure_spec(res, max_glyphs=500)["data"] if t["name"] == "mesh: glyphs")
    X = np.stack([g["x"], g["y"], g["z"]], axis=1).astype(np.float64).reshape(-1, 8, 3)
    base = X[:, 1]                                                 # where the two lines of a cross meet
    assert len(base) <= 500
    near = cKDTree(base).query(base, k=2)[0][:, 1]
    arm = np.linalg.norm(X[:, 2] - base, axis=1).mean()            # 0.45 of the spacing
    assert near.min() >= 0.9 * arm / 0.45, "glyph sites crowd together (an uneven subset)"
    assert cKDTree(base).query(V)[0].max() <= (1 + np.sqrt(3)) * arm / 0.45 * 1.05


def test_the_viewer_draws_a_bounded_evenly_spread_set_of_glyphs(fine_sphere):
    from scipy.spatial import cKDTree

    from dhlb.fields import direction_field
    from dhlb.render import view
    from dhlb.render.scene import scene_of

    V, F = fine_sphere
    drawn = {}

    class Structure:
        def __getattr__(self, name):
            return lambda *a, **k: None

        def add_vector_quantity(self, name, values, **kw):
            drawn[name] = np.asarray(values)

    class Polyscope:
        def __getattr__(self, name):
            return lambda *a, **k: Structure()

    view._register(Polyscope(), scene_of(direction_field(V, F, n=4)))
    assert len(drawn) == 4
    shown = np.nonzero(np.any([np.linalg.norm(v, axis=1) > 0 for v in drawn.values()], axis=0))[0]
    assert 0 < len(shown) <= 3000 < len(V)                          # at most the web view's MAX_GLYPHS
    length = np.linalg.norm(drawn["direction 0"][shown], axis=1).mean() / 0.45   # the spacing of the glyphs
    assert cKDTree(V[shown]).query(V[shown], k=2)[0][:, 1].min() >= 0.999 * length   # evenly spread, as far apart


# ---------------------------------------------------------------------------- filaments
def test_a_filament_line_has_no_white_notches(tmp_path):
    from dhlb.render import Camera, FilamentStyle, render_filaments_png
    from dhlb.render._figure import FILAMENT_COLORS

    t = np.cumsum(np.tile([0.004, 0.05], 90))                     # short and long segments, as traced filaments
    t = 2 * np.pi * t / (t[-1] + 0.05)
    ring = np.stack([np.cos(t), np.sin(t), np.zeros_like(t)], axis=1)
    path = render_filaments_png(tmp_path / "f.png", [ring], camera=Camera(view=(0, 0, 1), size=(300, 300)),
                                style=FilamentStyle(line_width=3.0))
    img = _rgb(path)
    red = np.abs(img - FILAMENT_COLORS[0]).max(axis=2) < 0.1
    rows, cols = np.nonzero(red)
    c = np.array([cols.mean(), rows.mean()])
    r = np.hypot(cols - c[0], rows - c[1]).mean()
    a = np.linspace(0, 2 * np.pi, 4000, endpoint=False)
    x, y = np.rint(c[0] + r * np.cos(a)).astype(int), np.rint(c[1] + r * np.sin(a)).astype(int)
    on = red[y, x]
    assert on.mean() > 0.99, f"{(~on).sum()} of 4000 points along the filament are not its colour (notches)"


# ---------------------------------------------------------------------------- web views: stripes, markers
@pytest.fixture(scope="module")
def torus_stripes():
    from dhlb.fields import direction_field
    from dhlb.io import example_path, read_surface
    from dhlb.stripes import stripe_pattern

    V, F = read_surface(example_path("double-torus.obj"))          # zeros, branch points, nodes inside faces
    return stripe_pattern(V, F, direction_field(V, F, n=2), spacing=5.0)


def _plotly_normals(X, T):
    """Vertex normals as a browser computes them for mesh3d: the sum of the normals of the triangles at a vertex."""
    n = np.cross(X[T[:, 1]] - X[T[:, 0]], X[T[:, 2]] - X[T[:, 0]])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    vn = np.zeros_like(X)
    for c in range(3):
        np.add.at(vn, T[:, c], n)
    return vn / np.maximum(np.linalg.norm(vn, axis=1, keepdims=True), 1e-300)


def test_the_web_stripes_shade_smoothly(torus_stripes):
    pytest.importorskip("plotly")
    from dhlb.render import web as rw

    res = torus_stripes
    mesh = next(t for t in rw.figure_spec(res)["data"] if t["name"] == "mesh")
    X = np.stack([mesh["x"], mesh["y"], mesh["z"]], axis=1).astype(np.float64)
    T = np.stack([mesh["i"], mesh["j"], mesh["k"]], axis=1).astype(np.int64)
    used = np.unique(T)
    places = np.unique(np.round(X[used] / 1e-5), axis=0)
    # welded: one vertex per place (two only across a branch cut), so the normals blend across the faces' edges
    assert len(places) >= 0.95 * len(used), f"{len(used)} vertices at {len(places)} places: faces drawn apart"
    _, _, _, face, bary = rw.stripe_surface(res.texture)
    inside = (bary > 1e-9).all(axis=1) & np.isin(np.arange(len(X)), used)
    P, Fm = res.mesh.points, res.mesh.faces
    fn = np.cross(P[Fm[:, 1]] - P[Fm[:, 0]], P[Fm[:, 2]] - P[Fm[:, 0]])
    fn /= np.linalg.norm(fn, axis=1, keepdims=True)
    turn = np.degrees(np.arccos(np.clip(np.einsum("kd,kd->k", _plotly_normals(X, T)[inside], fn[face[inside]]),
                                        -1, 1)))
    assert inside.sum() > 100 and np.median(turn) > 1.0, "inside a face the shading normal is the face's: facets"


def test_markers_and_isolines_sit_above_the_surface(torus_stripes):
    pytest.importorskip("plotly")
    from dhlb.render import web as rw

    res = torus_stripes
    tex = res.texture
    spec = rw.figure_spec(res)
    P, Fm = tex.mesh.points, tex.mesh.faces
    fn = np.cross(P[Fm[:, 1]] - P[Fm[:, 0]], P[Fm[:, 2]] - P[Fm[:, 0]])
    fn /= np.linalg.norm(fn, axis=1, keepdims=True)
    size = next(t for t in spec["data"] if t["name"] == "zeros")["marker"]["size"]
    mesh = next(t for t in spec["data"] if t["name"] == "mesh")
    X = np.stack([mesh["x"], mesh["y"], mesh["z"]], axis=1).astype(np.float64)
    flat, _, _, face, _ = rw.stripe_surface(tex)
    rise = np.einsum("kd,kd->k", X - flat, fn[face])               # how far the drawn surface stands out
    for name, faces, points in (("zeros", tex.zero_faces, tex.zero_points),
                                ("branch points", tex.branch_faces, tex.branch_points)):
        t = next(t for t in spec["data"] if t["name"] == name)
        drawn = np.stack([t["x"], t["y"], t["z"]], axis=1).astype(np.float64)
        lift = np.einsum("kd,kd->k", drawn - points, fn[faces])
        high = np.array([rise[face == f].max(initial=0.0) for f in faces])
        assert (lift > high).all(), f"{name}: a marker is not above the drawn surface"
        assert (lift > 0.2 * size * np.ptp(P, axis=0).max() / 480).all(), f"{name}: a marker is half buried"
    iso = next(t for t in spec["data"] if t["name"] == "isolines")
    assert np.isfinite(np.asarray(iso["x"], dtype=np.float64)).sum() > 100


def test_field_singularities_are_lifted_on_both_sides_of_an_open_surface():
    pytest.importorskip("plotly")
    from dhlb.fields import direction_field
    from dhlb.io import example_path, read_surface
    from dhlb.render import web as rw

    res = direction_field(*read_surface(example_path("saddle.obj")), n=4, align="boundary", lam=-10.0)
    sing = next(t for t in rw.figure_spec(res)["data"] if t["name"] == "singularities")
    drawn = np.stack([sing["x"], sing["y"], sing["z"]], axis=1).astype(np.float64)
    k = len(res.singularities.faces)
    P, Fm = res.mesh.points, res.mesh.faces[res.singularities.faces]
    n = np.cross(P[Fm[:, 1]] - P[Fm[:, 0]], P[Fm[:, 2]] - P[Fm[:, 0]])
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    assert len(drawn) == 2 * k and len(sing["hovertext"]) == 2 * k
    up, down = (np.einsum("kd,kd->k", drawn[s] - res.singularities.points, n) for s in (slice(0, k), slice(k, None)))
    assert (up > 0).all() and (down < 0).all()


# ---------------------------------------------------------------------------- conformal pair
def test_the_conformal_pair_cannot_overlap_however_the_view_turns():
    pytest.importorskip("plotly")
    from dhlb.conformal import conformal_deformation, mobius_factor
    from dhlb.mesh import ball_tet_mesh
    from dhlb.render import web as rw

    m = ball_tet_mesh(3)
    res = conformal_deformation(m.points, m.tets, mobius_factor((1.5, 0.0, 0.0), 1.5))   # grows the ball 2×
    spec = rw.figure_spec(res)
    spheres = []
    for name in ("before", "deformed"):
        t = next(t for t in spec["data"] if t["name"] == name)
        X = np.stack([t["x"], t["y"], t["z"]], axis=1).astype(np.float64)
        c = X.mean(axis=0)
        spheres.append((c, np.linalg.norm(X - c, axis=1).max()))
    (c0, r0), (c1, r1) = spheres
    assert np.linalg.norm(c1 - c0) > r0 + r1, "the two meshes' spheres intersect: a turn shows them overlapping"


# ---------------------------------------------------------------------------- polyscope's files
def test_polyscope_is_told_to_keep_no_prefs_file(monkeypatch):
    from dhlb.render import view

    calls = []

    class Polyscope:
        def __getattr__(self, name):
            return lambda *a, **k: calls.append((name, a))

    monkeypatch.setattr(view, "_STATE", {})
    monkeypatch.setattr(view, "_no_imgui_ini", lambda: None)
    view._init(Polyscope(), headless=True)
    names = [c[0] for c in calls]
    assert ("set_use_prefs_file", (False,)) in calls, names
    assert names.index("set_use_prefs_file") < names.index("init")    # before init, which reads the file


# ---------------------------------------------------------------------------- colours by name
def test_styles_take_colours_by_name(tmp_path, torus_stripes):
    """FieldStyle.face_color and StripeStyle.dark/light accept what they validate: any matplotlib colour."""
    from dhlb.render import Camera, FieldStyle, StripeStyle, render_field_png, render_stripes_png

    V, F = icosphere(2)
    cam = Camera(view=(0, 0, 1), size=(64, 64))
    field = _rgb(render_field_png(tmp_path / "f.png", V, F, camera=cam, style=FieldStyle(face_color="tab:green")))
    stripes = _rgb(render_stripes_png(tmp_path / "s.png", torus_stripes.texture, camera=cam,
                                      style=StripeStyle(dark="navy", light="gold")))
    assert (field[32, 32, 1] > field[32, 32, 0] + 0.1) and (stripes[..., 2] > stripes[..., 0] + 0.2).any()


def test_a_translucent_domain_is_one_colour_on_every_face():
    """Translucent faces blend in row order: lit differently, a box's top over its back drew saw-teeth."""
    pytest.importorskip("plotly")
    from dhlb.cli.vortex import demo_velocity
    from dhlb.mesh import box_tet_mesh
    from dhlb.render import web as rw
    from dhlb.vortex import vortex_filaments

    mesh = box_tet_mesh(6, lower=-1.0, upper=1.0)
    res = vortex_filaments(mesh, None, demo_velocity("ring", mesh.points)[0], 1.0)
    domain = next(t for t in rw.figure_spec(res)["data"] if t["name"] == "domain")
    assert domain["opacity"] < 1
    light = domain["lighting"]
    assert light["diffuse"] == 0 and light["specular"] == 0 and light["fresnel"] == 0, light
