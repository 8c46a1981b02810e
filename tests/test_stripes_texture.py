"""Texture coordinates from synthetic sections: exactness, continuity, zeros, branch points (seed part 2, §4.3)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb.bundles import index_form
from dhlb.errors import DhlbWarning, InvalidParameterError, NonFiniteError, SectionZeroError, ShapeError
from dhlb.mesh import validate_surface
from dhlb.stripes import larg, stripe_form, texture_coordinates
from dhlb.topology.complex import SimplicialComplex
from tests.surface_meshes import cylinder, grid, icosphere, torus


def jittered(name, seed):
    rng = np.random.default_rng(seed)
    if name == "sphere":
        V, F = icosphere(1)
        V = V * rng.uniform(0.8, 1.2, (len(V), 1))
    elif name == "torus":
        V, F = torus(10, 5)
        V = V + 0.08 * rng.normal(size=V.shape)
    elif name == "cylinder":
        V, F = cylinder(10, 3)
        V = V + 0.05 * rng.normal(size=V.shape)
    else:
        V, F = grid(5, 4, z=lambda x, y: 0.3 * np.sin(x) * np.cos(y))
        V[:, :2] += 0.25 * rng.uniform(-1, 1, (len(V), 2))
    return validate_surface(V, F)


def random_texture(name, seed, n):
    mesh = jittered(name, seed)
    rng = np.random.default_rng(seed + 1)
    form = stripe_form(mesh, rng.normal(size=(mesh.n_vertices, 3)), n,
                       frequency=rng.uniform(0.05, 3.0) * rng.uniform(0.5, 1.5, mesh.n_vertices), warn_aliasing=False)
    psi = rng.normal(size=mesh.n_vertices) + 1j * rng.normal(size=mesh.n_vertices)
    return texture_coordinates(form, psi)


def twin_sides(mesh):
    """(a, b): side a = (face, corner c → c+1) and its twin side b in the neighbouring face (interior edges)."""
    F = mesh.faces
    h = np.stack([F, np.roll(F, -1, 1)], -1).reshape(-1, 2)
    N = mesh.n_vertices
    key = h[:, 0] * N + h[:, 1]
    order = np.argsort(key)
    tw = h[:, 1] * N + h[:, 0]
    pos = np.minimum(np.searchsorted(key[order], tw), len(key) - 1)
    a = np.nonzero(key[order][pos] == tw)[0]
    return a, order[pos][a]


def side_points(sides, t):
    """Barycentric points at parameter t along sides (3 f + c), from corner c toward c+1."""
    c = sides % 3
    B = np.zeros((sides.size, 3))
    B[np.arange(sides.size), c] = 1 - t
    B[np.arange(sides.size), (c + 1) % 3] = t
    return sides // 3, B


def flat_grid(nx, ny, jitter, seed):
    V, F = grid(nx, ny)
    rng = np.random.default_rng(seed)
    inner = (V[:, 0] > 0) & (V[:, 0] < nx) & (V[:, 1] > 0) & (V[:, 1] < ny)
    V[inner, :2] += jitter * rng.uniform(-1, 1, (inner.sum(), 2))
    return validate_surface(V, F)


def random_bary(rng, k):
    return rng.dirichlet(np.ones(3), size=k)


# ---------------------------------------------------------------------- exact answers
@pytest.mark.parametrize("n", [1, 2])
@pytest.mark.parametrize("f", [0.07, 0.3, 2.7])  # the last: a period of 0.37 edge lengths (aliasing)
def test_plane_wave_is_linear_with_the_prescribed_spacing(n, f):
    mesh = flat_grid(6, 5, 0.3, seed=int(10 * f))
    rng = np.random.default_rng(3)
    sgn = rng.choice([-1.0, 1.0], mesh.n_vertices) if n == 2 else np.ones(mesh.n_vertices)
    X = sgn[:, None] * np.array([1.0, 0, 0])
    with warnings.catch_warnings():
        warnings.simplefilter("error" if f < 0.5 else "ignore", DhlbWarning)
        form = stripe_form(mesh, X, n, frequency=f)
    nu = 2 * np.pi * f
    psi = np.exp(1j * sgn * nu * mesh.points[:, 0])  # the stored value: the sheet of X_i
    tex = texture_coordinates(form, psi)
    assert tex.zero_faces.size == 0 and tex.branch_faces.size == 0
    faces = np.repeat(np.arange(mesh.n_faces), 7)
    B = random_bary(rng, faces.size)
    x = np.einsum("kc,kc->k", B, mesh.points[mesh.faces[faces], 0])
    alpha = tex.evaluate(faces, B)
    # per face α = νx + 2πk (sheet +1) or, for line fields, α = −νx + 2πk (sheet −1)
    sheet = np.where(form.corner_sheet[:, 0] * sgn[mesh.faces[:, 0]] > 0, 1.0, -1.0)[faces]
    assert n == 2 or np.all(sheet == 1)
    k = (alpha - sheet * nu * x) / (2 * np.pi)
    assert np.allclose(k, np.round(k), atol=1e-10, rtol=0)
    assert np.all(np.round(k).reshape(-1, 7) == np.round(k).reshape(-1, 7)[:, :1])  # one k per face: linear
    assert np.allclose(np.cos(alpha), np.cos(nu * x), atol=1e-10, rtol=0)  # spacing 2π/ν = 1/f


def test_zero_of_z_minus_z0_is_found_in_its_face():
    mesh = flat_grid(6, 6, 0.2, seed=5)
    z0 = 2.37 + 3.61j
    psi = mesh.points[:, 0] + 1j * mesh.points[:, 1] - z0
    form = stripe_form(mesh, np.tile([1.0, 0, 0], (mesh.n_vertices, 1)), frequency=1e-4)
    tex = texture_coordinates(form, psi)
    assert tex.zero_faces.size == 1 and tex.zero_index[tex.zero_faces[0]] == 1
    P = mesh.points[mesh.faces[tex.zero_faces[0]], :2]
    lam = np.linalg.solve(np.vstack([P.T, np.ones(3)]), [z0.real, z0.imag, 1.0])
    assert np.all(lam > 0)  # the face that contains z0
    bar = texture_coordinates(form, np.conj(psi))
    assert bar.zero_index[tex.zero_faces[0]] == -1


def test_larg_matches_the_printed_formula():
    rng = np.random.default_rng(0)
    t = random_bary(rng, 2000)
    n = rng.integers(-3, 4, len(t))
    ti, tj, tk = t.T
    printed = np.select(
        [(tk <= ti) & (tk <= tj), (ti <= tj) & (ti <= tk)],
        [np.pi * n / 3 * (1 + (tj - ti) / (1 - 3 * tk)), np.pi * n / 3 * (3 + (tk - tj) / (1 - 3 * ti))],
        np.pi * n / 3 * (5 + (ti - tk) / (1 - 3 * tj)))
    assert np.allclose(larg(n, t), printed, atol=1e-12, rtol=0)
    s = np.linspace(0, 1, 11)[:, None]  # linear on the boundary
    for a, b, v0 in ((0, 1, 0), (1, 2, 2), (2, 0, 4)):
        pts = (1 - s) * np.eye(3)[a] + s * np.eye(3)[b]
        want = np.pi / 3 * (v0 + 2 * s.ravel())
        assert np.allclose(larg(1, pts)[:-1], want[:-1], atol=1e-12)
        assert np.isclose(np.exp(1j * larg(1, pts)[-1]), np.exp(1j * want[-1]))  # 2π = 0 at the cut
    assert np.isnan(larg(2, [[1 / 3, 1 / 3, 1 / 3]])[0]) and larg(0, [[1 / 3, 1 / 3, 1 / 3]])[0] == 0


# ---------------------------------------------------------------------- continuity (App. B)
@pytest.mark.parametrize("name", ["sphere", "torus", "cylinder", "grid"])
@settings(max_examples=12, deadline=None)
@given(seed=st.integers(0, 2**31), n=st.sampled_from([1, 2]),
       ts=st.lists(st.floats(0, 1), min_size=1, max_size=4))
def test_pattern_is_continuous_across_every_edge(name, seed, n, ts):
    tex = random_texture(name, seed, n)
    assert tex.winding_defect < 1e-9
    a, b = twin_sides(tex.mesh)
    for t in list(ts) + [0.0, 1.0]:
        fa, Ba = side_points(a, t)
        fb, Bb = side_points(b, 1 - t)
        va, vb = tex.evaluate(fa, Ba), tex.evaluate(fb, Bb)
        assert np.allclose(np.cos(va), np.cos(vb), atol=1e-9, rtol=0)
        if n == 1:
            assert np.allclose(np.exp(1j * va), np.exp(1j * vb), atol=1e-9, rtol=0)


@pytest.mark.parametrize("name", ["sphere", "torus", "grid"])
@settings(max_examples=8, deadline=None)
@given(seed=st.integers(0, 2**31))
def test_zero_index_is_the_index_form_of_the_stripe_bundle(name, seed):
    tex = random_texture(name, seed, 1)
    m = tex.mesh
    ind = index_form(tex.form.line_bundle, tex.psi)
    assert np.array_equal(tex.zero_index, m.face_sign * ind[m.triangle_of_face])
    tex2 = random_texture(name, seed, 2)  # line fields: the index on the sheet-1 lift in the double cover
    dc = tex2.form.double_cover
    reg = ~tex2.is_branch
    lifts = dc.face_lifts[reg]
    ind2 = index_form(dc.bundle, dc.lift(tex2.psi))[dc.complex.index(2, lifts)]
    assert np.array_equal(tex2.zero_index[reg], SimplicialComplex.orientation_of(lifts) * ind2)
    if m.is_closed and name == "sphere":
        assert tex.zero_index.sum() == 0  # a trivial bundle (Ω = dω̂ exact): Σ index = 0


@settings(max_examples=10, deadline=None)
@given(seed=st.integers(0, 2**31), n=st.sampled_from([1, 2]), r=st.sampled_from([0.003, 0.2, 0.6, 1.0]))
def test_zero_faces_wind_n_times_and_are_continuous_off_the_zero(seed, n, r):
    tex = random_texture("torus", seed, n)
    zf = tex.zero_faces
    assert zf.size
    m = np.full(3, 1 / 3)
    s = np.linspace(0, 1, 400, endpoint=False)[:, None]
    loop = np.concatenate([(1 - s) * np.eye(3)[c] + s * np.eye(3)[(c + 1) % 3] for c in range(3)])
    loop = m + r * (loop - m)  # homothetic copy of the face boundary around the barycenter, mesh orientation
    vals = tex.evaluate(np.repeat(zf, len(loop)), np.tile(loop, (zf.size, 1))).reshape(zf.size, -1)
    steps = np.angle(np.exp(1j * np.diff(np.column_stack([vals, vals[:, :1]]), axis=1)))
    assert np.allclose(steps.sum(axis=1) / (2 * np.pi), tex.zero_index[zf], atol=1e-9)
    assert np.max(np.abs(steps)) < 0.35  # no jumps along the loop
    # across the cone boundaries (the rays m → corner, including lArg's cut) from both sides
    eps = 1e-9
    for c in range(3):
        ray = m + np.linspace(0.05, 1.0, 7)[:, None] * (np.eye(3)[c] - m)
        off = eps * (np.eye(3)[(c + 1) % 3] - np.eye(3)[(c + 2) % 3])
        p, q = np.clip(ray + off, 0, None), np.clip(ray - off, 0, None)
        p, q = p / p.sum(1, keepdims=True), q / q.sum(1, keepdims=True)
        fz = np.repeat(zf, len(ray))
        vp, vq = tex.evaluate(fz, np.tile(p, (zf.size, 1))), tex.evaluate(fz, np.tile(q, (zf.size, 1)))
        assert np.allclose(np.cos(vp), np.cos(vq), atol=1e-6)
        assert n == 2 or np.allclose(np.sin(vp), np.sin(vq), atol=1e-6)


@settings(max_examples=10, deadline=None)
@given(seed=st.integers(0, 2**31))
def test_branch_faces_are_continuous_through_their_cones(seed):
    tex = random_texture("sphere", seed, 2)
    bf = tex.branch_faces
    assert bf.size
    beta_m, beta_l = tex.branch_alpha.T
    assert np.allclose(np.sin(beta_m), 0, atol=1e-12)  # β_m ≡ 0 mod π
    assert np.allclose(np.cos(beta_l), np.cos(tex.corner_alpha[bf, 0]), atol=1e-12)  # β_l ≡ −β_i
    m = np.full(3, 1 / 3)
    eps = 1e-10
    for c in range(3):
        ray = m + np.linspace(0.0, 1.0, 9)[:, None] * (np.eye(3)[c] - m)
        off = eps * (np.eye(3)[(c + 1) % 3] - np.eye(3)[(c + 2) % 3])
        p, q = np.clip(ray + off, 0, None), np.clip(ray - off, 0, None)
        p, q = p / p.sum(1, keepdims=True), q / q.sum(1, keepdims=True)
        fb = np.repeat(bf, len(ray))
        vp, vq = tex.evaluate(fb, np.tile(p, (bf.size, 1))), tex.evaluate(fb, np.tile(q, (bf.size, 1)))
        assert np.allclose(np.cos(vp), np.cos(vq), atol=1e-7)
    centre = tex.evaluate(bf, np.tile(m, (bf.size, 1)))
    assert np.allclose(centre, beta_m)


# ---------------------------------------------------------------------- bad input
def test_bad_sections_name_the_vertex():
    V, F = grid(3, 3)
    V = np.vstack([[9.0, 9, 9], V])
    with pytest.warns(Warning):
        mesh = validate_surface(V, F + 1)
    form = stripe_form(mesh, np.tile([1.0, 0, 0], (len(V), 1)), frequency=0.1)
    psi = np.exp(1j * np.arange(len(V)))
    bad = psi.copy()
    bad[6] = 0
    with pytest.raises(SectionZeroError, match="vertex 6"):
        texture_coordinates(form, bad)
    bad[6] = np.nan
    with pytest.raises(NonFiniteError, match="vertex 6"):
        texture_coordinates(form, bad)
    with pytest.raises(ShapeError):
        texture_coordinates(form, psi[:4])
    with pytest.raises(ShapeError):
        texture_coordinates(form, np.stack([psi.real, psi.imag], 1))
    tex = texture_coordinates(form, psi)
    with pytest.raises(InvalidParameterError, match="face 99"):
        tex.evaluate([99], [[1, 0, 0]])
    with pytest.raises(InvalidParameterError, match="point 1"):
        tex.evaluate([0, 0], [[1, 0, 0], [0.5, 0.6, -0.1]])
    with pytest.raises(InvalidParameterError, match="sum to 1"):
        tex.evaluate(0, [[0.5, 0.6, 0.0]])
    with pytest.raises(NonFiniteError):
        tex.evaluate(0, [[np.nan, 0.5, 0.5]])
    with pytest.raises(ShapeError):
        tex.evaluate(0, [[0.5, 0.5]])
    with pytest.raises(ShapeError):
        tex.evaluate([0.5], [[1, 0, 0]])
    with pytest.raises(ShapeError, match="one per point"):
        tex.evaluate([0, 1], [[1, 0, 0]] * 3)
    with pytest.raises(InvalidParameterError):
        tex.subdivision(0)


def test_spinning_rotation_is_the_rotation_form_tie_rule_bit_for_bit():
    """The texture's ``ω − δ̂`` (δ̂ ∈ [−π, π)) equals ``ω + ξ`` with ξ from bundles._sections.rotation_angles."""
    from dhlb.stripes.texture import _spinning_rotation

    rng = np.random.default_rng(7)
    m = 20_000
    omega = rng.uniform(-4, 4, m)
    psi_i = rng.normal(size=m) + 1j * rng.normal(size=m)
    psi_j = rng.normal(size=m) + 1j * rng.normal(size=m)
    k = m // 4
    psi_j[:k] = -np.exp(1j * omega[:k]) * psi_i[:k]                       # ties δ̂ = ±π up to rounding
    omega[k:2 * k] = 0.0
    psi_j[k:2 * k] = -psi_i[k:2 * k] * rng.integers(1, 4, k)              # exact ties
    omega[2 * k:2 * k + 100] = np.pi
    delta = np.angle(np.exp(1j * omega) * psi_i * np.conj(psi_j))
    assert np.count_nonzero(delta == np.pi) > 100                         # the tie rule is exercised
    old = omega - np.where(delta >= np.pi, -np.pi, delta)                 # the former inline rule
    new = omega + _spinning_rotation(omega, psi_i, psi_j)
    assert np.array_equal(old, new)
