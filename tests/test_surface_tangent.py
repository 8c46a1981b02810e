"""The discrete tangent bundle: rescaled angles, transport, curvature (Gauss–Bonnet, holonomy), invariance."""

from __future__ import annotations

import os

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb.io import example_path, read_surface
from dhlb.mesh import tangent_bundle, validate_surface
from tests.surface_meshes import cylinder, grid, icosphere, torus

DATA = os.path.join(os.path.dirname(__file__), "data")
CLOSED = {
    "icosphere": lambda: icosphere(2),
    "torus-grid": lambda: torus(20, 9),
    "torus.obj": lambda: read_surface(example_path("torus.obj")),
    "double-torus": lambda: read_surface(os.path.join(DATA, "double-torus.obj")),
    "3holes": lambda: read_surface(os.path.join(DATA, "3holes.off")),
    "fertility": lambda: read_surface(os.path.join(DATA, "fertility.off")),
    "rounded-cube": lambda: read_surface(os.path.join(DATA, "rounded_cube.obj")),
}
CHI = {"icosphere": 2, "torus-grid": 0, "torus.obj": 0, "double-torus": -2, "3holes": -4, "fertility": -6,
       "rounded-cube": 2}


def half_edge_angle(tb, v, w):
    """Rescaled angle at v of the edge v → w, from ``edge_angles``."""
    v, w = np.asarray(v), np.asarray(w)
    N = tb.mesh.n_vertices
    E = tb.mesh.complex.simplices(1)
    e = np.searchsorted(E[:, 0] * N + E[:, 1], np.minimum(v, w) * N + np.maximum(v, w))
    return np.where(v < w, tb.edge_angles[e, 0], tb.edge_angles[e, 1])


def half_edge_transport(tb, v, w):
    N = tb.mesh.n_vertices
    E = tb.mesh.complex.simplices(1)
    e = np.searchsorted(E[:, 0] * N + E[:, 1], np.minimum(v, w) * N + np.maximum(v, w))
    r = tb.bundle.connection[e]
    return np.where(v < w, r, np.conj(r))


def wrapped(x):
    return np.angle(np.exp(1j * np.asarray(x)))


@pytest.mark.parametrize("name", sorted(CLOSED))
@pytest.mark.parametrize("n", [1, 2, 4])
def test_gauss_bonnet_closed(name, n):
    tb = tangent_bundle(*CLOSED[name](), n=n)
    chi = tb.mesh.euler_characteristic
    assert chi == CHI[name]
    deg = tb.mesh.triangle_sign @ tb.curvature / (2 * np.pi)
    assert abs(deg - n * chi) < 1e-9 * max(1, abs(tb.curvature).sum())
    assert abs(tb.total_curvature - 2 * np.pi * n * chi) < 1e-8
    assert tb.total_boundary_turning == 0
    # the bundle's degree is computed with X.orientation(), which may be opposite to the mesh's
    sign = int(tb.mesh.complex.orientation()[0] * tb.mesh.triangle_sign[0])
    assert tb.bundle.degree() == sign * n * chi


@pytest.mark.parametrize("name", ["icosphere", "double-torus", "rounded-cube"])
def test_holonomy_is_exp_of_curvature(name):
    n = 3
    tb = tangent_bundle(*CLOSED[name](), n=n)
    F = tb.mesh.faces
    a, b, c = F[:, 0], F[:, 1], F[:, 2]
    hol = half_edge_transport(tb, a, b) * half_edge_transport(tb, b, c) * half_edge_transport(tb, c, a)
    assert np.abs(hol - np.exp(1j * n * tb.face_curvature)).max() < 1e-9
    # canonical triangles: exp(iΩ) = r_ij r_jk r_ki (the convention of docs/conventions.md)
    T = tb.mesh.complex.simplices(2)
    i, j, k = T[:, 0], T[:, 1], T[:, 2]
    hol_t = half_edge_transport(tb, i, j) * half_edge_transport(tb, j, k) * half_edge_transport(tb, k, i)
    assert np.abs(hol_t - np.exp(1j * tb.curvature)).max() < 1e-9


def test_n_smooth_curvature_is_principal_holonomy_angle():
    tb = tangent_bundle(*icosphere(2), n=4)
    assert np.abs(tb.face_curvature).max() < np.pi / 4  # n-smooth
    assert np.allclose(tb.curvature, tb.bundle.holonomy_angles(), atol=1e-12)
    tb = tangent_bundle(*icosphere(0), n=8)  # icosahedron: σ = 4π/20 > π/8, not 8-smooth
    assert not np.allclose(tb.curvature, tb.bundle.holonomy_angles())
    assert np.allclose(wrapped(tb.curvature - tb.bundle.holonomy_angles()), 0, atol=1e-12)


