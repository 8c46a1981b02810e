"""The stripe 1-form ω̂, the signs s_ij, branch triangles and the double-cover bundles (seed part 2, §3)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb.errors import (
    DhlbWarning,
    InvalidConnectionError,
    InvalidParameterError,
    NonFiniteError,
    SectionZeroError,
    ShapeError,
    UnreferencedVertexWarning,
)
from dhlb.fields import direction_vectors, field_indices
from dhlb.fields.guidance import curvature_guidance
from dhlb.mesh import tangent_bundle, validate_surface
from dhlb.stripes import stripe_form
from tests.surface_meshes import ellipsoid, grid, icosphere, torus


def flat_square(nx=6, ny=5, jitter=0.0, seed=0):
    V, F = grid(nx, ny)
    rng = np.random.default_rng(seed)
    inner = (V[:, 0] > 0) & (V[:, 0] < nx) & (V[:, 1] > 0) & (V[:, 1] < ny)
    V[inner, :2] += jitter * rng.uniform(-1, 1, (inner.sum(), 2))
    return validate_surface(V, F)


def rotation(a):
    return np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])


# ---------------------------------------------------------------------- the 1-form
@pytest.mark.parametrize("n", [1, 2])
def test_constant_field_on_flat_mesh_integrates_exactly(n):
    mesh = flat_square(jitter=0.3, seed=n)
    rng = np.random.default_rng(7)
    sgn = rng.choice([-1.0, 1.0], mesh.n_vertices) if n == 2 else np.ones(mesh.n_vertices)
    X = sgn[:, None] * np.array([1.0, 0, 0])
    f = 0.13
    for method in ("intrinsic", "extrinsic"):
        form = stripe_form(mesh, 2.5 * X, n, frequency=f, method=method)  # the length of X is irrelevant
        E = mesh.complex.simplices(1)
        dx = mesh.points[E[:, 1], 0] - mesh.points[E[:, 0], 0]
        assert np.allclose(form.omega, 2 * np.pi * f * sgn[E[:, 0]] * dx, atol=1e-12, rtol=0)
        assert np.array_equal(form.edge_sign, (sgn[E[:, 0]] * sgn[E[:, 1]]).astype(np.int64))
        assert not form.is_branch.any()
        assert np.allclose(form.directions, X, atol=1e-12)


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.sampled_from([1, 2]))
def test_intrinsic_equals_extrinsic_on_flat_meshes(seed, n):
    mesh = flat_square(5, 4, jitter=0.35, seed=seed)
    rng = np.random.default_rng(seed)
    X = rng.normal(size=(mesh.n_vertices, 3))  # the normal part is dropped
    nu = rng.uniform(0.05, 0.3, mesh.n_vertices)
    a = stripe_form(mesh, X, n, frequency=nu)
    b = stripe_form(mesh, X, n, frequency=nu, method="extrinsic")
    assert np.allclose(a.omega, b.omega, atol=1e-12)
    assert np.array_equal(a.edge_sign, b.edge_sign)


def test_spacing_is_relative_to_the_mean_edge_length():
    mesh = validate_surface(*torus(12, 6))
    E = mesh.complex.simplices(1)
    mean_edge = np.mean(np.linalg.norm(mesh.points[E[:, 1]] - mesh.points[E[:, 0]], axis=1))
    X = np.cross(mesh.points, [0, 0, 1.0])
    form = stripe_form(mesh, X, spacing=6.0)
    assert np.allclose(form.frequency, 1 / (6 * mean_edge)) and np.allclose(form.nu, 2 * np.pi / (6 * mean_edge))
    assert np.max(np.abs(form.omega)) <= 2 * np.pi / 6 * np.max(np.linalg.norm(
        mesh.points[E[:, 1]] - mesh.points[E[:, 0]], axis=1)) / mean_edge + 1e-12


def test_vector_field_has_all_signs_positive():
    mesh = validate_surface(*icosphere(1))
    rng = np.random.default_rng(1)
    form = stripe_form(mesh, rng.normal(size=(mesh.n_vertices, 3)), 1, frequency=0.5)
    assert np.all(form.edge_sign == 1) and not form.is_branch.any()
    L = form.line_bundle
    assert np.allclose(np.angle(L.connection), np.angle(np.exp(1j * form.omega)))


# ---------------------------------------------------------------------- branch triangles
@pytest.mark.parametrize("name", ["sphere", "torus"])
@settings(max_examples=8, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_branch_triangles_are_the_half_integer_singularities(name, seed):
    V, F = icosphere(2) if name == "sphere" else torus(14, 7)
    tb2 = tangent_bundle(V, F, n=2)
    rng = np.random.default_rng(seed)
    u = rng.normal(size=tb2.mesh.n_vertices) + 1j * rng.normal(size=tb2.mesh.n_vertices)
    form = stripe_form(tb2, direction_vectors(tb2, u), 2, frequency=rng.uniform(0.1, 2.0), warn_aliasing=False)
    odd = field_indices(tb2, u).face_index % 2 != 0
    assert odd.any()
    assert np.array_equal(form.is_branch, odd)
    assert form.is_branch.sum() % 2 == 0  # Σ index = 2χ is even: half-integer singularities come in pairs


def test_umbilics_of_an_ellipsoid_are_branch_points():
    tb2 = tangent_bundle(*ellipsoid(3), n=2)
    u = curvature_guidance(tb2).values
    form = stripe_form(tb2, direction_vectors(tb2, u), 2, spacing=3.0)
    fi = field_indices(tb2, u)
    assert np.array_equal(form.is_branch, fi.face_index % 2 != 0)
    assert form.is_branch.sum() == 4  # the four umbilics, index +1/2 each


# ---------------------------------------------------------------------- the real rank-2 bundle and the double cover
def _random_form(seed, n, name="sphere"):
    V, F = {"sphere": icosphere(1), "torus": torus(10, 5), "grid": grid(5, 4, z=lambda x, y: 0.2 * x * y)}[name]
    mesh = validate_surface(V, F)
    rng = np.random.default_rng(seed)
    return stripe_form(mesh, rng.normal(size=(mesh.n_vertices, 3)), n, frequency=rng.uniform(0.2, 2, mesh.n_vertices),
                       warn_aliasing=False), rng


@pytest.mark.parametrize("n", [1, 2])
@settings(max_examples=10, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_holonomy_is_a_reflection_exactly_on_branch_triangles(seed, n):
    form, _ = _random_form(seed, n)
    H = form.bundle.triangle_monodromy()
    mesh = form.mesh
    det = np.linalg.det(H)[mesh.triangle_of_face]
    assert np.allclose(det, np.where(form.is_branch, -1.0, 1.0))
    assert np.allclose(np.einsum("tij,tkj->tik", H, H), np.eye(2), atol=1e-12)  # orthogonal
    circ = form.lift_halfedges(form.omega).sum(axis=1)  # ∮ ω̃ around the lifted face
    reg = ~form.is_branch
    assert np.allclose(np.einsum("tii->t", H)[mesh.triangle_of_face][reg], 2 * np.cos(circ[reg]), atol=1e-10)
    if n == 1:  # canonical triangles: the holonomy is the rotation by dω̂
        dw = mesh.complex.coboundary(1) @ form.omega
        assert np.allclose(H, np.stack([rotation(a) for a in dw]), atol=1e-10)


@pytest.mark.parametrize("name", ["sphere", "torus", "grid"])
@settings(max_examples=10, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_double_cover_energy_is_twice_the_real_bundle_energy(name, seed):
    form, rng = _random_form(seed, 2, name)
    N = form.mesh.n_vertices
    psi = rng.normal(size=N) + 1j * rng.normal(size=N)
    E = form.mesh.complex.simplices(1)
    w = rng.uniform(0.1, 2.0, len(E))
    v = np.column_stack([psi.real, psi.imag])
    moved = np.einsum("eij,ej->ei", form.bundle.transports, v[E[:, 0]])
    e_real = np.sum(w * np.sum((v[E[:, 1]] - moved) ** 2, axis=1))
    dc = form.double_cover
    Et = dc.complex.simplices(1)
    base = np.sort(Et % N, axis=1)
    wt = w[np.searchsorted(E[:, 0] * N + E[:, 1], base[:, 0] * N + base[:, 1])]
    z = dc.lift(psi)
    e_cover = np.sum(wt * np.abs(z[Et[:, 1]] - dc.bundle.connection * z[Et[:, 0]]) ** 2)
    assert np.isclose(e_cover, 2 * e_real, rtol=1e-12)
    # conjugate-symmetric functions = the real subspace P x; Hermitian forms restrict to real symmetric ones
    x = np.column_stack([psi.real, psi.imag]).ravel()
    P = dc.embedding()
    assert np.allclose(P @ x, z)
    H = sp.random(2 * N, 2 * N, density=0.05, random_state=seed % 2**32) * (1 + 1j)
    H = H + H.conj().T
    R = dc.restrict(H)
    assert R.dtype == np.float64 and abs(R - R.T).max() < 1e-14
    assert np.isclose(x @ (R @ x), np.real(np.conj(z) @ (H @ z)))
    assert np.array_equal(dc.points, np.concatenate([form.mesh.points, form.mesh.points]))
    assert dc.complex.counts == (2 * N, 2 * len(E), 2 * int((~form.is_branch).sum()))
    # lifts of regular faces are triangles of the cover; branch faces close up on the other sheet
    lifts = dc.face_lifts
    reg = ~form.is_branch
    assert np.all(dc.complex.contains(2, lifts[reg])) and not np.any(dc.complex.contains(2, lifts[~reg]))


def test_line_bundle_needs_consistent_orientation():
    form, _ = _random_form(3, 2)
    assert (form.edge_sign < 0).any()
    with pytest.raises(InvalidConnectionError, match="edge"):
        _ = form.line_bundle


# ---------------------------------------------------------------------- bad input
def test_bad_directions_name_the_vertex():
    V, F = grid(3, 3)
    V = np.vstack([[9.0, 9, 9], V])  # row 0 unused: errors name input rows of V
    with pytest.warns(UnreferencedVertexWarning):
        mesh = validate_surface(V, F + 1)
    X = np.tile([1.0, 0, 0], (len(V), 1))
    X0 = X.copy()
    X0[5] = 0
    with pytest.raises(SectionZeroError, match="vertex 5 is zero"):
        stripe_form(mesh, X0, frequency=1)
    X0 = X.copy()
    X0[6] = [0, 0, 2.0]
    with pytest.raises(SectionZeroError, match="vertex 6 is normal to the surface"):
        stripe_form(mesh, X0, 2, frequency=1)
    X0 = X.copy()
    X0[7, 1] = np.nan
    with pytest.raises(NonFiniteError, match="vertex 7"):
        stripe_form(mesh, X0, frequency=1)
    with pytest.raises(ShapeError):
        stripe_form(mesh, X[:5], frequency=1)
    with pytest.raises(ShapeError):
        stripe_form(mesh, X[:, :2], frequency=1)


def test_bad_frequencies_name_the_vertex():
    mesh = validate_surface(*grid(3, 3))
    X = np.tile([1.0, 0, 0], (mesh.n_vertices, 1))
    for bad in (0.0, -1.0):
        with pytest.raises(InvalidParameterError, match="positive"):
            stripe_form(mesh, X, frequency=bad)
    with pytest.raises(NonFiniteError):
        stripe_form(mesh, X, frequency=np.nan)
    nu = np.ones(mesh.n_vertices)
    nu[4] = -2
    with pytest.raises(InvalidParameterError, match="vertex 4"):
        stripe_form(mesh, X, frequency=nu)
    nu[4] = np.inf
    with pytest.raises(NonFiniteError, match="vertex 4"):
        stripe_form(mesh, X, spacing=nu)
    with pytest.raises(ShapeError):
        stripe_form(mesh, X, frequency=np.ones(3))
    with pytest.raises(InvalidParameterError, match="exactly one"):
        stripe_form(mesh, X, frequency=1, spacing=2)
    with pytest.raises(InvalidParameterError, match="exactly one"):
        stripe_form(mesh, X)
    with pytest.raises(InvalidParameterError, match="'a'"):
        stripe_form(mesh, X, frequency="a")
    for n in (0, 3, 4, 1.0, True):
        with pytest.raises(InvalidParameterError, match="n must be"):
            stripe_form(mesh, X, n, frequency=1)
    with pytest.raises(InvalidParameterError, match="method"):
        stripe_form(mesh, X, frequency=1, method="cotan")
    with pytest.raises(InvalidParameterError, match="stripe_form needs the face array F"):
        stripe_form((mesh.points, mesh.faces), X, frequency=1)


def test_aliasing_warns_and_names_an_edge():
    mesh = validate_surface(*grid(4, 4))
    X = np.tile([1.0, 0, 0], (mesh.n_vertices, 1))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        stripe_form(mesh, X, frequency=0.45)  # |ω| = 0.9π on the longest x-steps
    with pytest.warns(DhlbWarning, match=r"narrower than the mesh resolves on \d+ edge\(s\).*edge \(\d+, \d+\)"):
        form = stripe_form(mesh, X, frequency=1.7)
    assert np.max(np.abs(form.omega)) > np.pi
