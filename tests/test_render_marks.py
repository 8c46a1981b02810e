"""What the pictures say (issue 29): n = 1 fields as arrows, one colour per kind of point, a colour
legend with a robust range on the distortion pictures."""

from __future__ import annotations

import numpy as np
import pytest

from dhlb.fields import direction_field
from dhlb.render import Camera, FieldStyle, render_field_png
from dhlb.render._figure import BRANCH, NEGATIVE, POSITIVE

PIL = pytest.importorskip("PIL.Image")


def _ink(path):
    return np.asarray(PIL.open(path).convert("L")) < 128


def test_an_n1_glyph_has_a_head_at_its_tip(tmp_path):
    V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 0]], float)
    F = np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]])
    D = np.zeros((5, 1, 3))
    D[4, 0] = (1, 0, 0)                                               # one arrow, at the centre, along +x
    path = render_field_png(tmp_path / "a.png", V, F, D, camera=Camera(view=(0, 0, 1), up=(0, 1, 0), size=(400, 400)),
                            style=FieldStyle(glyph_length=0.4, face_color=(1, 1, 1), ambient=1.0))
    ink = _ink(path)
    cols = np.nonzero(ink.any(axis=0))[0]
    base, tip = ink[:, cols[0]:cols[0] + 20].sum(), ink[:, cols[-1] - 20:cols[-1] + 1].sum()
    assert tip > 4 * base, (tip, base)                                # the head is at the +x end


def test_one_colour_per_kind_of_point_in_pictures_viewer_and_web():
    from dhlb.io import example_path, read_surface
    from dhlb.render.scene import index_colors, scene_of
    from dhlb.stripes import stripe_pattern

    assert index_colors([2, -1, 0]).tolist() == [list(POSITIVE), list(NEGATIVE), [0.5, 0.5, 0.5]]
    V, F = read_surface(example_path("spot.obj"))
    scene = scene_of(stripe_pattern(V, F, direction_field(V, F, n=2), spacing=6.0))   # the viewer's and the web's
    points = {p.name: p for p in scene.points}
    assert {tuple(c) for c in points["branch points"].colors} == {BRANCH}
    assert {tuple(c) for c in points["zeros"].colors} <= {POSITIVE, NEGATIVE}


def test_distortion_colours_have_a_legend_and_ignore_one_outlier(tmp_path):
    from dhlb.render.conformal_png import distortion_range, render_conformal_png

    d = np.r_[np.linspace(1.0, 1.2, 199), 2.9]
    assert distortion_range(d)[1] < 1.25                              # the outlier saturates, the rest is resolved
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]])
    F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    path = render_conformal_png(tmp_path / "c.png", V, 1.1 * V, F, np.array([1.0, 1.1, 1.2, 2.9]),
                                camera=Camera(size=(600, 300)))
    img = np.asarray(PIL.open(path).convert("L"))
    assert (img[-int(0.09 * img.shape[0]):] < 200).sum() > 200        # the colour bar and its labels


def test_the_conformal_colour_bar_label_is_inside_the_picture(tmp_path):
    """Issue 42, point 9: the label under the colour bar was cut off at the bottom of every conformal PNG."""
    from PIL import Image

    from dhlb.mesh import ball_tet_mesh
    from dhlb.render.conformal_png import render_conformal_png

    mesh = ball_tet_mesh(3)
    F = mesh.boundary_faces
    d = np.linspace(1.0, 1.3, len(F))
    path = render_conformal_png(tmp_path / "c.png", mesh.points, 1.1 * mesh.points, F, d, title="t")
    img = np.asarray(Image.open(path).convert("L"), dtype=float)
    ink = np.nonzero((img < 128).any(axis=1))[0]                   # rows with dark pixels (text, the surface)
    assert ink.max() < 0.975 * img.shape[0], "something is drawn against the bottom edge (a clipped label)"