def test_geometric_curvature_of_the_icosahedron():
    tb = tangent_bundle(*icosphere(0), n=1)
    # 12 vertices with angle defect π/3 = 2π - 5π/3, pushed into 20 faces: σ = 12 (π/3) / 20 each
    assert np.allclose(tb.face_curvature, 12 * (np.pi / 3) / 20)
    assert np.allclose(tb.scale, 2 * np.pi / (5 * np.pi / 3))


@pytest.mark.parametrize("mesh", [grid(4, 3), cylinder(16, 4), grid(5, 5, z=lambda x, y: 0.3 * np.sin(x) * np.cos(y)),
                                  torus(12, 6)])
@pytest.mark.parametrize("n", [1, 4])
def test_gauss_bonnet_with_boundary(mesh, n):
    tb = tangent_bundle(*mesh, n=n)
    chi = tb.mesh.euler_characteristic
    assert abs(tb.total_curvature + tb.total_boundary_turning - 2 * np.pi * n * chi) < 1e-9
    assert np.all(tb.scale[tb.is_boundary_vertex] == 1)
    inner = ~tb.is_boundary_vertex
    assert np.allclose(tb.scale[inner] * tb.angle_sums[inner], 2 * np.pi)


def test_flat_grid_has_zero_curvature_and_right_angle_turns():
    tb = tangent_bundle(*grid(4, 3), n=1)
    assert np.allclose(tb.face_curvature, 0, atol=1e-14)
    turn = tb.boundary_turning[tb.is_boundary_vertex]
    assert np.isclose(np.sort(turn)[-4:], np.pi / 2).all() and np.allclose(np.sort(turn)[:-4], 0, atol=1e-14)


@pytest.mark.parametrize("mesh", [icosphere(1), grid(3, 3, z=lambda x, y: 0.2 * x * y), cylinder(10, 3)])
def test_rescaled_edge_angles_step_by_corner_angles(mesh):
    tb = tangent_bundle(*mesh)
    F = tb.mesh.faces
    for p in range(3):
        v, a, b = F[:, p], F[:, (p + 1) % 3], F[:, (p + 2) % 3]
        step = half_edge_angle(tb, v, b) - half_edge_angle(tb, v, a)
        assert np.allclose(wrapped(step - tb.scale[v] * tb.corner_angles[:, p]), 0, atol=1e-12)
    # reference edges have angle 0; at boundary vertices the fan spans [0, Θ] without wrapping
    N = np.arange(tb.mesh.n_vertices)
    assert np.allclose(half_edge_angle(tb, N, tb.reference_neighbors), 0)
    bd = tb.mesh.boundary_halfedges
    assert np.allclose(half_edge_angle(tb, bd[:, 0], bd[:, 1]), 0)  # outgoing boundary edge
    assert np.allclose(half_edge_angle(tb, bd[:, 1], bd[:, 0]), tb.angle_sums[bd[:, 1]])  # incoming


def test_transport_formula():
    tb = tangent_bundle(*icosphere(1), n=2)
    E = tb.mesh.complex.simplices(1)
    rho = 2 * (half_edge_angle(tb, E[:, 1], E[:, 0]) + np.pi - half_edge_angle(tb, E[:, 0], E[:, 1]))
    assert np.allclose(np.exp(1j * rho), tb.bundle.connection)


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 6))
def test_relabeling_is_a_gauge_transformation(seed, n):
    rng = np.random.default_rng(seed)
    V, F = icosphere(1)
    V = V * rng.uniform(0.7, 1.3, size=(len(V), 1))
    tb = tangent_bundle(V, F, n=n)
    p = rng.permutation(len(V))  # new label of old vertex v is p[v]
    fperm = rng.permutation(len(F))
    F2 = np.roll(p[F], rng.integers(0, 3), axis=1)[fperm]
    V2 = np.empty_like(V)
    V2[p] = V
    tb2 = tangent_bundle(V2, F2, n=n)
    assert np.allclose(tb2.face_curvature[np.argsort(fperm)], tb.face_curvature)
    # new frame of old vertex v: its reference edge v -> w has old rescaled angle φ_v
    inv = np.argsort(p)
    ref_old = inv[tb2.reference_neighbors[p]]
    g = np.exp(1j * n * half_edge_angle(tb, np.arange(len(V)), ref_old))
    E = tb.mesh.complex.simplices(1)
    r2 = half_edge_transport(tb2, p[E[:, 0]], p[E[:, 1]])
    assert np.allclose(r2, np.conj(g[E[:, 1]]) * tb.bundle.connection * g[E[:, 0]])
    assert tb2.bundle.is_isomorphic(tb2.bundle.gauge(np.exp(1j * rng.uniform(0, 7, len(V)))))


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 5))
def test_gauss_bonnet_random_embeddings(seed, n):
    rng = np.random.default_rng(seed)
    V, F = torus(10, 6)
    V = V + rng.normal(scale=0.08, size=V.shape)
    tb = tangent_bundle(V, F, n=n)
    assert abs(tb.total_curvature) < 1e-9
    sphere = icosphere(1)
    tb = tangent_bundle(sphere[0] * rng.uniform(0.5, 1.5, (len(sphere[0]), 3)), sphere[1], n=n)
    assert abs(tb.total_curvature - 4 * np.pi * n) < 1e-9


