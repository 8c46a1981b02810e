"""OBJ + JSON sidecar of stripe patterns (round trip, documented rules reproduce α) and the PNG renderer."""

from __future__ import annotations

import json

import numpy as np
import pytest

from dhlb.errors import InvalidParameterError
from dhlb.io import read_surface
from dhlb.io.stripes import write_stripes_obj
from dhlb.render import Camera, StripeStyle
from dhlb.stripes import stripe_form, texture_coordinates
from tests.test_stripes_texture import flat_grid, random_texture


def parse_obj(path):
    V, U, F = [], [], []
    with open(path) as fh:
        for line in fh:
            w = line.split()
            if not w or w[0] == "#":
                continue
            if w[0] == "v":
                V.append([float(x) for x in w[1:4]])
            elif w[0] == "vt":
                U.append(float(w[1]))
            elif w[0] == "f":
                F.append([[int(y) - 1 for y in x.split("/")] for x in w[1:]])
    F = np.array(F)
    return np.array(V), np.array(U), F[:, :, 0], F[:, :, 1]


def printed_larg(n, t):
    ti, tj, tk = t.T
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.select([(tk <= ti) & (tk <= tj), (ti <= tj) & (ti <= tk)],
                         [np.pi * n / 3 * (1 + (tj - ti) / (1 - 3 * tk)),
                          np.pi * n / 3 * (3 + (tk - tj) / (1 - 3 * ti))],
                         np.pi * n / 3 * (5 + (ti - tk) / (1 - 3 * tj)))


@pytest.mark.parametrize("n", [1, 2])
def test_obj_and_sidecar_reproduce_the_pattern(tmp_path, n):
    tex = random_texture("sphere", 5, n)
    assert tex.zero_faces.size and (n == 1 or tex.branch_faces.size)
    obj, side = write_stripes_obj(tmp_path / "p.obj", tex)
    assert side == str(tmp_path / "p.json")
    V, U, F, T = parse_obj(obj)
    m = tex.mesh
    assert np.array_equal(V, m.points) and np.array_equal(F, m.faces)
    assert np.array_equal(T, np.arange(3 * m.n_faces).reshape(-1, 3))
    assert np.array_equal(U, (tex.corner_alpha / (2 * np.pi)).ravel())  # %.17g round-trips exactly
    V2, F2 = read_surface(obj)
    assert np.array_equal(V2, m.points) and np.array_equal(F2, m.faces)
    meta = json.load(open(side))
    assert meta["n"] == n and meta["n_faces"] == m.n_faces and meta["expanded"] == 0
    # rebuild α at random points from the files alone, following the documented rules
    rng = np.random.default_rng(0)
    faces = np.repeat(np.arange(m.n_faces), 5)
    t = rng.dirichlet(np.ones(3), faces.size)
    u = np.einsum("kc,kc->k", t, U[T[faces]])
    zero = dict(zip(meta["zeros"]["faces"], meta["zeros"]["index"]))
    nz = np.array([zero.get(f, 0) for f in faces])
    u = u + printed_larg(nz, t) / (2 * np.pi)
    br = {f: (a, b) for f, a, b in zip(meta["branch"]["faces"], meta["branch"]["u_m"], meta["branch"]["u_l"])}
    for r in np.nonzero([f in br for f in faces])[0]:
        um, ul = br[faces[r]]
        cu = list(U[T[faces[r]]]) + [ul]
        lo = [2, 0, 1][int(np.argmin(t[r][[2, 0, 1]]))]  # which cone: (m,i,j), (m,j,k), (m,k,i)
        c = (lo + 1) % 3
        u[r] = 3 * t[r, lo] * um + (t[r, c] - t[r, lo]) * cu[c] + (t[r, (c + 1) % 3] - t[r, lo]) * cu[c + 1]
    assert np.allclose(2 * np.pi * u, tex.evaluate(faces, t), atol=1e-12)
    assert np.allclose(np.array(meta["zeros"]["points"]).reshape(-1, 3), tex.zero_points)


