"""The default camera (issue 29): upright (+y up, the OBJ/PLY/OFF convention), from above, framing the
whole model, the same rule for every renderer."""

from __future__ import annotations

import numpy as np
import pytest

from dhlb.errors import InvalidParameterError
from dhlb.io import example_path, read_surface
from dhlb.render import Camera
from dhlb.render._figure import up_vector


def test_spot_is_seen_upright_from_above_and_from_its_side():
    V, _ = read_surface(example_path("spot.obj"))
    cam = Camera().fitted(V)
    _, up, toward = cam.frame()
    assert np.allclose(up @ [0, 1, 0], np.cos(np.arcsin(toward[1])))   # the screen's up is the world's +y, tilted
    assert toward[1] > 0.4                                              # from above: no view of the belly
    ext = np.ptp(V, axis=0)
    thin = 0 if ext[0] < ext[2] else 2
    assert abs(toward[thin]) > abs(toward[2 - thin])                    # mostly across the thinner side


@pytest.mark.parametrize("up,axis", [("z", 2), ("-x", 0), ((0, 0, 3), 2)])
def test_up_may_be_chosen(up, axis):
    P = np.random.default_rng(0).normal(size=(50, 3))
    cam = Camera(up=up).fitted(P)
    _, screen_up, toward = cam.frame()
    u = up_vector(up)
    assert u[axis] != 0 and toward @ u > 0.5 and screen_up @ u > 0.5


def test_an_explicit_view_is_kept_and_bad_directions_are_named():
    assert Camera(view=(0, 0, 1)).fitted(np.eye(3)).view == (0, 0, 1)
    with pytest.raises(InvalidParameterError, match="up must be one of"):
        Camera(up="w")
    with pytest.raises(InvalidParameterError, match="up must be one of"):
        Camera(up=(0, 0, 0))
    with pytest.raises(InvalidParameterError, match="fitted"):
        Camera().frame()


def test_field_png_frames_the_whole_model(tmp_path):
    from PIL import Image  # matplotlib depends on pillow

    from dhlb.fields import direction_field
    from dhlb.render import render_field_png

    V, F = read_surface(example_path("spot.obj"))
    fld = direction_field(V, F, n=1)
    path = render_field_png(tmp_path / "spot.png", fld.mesh.points, fld.mesh.faces, fld.directions,
                            camera=Camera(size=(200, 200)))
    img = np.asarray(Image.open(path).convert("L"))
    ink = img < 250
    assert ink.mean() > 0.2                                             # the model fills the picture ...
    assert not (ink[0].any() or ink[-1].any() or ink[:, 0].any() or ink[:, -1].any())   # ... and is not clipped
    rows = np.nonzero(ink.any(axis=1))[0]
    assert rows[0] < 0.15 * img.shape[0] and rows[-1] > 0.85 * img.shape[0]          # centred, not a third empty


def test_the_back_view_walks_around_the_model_and_stays_above():
    V, _ = read_surface(example_path("spot.obj"))
    front = Camera().fitted(V)
    back = Camera().behind(V)
    f, b = np.array(front.view), np.array(back.view)
    assert np.isclose(f[1], b[1]) and b[1] > 0                            # the same height, still from above
    assert np.allclose(f[[0, 2]], -b[[0, 2]])                             # the other side


def test_the_viewer_looks_from_where_the_pictures_do():
    from dhlb.render.view import Scene, camera_for

    V, F = read_surface(example_path("spot.obj"))
    s = Scene()
    s.add_mesh("spot", V, F)
    position, target, up = camera_for(s)
    d = (position - target) / np.linalg.norm(position - target)
    lo, hi = V.min(axis=0), V.max(axis=0)
    fitted = np.array(Camera().fitted(np.vstack([lo, hi])).view)
    assert np.allclose(d, fitted / np.linalg.norm(fitted)) and np.allclose(up, [0, 1, 0])


@pytest.mark.parametrize("view", [None, (1.0, -1.6, 1.0), (0.0, 0.0, 1.0)])
def test_the_viewer_does_not_clip_a_box(view):
    # issue 29: the vortex box was clipped at the frame edges (the camera sat 2.4 half-diagonals away)
    from dhlb.render.view import FIELD_OF_VIEW, Scene, camera_for

    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)
    s = Scene()
    s.add_points("box", corners, (0, 0, 0))
    p, c, u = camera_for(s, view)
    f = (c - p) / np.linalg.norm(c - p)
    right = np.cross(f, u)
    right /= np.linalg.norm(right)
    screen_up = np.cross(right, f)
    t = np.tan(np.radians(FIELD_OF_VIEW / 2))
    depth = (corners - p) @ f
    x, y = (corners - p) @ right / (depth * t), (corners - p) @ screen_up / (depth * t)
    assert np.all(np.abs(x) < 1) and np.all(np.abs(y) < 1), (x, y)


def test_picture_sizes_are_checked_and_estimated_before_drawing():
    # issue 39: a picture size scales the work (about PNG_BYTES_PER_PIXEL bytes a pixel)
    from dhlb.errors import InvalidParameterError, ResourceLimitError
    from dhlb.linalg import set_memory_limit
    from dhlb.render import Camera

    for bad in ((0, 10), (100_000, 100_000), (800, 800.0), (800,), True, "800x800"):
        with pytest.raises(InvalidParameterError, match=r"Camera\.size"):
            Camera(size=bad)
    with pytest.raises(InvalidParameterError, match=r"Camera\.dpi"):
        Camera(dpi=0)
    set_memory_limit(200 * 2**20)
    try:
        with pytest.raises(ResourceLimitError, match="size") as err:
            Camera(size=(4000, 4000))            # 640 MB of picture against 200 MB
        assert "fits" in str(err.value)
        assert Camera(size=(800, 800)).size == (800, 800)
    finally:
        set_memory_limit(None)