def test_curvature_density_integrates_to_total_curvature():
    tb = tangent_bundle(*icosphere(2), n=2)
    assert np.isclose(tb.curvature_density @ tb.geometry.volumes(2), tb.total_curvature)
    # density n σ_t / area_t: on a closed sphere mesh its area-weighted mean is 2 n·2π / area exactly
    area = tb.geometry.volumes(2)
    assert np.isclose(np.average(tb.curvature_density, weights=area), 2 * 4 * np.pi / area.sum())


def test_frames_and_normals():
    tb = tangent_bundle(*icosphere(2))
    T = tb.frames
    assert np.allclose(np.einsum("vij,vkj->vik", T, T), np.eye(3))
    assert np.allclose(np.linalg.det(T), 1)
    assert np.all(np.sum(tb.normals * tb.mesh.points, axis=1) > 0.99)  # outward on the unit sphere
    X = tb.reference_vectors
    assert np.allclose(np.sum(X * T[:, 1], 1), 0) and np.all(np.sum(X * T[:, 0], 1) > 0)


@pytest.mark.parametrize("mesh", [icosphere(2), grid(4, 4, z=lambda x, y: 0.3 * np.sin(x + y)), cylinder(12, 3)])
def test_angle_map_is_exact_on_edges_and_invertible(mesh):
    tb = tangent_bundle(*mesh)
    assert not tb.angle_map.fallback.any()
    F = tb.mesh.faces
    v, w = F.ravel(), np.roll(F, -1, axis=1).ravel()
    d = tb.mesh.points[w] - tb.mesh.points[v]
    N = tb.normals[v]
    proj = d - np.sum(d * N, 1, keepdims=True) * N
    proj /= np.linalg.norm(proj, axis=1, keepdims=True)
    assert np.allclose(tb.angles_to_vectors(v, half_edge_angle(tb, v, w)), proj, atol=1e-12)
    rng = np.random.default_rng(0)
    theta = rng.uniform(0, 2 * np.pi, tb.mesh.n_vertices)
    vec = tb.angles_to_vectors(np.arange(tb.mesh.n_vertices), theta)
    assert np.allclose(np.linalg.norm(vec, axis=1), 1) and np.allclose(np.sum(vec * tb.normals, 1), 0)
    back, length = tb.vectors_to_angles(3 * vec + 2 * tb.normals)
    assert np.allclose(wrapped(back - theta), 0, atol=1e-12) and np.allclose(length, 3)


def test_flat_interior_vertex_angles_are_euclidean():
    tb = tangent_bundle(*grid(2, 2))
    v = 4  # the centre vertex (1, 1)
    X = tb.reference_vectors[v]
    Y = np.cross([0, 0, 1.0], X)
    th = np.linspace(0, 6, 7)
    assert np.allclose(tb.angles_to_vectors(np.full(7, v), th), np.cos(th)[:, None] * X + np.sin(th)[:, None] * Y)


def test_geometry_matches_mesh():
    V, F = icosphere(1)
    tb = tangent_bundle(V, F)
    P = tb.mesh.points
    area = 0.5 * np.linalg.norm(np.cross(P[F[:, 1]] - P[F[:, 0]], P[F[:, 2]] - P[F[:, 0]]), axis=1).sum()
    assert np.isclose(tb.geometry.volumes(2).sum(), area)
    assert tb.bundle.X is tb.mesh.complex and tb.geometry.complex is tb.mesh.complex
    m = validate_surface(V, F)
    assert repr(tangent_bundle(m, n=2)).startswith("TangentBundle(n=2")


def test_fans_refuse_a_vertex_with_two_fans():
    from dhlb.errors import NonManifoldError
    from dhlb.mesh.halfedge import vertex_fans

    _V, F = icosphere(0)
    F2 = np.where(F == 0, 0, F + 11)  # a second icosahedron sharing vertex 0 (a double cone there)
    FF = np.vstack([F, F2[:, ::-1]])
    with pytest.raises(NonManifoldError, match="vertex 0"):
        vertex_fans(FF, 23, np.ones(FF.shape))


@pytest.mark.parametrize("n", [2.5, "3", True, 0])
def test_a_tangent_bundle_is_not_silently_given_another_n(n):
    # issue 27's audit: energy_matrices(tb, n=2.5) truncated n to 2
    from dhlb.errors import InvalidParameterError
    from dhlb.fields import energy_matrices
    from dhlb.mesh import tangent_bundle

    tb = tangent_bundle([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0.3]], [[0, 1, 2], [1, 3, 2]], n=4)
    with pytest.raises(InvalidParameterError, match="n"):
        energy_matrices(tb, n=n)