def test_expanded_obj_needs_only_linear_uvs(tmp_path):
    tex = random_texture("sphere", 5, 2)
    r = 6
    obj, side = write_stripes_obj(tmp_path / "e.obj", tex, expand=r)
    V, U, F, T = parse_obj(obj)
    meta = json.load(open(side))
    m = tex.mesh
    face_of = np.array(meta["obj_face_of"])
    plain = (~tex.is_branch) & (tex.zero_index == 0)
    assert len(F) == plain.sum() + 3 * tex.branch_faces.size + 6 * r * r * tex.zero_faces.size
    assert np.array_equal(np.bincount(face_of, minlength=m.n_faces),
                          np.where(plain, 1, np.where(tex.is_branch, 3, 6 * r * r)))
    assert np.array_equal(V[:m.n_vertices], m.points)
    # sub-triangle centroids: linear UV interpolation against the exact evaluation
    cen = V[F].mean(axis=1)
    P = m.points[m.faces[face_of]]
    A = np.stack([P[:, 0] - P[:, 2], P[:, 1] - P[:, 2]], axis=2)
    AtA = np.einsum("kdi,kdj->kij", A, A)
    st = np.linalg.solve(AtA, np.einsum("kdi,kd->ki", A, cen - P[:, 2])[..., None])[..., 0]
    bary = np.column_stack([st, 1 - st.sum(axis=1)])
    exact = tex.evaluate(face_of, np.clip(bary, 0, None) / np.clip(bary, 0, None).sum(1, keepdims=True))
    lin = 2 * np.pi * U[T].mean(axis=1)
    z = np.isin(face_of, tex.zero_faces)
    assert np.allclose(np.cos(lin[~z]), np.cos(exact[~z]), atol=1e-9)
    assert np.max(np.abs(np.cos(lin[z]) - np.cos(exact[z]))) < 0.5  # zero faces: piecewise-linear approximation


def test_bad_expand():
    tex = random_texture("sphere", 1, 1)
    for bad in (-1, 1.5, True):
        with pytest.raises(InvalidParameterError):
            write_stripes_obj("unused.obj", tex, expand=bad)


# ---------------------------------------------------------------------- PNG
mpimg = pytest.importorskip("matplotlib.image")


def test_png_of_a_plane_wave_shows_the_stripes(tmp_path):
    from dhlb.render.stripes_png import render_stripes_png

    mesh = flat_grid(6, 6, 0.3, seed=1)
    f = 0.25
    form = stripe_form(mesh, np.tile([1.0, 0, 0], (mesh.n_vertices, 1)), frequency=f)
    tex = texture_coordinates(form, np.exp(2j * np.pi * f * mesh.points[:, 0]))
    W = 300
    path = render_stripes_png(tmp_path / "s.png", tex, k=12, camera=Camera(view=(0, 0, 1), up=(0, 1, 0), size=(W, W)))
    img = mpimg.imread(path)[..., :3]
    assert img.shape == (W, W, 3)
    half = 0.53 * 6  # the renderer's framing: centre 3, half-width 0.53 × extent
    x = np.linspace(0.3, 5.7, 60)
    cols = np.round((x - (3 - half)) / (2 * half) * W).astype(int)
    lum = img[W // 2, cols].mean(axis=1)
    want = (1 + np.cos(2 * np.pi * f * x)) / 2
    assert np.corrcoef(lum, want)[0, 1] > 0.98
    assert np.ptp(img[W // 4:3 * W // 4, cols].mean(axis=2), axis=0).max() < 0.12  # constant along y (k = 12 steps)


def test_png_marks_zeros_and_branch_points(tmp_path):
    from dhlb.render.stripes_png import render_stripes_png

    tex = random_texture("sphere", 2, 2)
    path = render_stripes_png(tmp_path / "b.png", tex, camera=Camera(size=(240, 200)),
                              style=StripeStyle(mark_singularities=True))
    img = mpimg.imread(path)[..., :3]
    assert img.shape == (200, 240, 3) and np.all(img[0, 0] == 1)
    green = (img[..., 1] > 0.5) & (img[..., 0] < 0.3) & (img[..., 2] < 0.4)
    assert green.sum() > 10
    with pytest.raises(InvalidParameterError):
        render_stripes_png(tmp_path / "x.png", tex, k=0)
