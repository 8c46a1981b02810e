"""Sections to 3D directions; indices, Poincaré–Hopf with and without boundary; singularity positions."""

from __future__ import annotations

import os

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb.errors import NonFiniteError, SectionZeroError, ShapeError
from dhlb.fields.directions import direction_vectors, field_indices
from dhlb.fields.guidance import user_guidance
from dhlb.io import read_surface
from dhlb.mesh import tangent_bundle
from tests.surface_meshes import cylinder, grid, icosphere, torus

DATA = os.path.join(os.path.dirname(__file__), "data")
MESHES = {
    "sphere": icosphere(1),
    "torus": torus(12, 6),
    "double-torus": read_surface(os.path.join(DATA, "double-torus.obj")),
    "grid": grid(4, 4, z=lambda x, y: 0.3 * np.sin(x) * np.cos(y)),
    "cylinder": cylinder(12, 3),
}


def wrapped(x):
    return np.angle(np.exp(1j * np.asarray(x)))


@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_directions_are_unit_tangent_and_n_symmetric(n):
    tb = tangent_bundle(*icosphere(2), n=n)
    rng = np.random.default_rng(n)
    u = rng.normal(size=tb.mesh.n_vertices) + 1j * rng.normal(size=tb.mesh.n_vertices)
    u[5] = 0
    D = direction_vectors(tb, u)
    assert D.shape == (tb.mesh.n_vertices, n, 3)
    assert np.all(D[5] == 0)
    ok = np.arange(tb.mesh.n_vertices) != 5
    assert np.allclose(np.linalg.norm(D[ok], axis=2), 1)
    assert np.allclose(np.einsum("vkd,vd->vk", D, tb.normals), 0)
    for k in range(n):
        theta, _ = tb.vectors_to_angles(D[:, k])
        assert np.allclose(wrapped(n * theta[ok] - np.angle(u[ok])), 0, atol=1e-9)  # each one is an n-th root
        assert np.allclose(wrapped(theta[ok] - np.angle(u[ok]) / n - 2 * np.pi * k / n), 0, atol=1e-9)


@pytest.mark.parametrize("name", ["sphere", "torus", "double-torus"])
@settings(max_examples=10, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 6))
def test_poincare_hopf_closed(name, seed, n):
    tb = tangent_bundle(*MESHES[name], n=n)
    rng = np.random.default_rng(seed)
    u = np.exp(1j * rng.uniform(-np.pi, np.pi, tb.mesh.n_vertices)) * rng.uniform(0.1, 2, tb.mesh.n_vertices)
    fi = field_indices(tb, u)
    chi = tb.mesh.euler_characteristic
    assert fi.total == n * chi and fi.face_index.sum() == n * chi
    assert fi.boundary_rotation == 0 and abs(fi.poincare_hopf - n * chi) < 1e-9
    assert np.array_equal(fi.singularities.index, fi.face_index[fi.singularities.faces])
    assert np.all(fi.singularities.index != 0) and np.count_nonzero(fi.face_index) == len(fi.singularities.faces)


@pytest.mark.parametrize("name", ["grid", "cylinder"])
@settings(max_examples=10, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 5))
def test_poincare_hopf_with_boundary(name, seed, n):
    tb = tangent_bundle(*MESHES[name], n=n)
    rng = np.random.default_rng(seed)
    u = np.exp(1j * rng.uniform(-np.pi, np.pi, tb.mesh.n_vertices))
    fi = field_indices(tb, u)
    assert abs(fi.poincare_hopf - fi.total) < 1e-9
    assert np.isclose(fi.total_curvature, tb.total_curvature)


def test_radial_field_on_a_disk():
    V, F = grid(6, 6)
    V = V - [3.3, 2.8, 0.0]  # the centre lies inside a face, not at a vertex
    tb = tangent_bundle(V, F, n=1)
    u = user_guidance(tb, V).values  # the radial vector field x ∂x + y ∂y: index +1 at the origin
    fi = field_indices(tb, u)
    s = fi.singularities
    assert fi.total == 1 and s.index.tolist() == [1]
    assert np.isclose(fi.boundary_rotation, 2 * np.pi) and np.isclose(fi.total_curvature, 0, atol=1e-12)
    face = tb.mesh.points[tb.mesh.faces[s.faces[0]]]
    assert np.allclose(s.barycentric.sum(1), 1) and np.all(s.barycentric >= 0)
    assert np.allclose(s.points[0], s.barycentric[0] @ face)
    assert np.linalg.norm(s.points[0]) < 1e-12  # the linear field vanishes exactly at the origin
    assert s.input_faces[0] == tb.mesh.face_rows[s.faces[0]]
    # the same field as a line field (n = 2) has index 2 there (angles double: near the zero the
    # discrete index may spread over neighbouring faces, as +1s and a ±1 pair)
    tb2 = tangent_bundle(tb.mesh, n=2)
    fi2 = field_indices(tb2, user_guidance(tb2, V).values)
    assert fi2.total == 2 and np.linalg.norm(fi2.singularities.points, axis=1).max() < 1.5


def test_vortex_of_index_minus_one():
    V, F = grid(6, 6)
    V = V - [3.3, 2.8, 0.0]
    tb = tangent_bundle(V, F, n=1)
    W = np.stack([V[:, 0], -V[:, 1], 0 * V[:, 0]], 1)  # the saddle field x ∂x − y ∂y
    fi = field_indices(tb, user_guidance(tb, W).values)
    assert fi.total == -1 and fi.singularities.index.tolist() == [-1]
    assert np.linalg.norm(fi.singularities.points[0]) < 1e-12


def test_reoriented_faces_report_indices_in_the_mesh_orientation():
    V, F = icosphere(1)
    F = F.copy()
    F[[0, 7]] = F[[0, 7]][:, ::-1]
    tb = tangent_bundle(V, F, n=2, reorient=True)
    u = np.exp(1j * np.arange(tb.mesh.n_vertices) * 0.7)
    assert field_indices(tb, u).total == 4


def test_bad_sections():
    tb = tangent_bundle(*icosphere(0), n=2)
    u = np.ones(12, complex)
    u[3] = 0
    with pytest.raises(SectionZeroError, match="vertex 3"):
        field_indices(tb, u)
    u[3] = np.nan
    with pytest.raises(NonFiniteError, match="vertex 3"):
        field_indices(tb, u)
    with pytest.raises(NonFiniteError):
        direction_vectors(tb, u)
    with pytest.raises(ShapeError):
        direction_vectors(tb, np.ones((12, 2)))
    with pytest.raises(ShapeError):
        direction_vectors(tb, np.ones(5))


def test_singularity_positions_do_not_depend_on_the_corner_order():
    from dhlb.fields import direction_field
    from dhlb.io import example_path, read_surface

    V, F = read_surface(example_path("spot.obj"))
    a = direction_field(V, F, n=1)
    for k in (1, 2):
        b = direction_field(V, np.roll(F, k, axis=1), n=1)
        assert np.array_equal(a.singularities.input_faces, b.singularities.input_faces)
        assert np.allclose(a.singularities.points, b.singularities.points, atol=1e-12)
