"""Guidance fields: the discrete Hopf differential (sphere, cylinder, ellipsoid umbilics), boundary, user data."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import scipy.sparse as sp

from dhlb.errors import InvalidParameterError, NonFiniteError, ShapeError
from dhlb.fields.directions import field_indices
from dhlb.fields.guidance import (
    boundary_guidance,
    curvature_guidance,
    dihedral_angles,
    hopf_differential,
    user_guidance,
)
from dhlb.mesh import tangent_bundle
from tests.surface_meshes import cylinder, ellipsoid, grid, icosphere

UMBILICS = np.array([[sx * 3 * np.sqrt(5 / 8), 0, sz * np.sqrt(3 / 8)] for sx in (1, -1) for sz in (1, -1)])


def test_hopf_differential_vanishes_on_the_sphere():
    means = []
    for level in (2, 3, 4):
        tb = tangent_bundle(*icosphere(level), n=2)
        q, _q_dual = hopf_differential(tb)
        assert np.abs(q).max() < 0.07  # H = 1; the 12 valence-5 vertices keep a small anisotropy
        means.append(np.abs(q).mean())
    assert means[0] < 0.025 and means[1] < means[0] / 2 and means[2] < means[1] / 2


def test_hopf_differential_on_a_cylinder():
    R = 1.5
    tb = tangent_bundle(*cylinder(40, 12, R=R, h=3.0), n=2)
    q, _ = hopf_differential(tb)
    inner = ~tb.is_boundary_vertex
    assert np.allclose(np.abs(q[inner]), 1 / (2 * R), rtol=2e-3)  # |κ1 − κ2| / 2
    P = tb.mesh.points
    around = np.stack([-P[:, 1], P[:, 0], 0 * P[:, 0]], 1) / R
    d_max = tb.angles_to_vectors(np.arange(len(q)), np.angle(q) / 2)
    d_min = tb.angles_to_vectors(np.arange(len(q)), np.angle(-q) / 2)
    assert np.all(np.abs(np.sum(d_max * around, 1))[inner] > 1 - 1e-9)  # maximal curvature: around
    assert np.all(np.abs(d_min[inner, 2]) > 1 - 1e-9)  # minimal curvature: along the axis
    beta = dihedral_angles(tb)
    assert beta.max() > 0 and beta.min() > -1e-12  # outward normals: convex edges are positive


@pytest.mark.parametrize("level", [3, 4])
def test_ellipsoid_has_four_umbilics(level):
    tb = tangent_bundle(*ellipsoid(level, (3.0, 2.0, 1.0)), n=2)
    g = curvature_guidance(tb)
    fi = field_indices(tb, g.values)
    s = fi.singularities
    assert fi.total == 4 and s.index.tolist() == [1, 1, 1, 1]
    dist = np.linalg.norm(s.points[:, None, :] - UMBILICS[None], axis=2)
    assert sorted(dist.argmin(axis=1).tolist()) == [0, 1, 2, 3]
    assert dist.min(axis=1).max() < 0.15
    # cross field q²: index 2 at each umbilic (Σ = 4 χ = 8), possibly split over nearby faces
    tb4 = tangent_bundle(tb.mesh, n=4)
    s4 = field_indices(tb4, curvature_guidance(tb4).values).singularities
    dist4 = np.linalg.norm(s4.points[:, None, :] - UMBILICS[None], axis=2)
    assert dist4.min(axis=1).max() < 0.2
    assert np.bincount(dist4.argmin(axis=1), weights=s4.index, minlength=4).tolist() == [2, 2, 2, 2]


def test_curvature_guidance_variants():
    tb = tangent_bundle(*ellipsoid(2), n=4)
    q, _q_dual = hopf_differential(tb)
    g = curvature_guidance(tb, "max")
    assert np.allclose(g.values, q**2) and g.kind == "curvature-max" and not g.empty
    assert np.allclose(curvature_guidance(tb, "min").values, q**2)  # (−q)² = q²
    lin = curvature_guidance(tb, magnitude="linear").values
    assert np.allclose(np.abs(lin), np.abs(q)) and np.allclose(lin * np.abs(q), q**2)
    tb2 = tangent_bundle(tb.mesh, n=2)
    assert np.allclose(curvature_guidance(tb2, "min").values, -q)
    M = sp.diags(tb.geometry.mass_matrix(lumped=True).diagonal())
    assert np.allclose(hopf_differential(tb, mass=M)[0], q)
    with pytest.raises(ShapeError):
        hopf_differential(tb, mass=sp.eye(3))
    with pytest.raises(InvalidParameterError, match="even n"):
        curvature_guidance(tangent_bundle(tb.mesh, n=3))
    with pytest.raises(InvalidParameterError):
        curvature_guidance(tb, "maximal")
    with pytest.raises(InvalidParameterError):
        curvature_guidance(tb, magnitude="cubic")


def test_flat_mesh_gives_empty_guidance_without_nan():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        tb = tangent_bundle(*grid(5, 4), n=4)
        g = curvature_guidance(tb)
    assert g.empty and "flat" in g.reason and np.all(g.values == 0)
    bump = tangent_bundle(*grid(6, 6, z=lambda x, y: np.exp(-((x - 3) ** 2 + (y - 3) ** 2))), n=2)
    gb = curvature_guidance(bump)
    assert not gb.empty and np.all(np.isfinite(gb.values))


@pytest.mark.parametrize("mesh", [grid(4, 3), cylinder(12, 3), grid(5, 4, z=lambda x, y: 0.2 * x * y)])
def test_boundary_guidance_bisects_the_boundary_angle(mesh):
    tb = tangent_bundle(*mesh, n=1)
    g = boundary_guidance(tb)
    b = tb.is_boundary_vertex
    # intrinsically: halfway between the outgoing edge (angle 0) and the incoming motion (angle Θ − π)
    assert np.allclose(np.angle(g.values[b]), (tb.angle_sums[b] - np.pi) / 2)
    assert np.allclose(np.angle(boundary_guidance(tb, normal=True).values[b]), tb.angle_sums[b] / 2)


@pytest.mark.parametrize("mesh", [grid(4, 3), cylinder(12, 3)])
def test_boundary_guidance_is_tangent_to_a_developable_boundary(mesh):
    tb = tangent_bundle(*mesh, n=1)
    g = boundary_guidance(tb)
    P = tb.mesh.points
    bd = tb.mesh.boundary_halfedges
    out_e = np.zeros_like(P)
    in_e = np.zeros_like(P)
    out_e[bd[:, 0]] = P[bd[:, 1]] - P[bd[:, 0]]
    in_e[bd[:, 1]] = P[bd[:, 1]] - P[bd[:, 0]]
    b = tb.is_boundary_vertex
    assert np.all(g.values[~b] == 0) and np.allclose(np.abs(g.values[b]), 1)
    out_e, in_e, nb = out_e[b], in_e[b], tb.normals[b]
    want = out_e / np.linalg.norm(out_e, axis=1, keepdims=True) + in_e / np.linalg.norm(in_e, axis=1, keepdims=True)
    want -= np.sum(want * nb, 1, keepdims=True) * nb
    want /= np.linalg.norm(want, axis=1, keepdims=True)
    d = tb.angles_to_vectors(np.nonzero(b)[0], np.angle(g.values[b]))
    assert np.allclose(d, want, atol=1e-9)
    dn = tb.angles_to_vectors(np.nonzero(b)[0], np.angle(boundary_guidance(tb, normal=True).values[b]))
    assert np.allclose(dn, np.cross(nb, want), atol=1e-9)  # inward: the surface is on the left
    g4 = boundary_guidance(tangent_bundle(tb.mesh, n=4))
    straight = b & np.isclose(tb.angle_sums, np.pi)          # smooth boundary: the 4th power of the tangent
    assert np.allclose(g4.values[straight], g.values[straight] ** 4)
    corner = b & np.isclose(tb.angle_sums, np.pi / 2)        # right-angle corners: aligned with both edges
    assert np.allclose(g4.values[corner], 1.0)


def test_boundary_guidance_on_closed_mesh_is_empty():
    g = boundary_guidance(tangent_bundle(*icosphere(1), n=2))
    assert g.empty and "no boundary" in g.reason


def test_user_guidance_vectors_and_values():
    V, F = grid(3, 3, z=lambda x, y: 0.1 * x * y)
    tb = tangent_bundle(V, F, n=1)
    rng = np.random.default_rng(1)
    theta = rng.uniform(-np.pi, np.pi, tb.mesh.n_vertices)
    vec = tb.angles_to_vectors(np.arange(tb.mesh.n_vertices), theta)
    g = user_guidance(tb, 2.0 * vec + 0.5 * tb.normals)
    assert np.allclose(g.values, 2 * np.exp(1j * theta))
    tb3 = tangent_bundle(tb.mesh, n=3)
    assert np.allclose(user_guidance(tb3, vec).values, np.exp(3j * theta))
    z = np.exp(1j * theta)
    assert np.array_equal(user_guidance(tb, z).values, z)
    assert user_guidance(tb, np.zeros((len(V), 3))).empty
    with pytest.raises(NonFiniteError, match="vertex 2"):
        user_guidance(tb, np.where(np.arange(len(V))[:, None] == 2, np.nan, vec))
    with pytest.raises(ShapeError):
        user_guidance(tb, np.zeros((len(V), 2)))
    with pytest.raises(ShapeError):
        user_guidance(tb, np.zeros(len(V) + 3, complex))
    with pytest.raises(NonFiniteError):
        user_guidance(tb, np.full(len(V), np.nan + 0j))


def test_user_guidance_uses_input_vertex_rows():
    V, F = grid(2, 2)
    V = np.vstack([V, [[7.0, 7.0, 7.0]]])  # an unused last row
    with pytest.warns(Warning):
        tb = tangent_bundle(V, F, n=1)
    W = np.tile([1.0, 0.0, 0.0], (len(V), 1))
    W[-1] = np.nan  # the dropped vertex is ignored
    g = user_guidance(tb, W)
    d = tb.angles_to_vectors(np.arange(tb.mesh.n_vertices), np.angle(g.values))
    assert np.allclose(d, [1, 0, 0])
