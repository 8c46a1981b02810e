"""Isolines α ≡ c: exact straight lines for plane waves, exact on plain and branch faces, ends only at zeros."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb.errors import InvalidParameterError, NonFiniteError
from dhlb.stripes import isolines, stripe_form, texture_coordinates
from dhlb.stripes.texture import _cones
from tests.test_stripes_texture import flat_grid, random_texture


@pytest.mark.parametrize("n", [1, 2])
@pytest.mark.parametrize("c", [1.0, 0.0, -2.5])
def test_plane_wave_isolines_are_the_lines_x_const(n, c):
    mesh = flat_grid(6, 5, 0.3, seed=2)
    rng = np.random.default_rng(4)
    sgn = rng.choice([-1.0, 1.0], mesh.n_vertices) if n == 2 else np.ones(mesh.n_vertices)
    f = 0.3
    nu = 2 * np.pi * f
    form = stripe_form(mesh, sgn[:, None] * [1.0, 0, 0], n, frequency=f)
    tex = texture_coordinates(form, np.exp(1j * sgn * nu * mesh.points[:, 0]))
    iso = isolines(tex, level=c)
    levels = [c] if n == 1 or c == 0 else [c, -c]
    want = np.sort([x for L in levels for k in range(-5, 6) if 0 < (x := (L + 2 * np.pi * k) / nu) < 6])
    assert len(iso.polylines) == want.size and not iso.closed.any()
    got = []
    for p in iso.polylines:
        pts = iso.points[p]
        assert np.ptp(pts[:, 0]) < 1e-9 and np.allclose(pts[:, 2], 0)
        assert np.isclose(pts[:, 1].min(), 0, atol=1e-9) and np.isclose(pts[:, 1].max(), 5, atol=1e-9)
        assert np.all(np.diff(pts[:, 1]) > 0) or np.all(np.diff(pts[:, 1]) < 0)  # ordered along the line
        got.append(pts[0, 0])
    assert np.allclose(np.sort(got), want, atol=1e-9)


def _open_ends(iso):
    return np.array([p[[0, -1]] for p, c in zip(iso.polylines, iso.closed) if not c], np.int64).reshape(-1)


@pytest.mark.parametrize("name", ["sphere", "torus"])
@settings(max_examples=10, deadline=None)
@given(seed=st.integers(0, 2**31), n=st.sampled_from([1, 2]), c=st.floats(-3.0, 3.0))
def test_isolines_on_closed_surfaces(name, seed, n, c):
    tex = random_texture(name, seed, n)
    iso = isolines(tex, level=c, refine=6)
    alpha = tex.evaluate(iso.faces, iso.bary)
    exact = ~np.isin(iso.faces, tex.zero_faces)  # plain faces and branch cones: α is linear
    if n == 1:
        assert np.allclose(np.exp(1j * alpha[exact]), np.exp(1j * c), atol=1e-9)
    else:
        assert np.allclose(np.cos(alpha[exact]), np.cos(c), atol=1e-9)
    for p, closed in zip(iso.polylines, iso.closed):
        assert len(p) >= 2 and (not closed or p[0] == p[-1])
        assert np.all(np.linalg.norm(np.diff(iso.points[p], axis=0), axis=1) > 0)
    # a closed surface: isolines end only at zeros, |n| of them per level (n = 1) or 2|n| (levels ±c), and
    # (non-generic) at branch points where cos β_m = cos c: there the folded isoline runs into the branch point
    ends = _open_ends(iso)
    zp = tex.zero_points
    fold = tex.branch_points[np.isclose(np.cos(tex.branch_alpha[:, 0]), np.cos(c), atol=1e-9)]
    if ends.size:
        d = np.linalg.norm(iso.points[ends][:, None] - zp[None], axis=2)
        df = np.linalg.norm(iso.points[ends][:, None] - fold[None], axis=2).min(axis=1, initial=np.inf)
        assert np.all((d.min(axis=1, initial=np.inf) < 1e-12) | (df < 1e-12))
        count = np.bincount(np.argmin(d, axis=1)[df >= 1e-12], minlength=len(zp))
    else:
        count = np.zeros(len(zp), np.int64)
    per_level = 1 if n == 1 or abs(np.sin(c)) < 1e-6 else 2  # line fields: ±c (snapped to one level near 0, π)
    assert np.array_equal(count, per_level * np.abs(tex.zero_index[tex.zero_faces]))


@settings(max_examples=8, deadline=None)
@given(seed=st.integers(0, 2**31), n=st.sampled_from([1, 2]))
def test_isolines_on_surfaces_with_boundary_end_at_zeros_or_on_the_boundary(seed, n):
    tex = random_texture("grid", seed, n)
    iso = isolines(tex, level=0.3)
    ends = _open_ends(iso)
    m = tex.mesh
    bnd = m.boundary_halfedges
    keys = set(map(tuple, np.sort(bnd, axis=1).tolist()))
    at_zero = np.min(np.linalg.norm(iso.points[ends][:, None] - tex.zero_points[None], axis=2), axis=1,
                     initial=np.inf) < 1e-12
    B = iso.bary[ends]
    F = m.faces[iso.faces[ends]]
    side = np.argmin(B, axis=1)  # the point lies on the side opposite the smallest coordinate
    on_side = B[np.arange(len(B)), side] < 1e-12
    edge = np.sort(np.stack([F[np.arange(len(F)), (side + 1) % 3], F[np.arange(len(F)), (side + 2) % 3]], 1), 1)
    on_boundary = on_side & np.array([tuple(e) in keys for e in edge.tolist()], bool)
    assert np.all(at_zero | on_boundary)


@settings(max_examples=6, deadline=None)
@given(seed=st.integers(0, 2**31), n=st.sampled_from([1, 2]))
def test_isolines_in_zero_faces_converge_quadratically(seed, n):
    tex = random_texture("torus", seed, n)
    errs = []
    for r in (8, 32):
        iso = isolines(tex, level=0.7, refine=r)
        alpha = tex.evaluate(iso.faces, iso.bary)
        z = np.isin(iso.faces, tex.zero_faces) & np.isfinite(alpha)
        rho = _cones(iso.bary)[4]
        e = np.abs(np.angle(np.exp(1j * (alpha - 0.7)))) if n == 1 else np.abs(np.cos(alpha) - np.cos(0.7))
        errs.append(np.max(e[z] * rho[z]))  # ∝ the distance to the true curve (|∇α| ~ 1/ρ near the zero)
    assert errs[0] < 0.2 and errs[1] < errs[0] / 8


def test_line_field_levels_are_symmetric():
    tex = random_texture("sphere", 11, 2)
    a, b = isolines(tex, level=0.9), isolines(tex, level=-0.9)
    pa = np.unique(np.round(a.points, 9), axis=0)
    pb = np.unique(np.round(b.points, 9), axis=0)
    assert a.level == b.level == 0.9 and pa.shape == pb.shape and np.allclose(pa, pb)


def test_bad_parameters():
    tex = random_texture("sphere", 1, 1)
    with pytest.raises(NonFiniteError):
        isolines(tex, level=np.nan)
    with pytest.raises(InvalidParameterError):
        isolines(tex, refine=0)
    with pytest.raises(InvalidParameterError):
        isolines(tex, tol=-1.0)
