"""The PNG renderer writes valid pictures: shaded mesh, glyphs, singularity dots; bad input is typed."""

from __future__ import annotations

import numpy as np
import pytest

from dhlb.errors import InvalidParameterError, InvalidSimplexError, NonFiniteError, ShapeError
from dhlb.fields.directions import direction_vectors, field_indices
from dhlb.fields.guidance import curvature_guidance
from dhlb.mesh import tangent_bundle
from dhlb.render import Camera
from tests.surface_meshes import ellipsoid, grid, icosphere

mpimg = pytest.importorskip("matplotlib.image")
PNG = b"\x89PNG\r\n\x1a\n"


def _read(path):
    with open(path, "rb") as fh:
        assert fh.read(8) == PNG
    return mpimg.imread(path)


def test_render_ellipsoid_with_umbilics(tmp_path):
    tb = tangent_bundle(*ellipsoid(3), n=2)
    u = curvature_guidance(tb).values
    fi = field_indices(tb, u)
    path = tmp_path / "ellipsoid.png"
    out = tb.mesh.points, tb.mesh.faces
    assert render(path, *out, directions=direction_vectors(tb, u), singularities=fi.singularities,
                  camera=Camera(view=(0, -0.3, 1), up=(0, 1, 0), size=(400, 300))) == str(path)
    img = _read(path)
    assert img.shape[:2] == (300, 400)
    rgb = img[..., :3]
    assert np.all(rgb[0, 0] == 1)  # white background
    centre = rgb[150, 200]
    assert np.all(centre < 0.95) and np.ptp(centre) < 0.2  # grey shaded surface
    red = (rgb[..., 0] > 0.7) & (rgb[..., 1] < 0.3) & (rgb[..., 2] < 0.3)
    assert red.sum() > 20  # the two umbilics facing the camera (index +1: red)
    dark = rgb.max(axis=2) < 0.25
    assert dark.sum() > 200  # glyphs


def test_back_faces_and_hidden_dots_are_culled(tmp_path):
    V, F = icosphere(2)
    back = (np.array([[0.0, 0.0, -1.0]]), np.array([-1]))  # behind the sphere, seen from +z
    front = (np.array([[0.0, 0.0, 1.0]]), np.array([-1]))
    p1, p2 = tmp_path / "back.png", tmp_path / "front.png"
    render(p1, V, F, singularities=back, camera=Camera(view=(0, 0, 1), up=(0, 1, 0), size=(200, 200)))
    render(p2, V, F, singularities=front, camera=Camera(view=(0, 0, 1), up=(0, 1, 0), size=(200, 200)))

    def blue(p):
        rgb = _read(p)[..., :3]
        return ((rgb[..., 2] > 0.6) & (rgb[..., 0] < 0.3)).sum()

    assert blue(p1) == 0 and blue(p2) > 20


def test_open_mesh_shows_both_sides(tmp_path):
    V, F = grid(4, 4, z=lambda x, y: 0.2 * np.sin(x))
    p = tmp_path / "grid.png"
    render(p, V, F, camera=Camera(view=(0.2, 0.3, -1.0), size=(120, 120)))  # seen from below
    rgb = _read(p)[..., :3]
    assert (rgb.max(axis=2) < 0.99).sum() > 2000


def test_render_rejects_bad_input(tmp_path):
    V, F = icosphere(0)
    p = tmp_path / "x.png"
    D = np.zeros((len(V), 1, 3))
    D[2, 0, 1] = np.nan
    with pytest.raises(NonFiniteError, match="vertex 2"):
        render(p, V, F, directions=D)
    with pytest.raises(ShapeError):
        render(p, V, F, directions=np.zeros((3, 3)))
    with pytest.raises(InvalidSimplexError):
        render(p, V, F + 1)
    with pytest.raises(InvalidParameterError):
        render(p, V, F, camera=Camera(view=(0, 0, 0)))
    with pytest.raises(ShapeError):
        render(p, V, F, singularities=(np.zeros((2, 3)), np.ones(3)))
    V2 = V.copy()
    V2[0, 0] = np.inf
    with pytest.raises(NonFiniteError):
        render(p, V2, F)
    assert not p.exists()


def render(*args, **kwargs):
    from dhlb.render import render_field_png

    return render_field_png(*args, **kwargs)
