"""Filament extraction on synthetic sections with known zero sets (independent of the FEM engine)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb import SimplicialComplex
from dhlb.bundles import HermitianLineBundle
from dhlb.errors import (
    DhlbWarning,
    InconsistentOrientationError,
    InvalidParameterError,
    NonFiniteError,
    NonManifoldError,
    SectionZeroError,
    ShapeError,
)
from dhlb.mesh import box_tet_mesh
from dhlb.vortex import extract_filaments, face_zeros, hausdorff_distance, hopf_link, linking_number, vortex_ring

BOX = box_tet_mesh(5)
TRIVIAL = HermitianLineBundle.trivial(BOX.complex)


def line_section(P, x0, y0):
    """ψ = (x − x0) + i(y − y0): zero set the vertical line, winding +1 about +z."""
    return (P[:, 0] - x0) + 1j * (P[:, 1] - y0)


def ring_section(P, center, axis, R):
    """ψ = (ρ − R) − i h: zero set the circle of radius R about ``axis`` (unit), oriented like vortex_ring."""
    d = P - center
    h = d @ axis
    rho = np.linalg.norm(d - h[:, None] * axis, axis=1)
    return (rho - R) - 1j * h


def random_bundle(X, rng, scale):
    w = rng.uniform(-scale, scale, X.n_simplices(1))
    f = X.faces(2)
    return HermitianLineBundle(X, np.exp(1j * w), w[f[:, 2]] - w[f[:, 1]] + w[f[:, 0]])


# ---------------------------------------------------------------------------- exact zero sets
@settings(max_examples=20, deadline=None)
@given(st.floats(0.02, 0.98), st.floats(0.02, 0.98), st.booleans())
def test_vertical_line_is_recovered_exactly(x0, y0, reverse):
    psi = line_section(BOX.points, x0, y0)
    if reverse:
        psi = np.conj(psi)  # winding −1: the same line, oriented downwards
    res = extract_filaments(TRIVIAL, psi, BOX.points)
    assert len(res) == 1 and not res[0].closed
    f = res[0]
    assert np.allclose(f.points[:, :2], [x0, y0], rtol=0, atol=1e-12)  # the interpolant is exact
    dz = np.diff(f.points[:, 2])
    assert np.all(dz <= 1e-15) if reverse else np.all(dz >= -1e-15)
    ends = f.points[[0, -1], 2]
    assert np.allclose(ends, [1.0, 0.0] if reverse else [0.0, 1.0], atol=1e-15)
    assert f.length == pytest.approx(1.0, abs=1e-12)
    assert res.ambiguous_tets.size == 0 and res.clamped_faces.size == 0  # (ties happen when the line meets an edge)


def test_line_through_mesh_edges_is_a_tie_and_still_exact():
    res = extract_filaments(TRIVIAL, line_section(BOX.points, 0.33, 0.4), BOX.points)  # y0 = 0.4 is a grid plane
    assert res.tie_edges.size > 0 and len(res) == 1
    assert np.allclose(res[0].points[:, :2], [0.33, 0.4], atol=1e-12)


def test_ring_is_recovered_to_second_order():
    c = np.array([0.013, 0.007, 0.011])
    errs = []
    for m in (8, 16):
        mesh = box_tet_mesh(m, lower=-1.5, upper=1.5)
        psi = ring_section(mesh.points, c, np.array([0, 0, 1.0]), 1.0)
        res = extract_filaments(HermitianLineBundle.trivial(mesh.complex), psi, mesh.points)
        assert len(res) == 1 and res[0].closed
        ring = vortex_ring(1.0, center=c, n=4000)
        errs.append(hausdorff_distance(res[0].points, ring, spacing=2e-3))
        h = 3 / m
        assert errs[-1] < 0.3 * h**2  # measured 0.18 h² and 0.21 h²
        # orientation: it links a small loop right-handed about +y at (1, 0, 0) positively, like vortex_ring
        probe = vortex_ring(0.4, center=c + [1.0, 0, 0], normal=(0, 1.0, 0), n=40)
        assert linking_number(res[0].points, probe) == linking_number(ring[::100], probe) == 1
        assert res[0].length == pytest.approx(2 * np.pi, rel=2 * h**2)
    assert errs[1] < errs[0] / 2.5


def test_hopf_link_of_a_product_section():
    a, b = hopf_link(0.9, n=400)
    shift = np.array([0.011, -0.013, 0.017])
    mesh = box_tet_mesh((18, 14, 14), lower=np.array([-1.35, -1.35, -1.35]), upper=np.array([2.25, 1.45, 1.45]))
    P = mesh.points - shift
    psi = ring_section(P, np.zeros(3), np.array([0, 0, 1.0]), 0.9) * ring_section(P, np.array([0.9, 0, 0]),
                                                                                  np.array([0, 1.0, 0]), 0.9)
    res = extract_filaments(HermitianLineBundle.trivial(mesh.complex), psi, mesh.points)
    assert len(res) == 2 and all(f.closed for f in res)
    fa, fb = sorted(res, key=lambda f: abs(f.points[:, 2]).max())  # ring a is flat in z
    assert hausdorff_distance(fa.points, a + shift) < 0.05 and hausdorff_distance(fb.points, b + shift) < 0.05
    assert linking_number(fa.points, fb.points) == 1


# ---------------------------------------------------------------------------- invariance and structure
@settings(max_examples=15, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from(["balanced", "vertex"]))
def test_filaments_are_gauge_invariant(seed, placement):
    rng = np.random.default_rng(seed)
    X, P = BOX.complex, BOX.points
    L = random_bundle(X, rng, 0.5)
    psi = line_section(P, 0.41, 0.57) * np.exp(1j * rng.uniform(-0.2, 0.2, X.n_vertices))
    g = np.exp(1j * rng.uniform(-np.pi, np.pi, X.n_vertices))
    r1 = extract_filaments(L, psi, P, placement=placement)
    r2 = extract_filaments(L.gauge(g), np.conj(g) * psi, P, placement=placement)
    assert np.array_equal(r1.index, r2.index) and len(r1) == len(r2)
    for f1, f2 in zip(r1, r2):
        assert np.array_equal(f1.faces, f2.faces) and f1.closed == f2.closed
        assert np.allclose(f1.points, f2.points, rtol=0, atol=1e-12)


@settings(max_examples=15, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from([0.3, 1.0, 3.0]))
def test_filament_structure_for_random_curved_bundles(seed, scale):
    """Every crossing is used |ind| times; consecutive points share a tetrahedron; chains end on the boundary."""
    rng = np.random.default_rng(seed)
    mesh = box_tet_mesh(3)
    X, P = mesh.complex, mesh.points
    L = random_bundle(X, rng, scale)
    psi = rng.normal(size=X.n_vertices) + 1j * rng.normal(size=X.n_vertices)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DhlbWarning)
        res = extract_filaments(L, psi, P)
    faces = np.concatenate([f.faces for f in res]) if len(res) else np.zeros(0, np.int64)
    assert np.array_equal(np.bincount(faces, minlength=X.n_simplices(2)), np.abs(res.index))
    boundary = np.bincount(X.faces(3).ravel(), minlength=X.n_simplices(2)) == 1
    tets = X.simplices(3)
    tri = X.simplices(2)
    for f in res:
        nxt = np.roll(f.faces, -1) if f.closed else f.faces[1:]
        pairs = np.stack([f.faces[:nxt.size], nxt], axis=1)
        for s, t in pairs:  # the two triangles span at most 4 vertices: a tetrahedron of the mesh
            verts = np.union1d(tri[s], tri[t])
            assert verts.size <= 4 and (verts.size < 4 or np.any(np.all(tets == verts, axis=1)))
        if not f.closed:
            assert boundary[f.faces[0]] and boundary[f.faces[-1]]
        # points lie on their triangles
        lam = np.linalg.lstsq(np.vstack([P[tri[f.faces[0]]].T, np.ones(3)]), np.append(f.points[0], 1.0), rcond=None)[0]
        assert np.all(lam > -1e-9)


def test_ambiguous_tetrahedra_are_reported():
    rng = np.random.default_rng(0)
    mesh = box_tet_mesh(2)
    L = random_bundle(mesh.complex, rng, 3.0)
    psi = rng.normal(size=27) + 1j * rng.normal(size=27)
    with pytest.warns(DhlbWarning, match="crossed by more than one filament"):
        res = extract_filaments(L, psi, mesh.points)
    assert res.ambiguous_tets.size > 0 and "ambiguous" in repr(res)


def test_face_zeros_barycentric():
    tri = SimplicialComplex([(0, 1, 2, 3)])
    L = HermitianLineBundle.trivial(tri)
    P = np.eye(4, 3)
    P[3] = [1.0, 1.0, 1.0]
    z = np.array([1.0, -1.0 + 1j, -1.0 - 1j, 5.0])  # on face (0, 1, 2): zero at λ = (1/2, 1/4, 1/4)
    pos, lam, clamped, degenerate = face_zeros(L, z, P, [0])
    assert np.allclose(lam, [[0.5, 0.25, 0.25]]) and np.allclose(pos, [[0.5, 0.25, 0.25]])
    assert not clamped[0] and not degenerate[0]
    _, lam, clamped, _ = face_zeros(L, np.array([1.0, 2.0 + 1j, 2.0 - 1j, 1.0]), P, [0])  # zero outside
    assert clamped[0] and np.all(lam >= 0) and lam.sum() == pytest.approx(1.0)
    _, lam, _, degenerate = face_zeros(L, np.array([1.0, 2.0, 3.0, 1.0]), P, [0])  # collinear values
    assert degenerate[0] and np.allclose(lam, 1 / 3)


def test_no_zeros_no_filaments():
    res = extract_filaments(TRIVIAL, np.ones(BOX.complex.n_vertices) * (2 + 1j), BOX.points)
    assert len(res) == 0 and not res.index.any()


# ---------------------------------------------------------------------------- bad input
def test_zero_at_a_vertex_is_named():
    psi = line_section(BOX.points, 0.4, 0.6)  # (0.4, 0.6, z) are grid points
    v = int(np.argmax(psi == 0))
    with pytest.raises(SectionZeroError, match=rf"vertex {v} \(position \[0.4, 0.6, 0.0\]\)"):
        extract_filaments(TRIVIAL, psi, BOX.points)


def test_bad_section_and_points():
    psi = line_section(BOX.points, 0.41, 0.57)
    with pytest.raises(ShapeError):
        extract_filaments(TRIVIAL, psi[:-1], BOX.points)
    with pytest.raises(ShapeError):
        extract_filaments(TRIVIAL, psi, BOX.points[:, :2])
    with pytest.raises(ShapeError):
        extract_filaments(TRIVIAL, psi.astype(str), BOX.points)
    bad = psi.copy()
    bad[7] = np.nan
    with pytest.raises(NonFiniteError, match="vertex 7"):
        extract_filaments(TRIVIAL, bad, BOX.points)
    badP = BOX.points.copy()
    badP[3, 1] = np.inf
    with pytest.raises(NonFiniteError, match="vertex 3"):
        extract_filaments(TRIVIAL, psi, badP)
    surf = SimplicialComplex([(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)])
    with pytest.raises(NonManifoldError, match="dimension 2"):
        extract_filaments(HermitianLineBundle.trivial(surf), np.ones(4), np.eye(4, 3))


def test_folded_or_branching_meshes_are_rejected():
    P = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [0.1, 0.1, 0.5], [0.2, 0.2, -1]], float)
    z = (P[:, 0] - 0.2) + 1j * (P[:, 1] - 0.3)  # crosses the triangle (0, 1, 2)
    folded = SimplicialComplex([(0, 1, 2, 3), (0, 1, 2, 4)])  # both apexes above the triangle
    with pytest.raises(InconsistentOrientationError, match=r"\(0, 1, 2\)"):
        extract_filaments(HermitianLineBundle.trivial(folded), z[:5], P[:5])
    branching = SimplicialComplex([(0, 1, 2, 3), (0, 1, 2, 4), (0, 1, 2, 5)])
    with pytest.raises(NonManifoldError, match=r"\(0, 1, 2\) lies in 3"):
        extract_filaments(HermitianLineBundle.trivial(branching), z, P)


# ---------------------------------------------------------------------------- placement gauges
def test_placements_agree_for_flat_connections():
    rng = np.random.default_rng(3)
    g = np.exp(1j * rng.uniform(-np.pi, np.pi, BOX.complex.n_vertices))
    L = TRIVIAL.gauge(g)  # flat, but r != 1
    psi = np.conj(g) * ring_section(BOX.points, np.array([0.5, 0.51, 0.52]), np.array([0, 0.6, 0.8]), 0.3)
    a = extract_filaments(L, psi, BOX.points, placement="balanced")
    b = extract_filaments(L, psi, BOX.points, placement="vertex")
    assert len(a) == len(b) == 1 and a[0].closed
    assert np.allclose(a[0].points, b[0].points, rtol=0, atol=1e-12)
    with pytest.raises(InvalidParameterError):
        extract_filaments(L, psi, BOX.points, placement="middle")


@settings(max_examples=15, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from([0.5, 1.5]))
def test_balanced_placement_clamps_only_when_a_balanced_angle_reaches_pi(seed, scale):
    rng = np.random.default_rng(seed)
    X, P = BOX.complex, BOX.points
    L = random_bundle(X, rng, scale)
    z = rng.normal(size=X.n_vertices) + 1j * rng.normal(size=X.n_vertices)
    ind = L.index_form(z)
    faces = np.nonzero(np.abs(ind) == 1)[0]
    _, lam, clamped, degenerate = face_zeros(L, z, P, faces)
    xi = L.rotation_form(z)
    f = X.faces(2)[faces]
    balanced = np.stack([xi[f[:, 2]], xi[f[:, 0]], -xi[f[:, 1]]], axis=1) + L.curvature[faces, None] / 3
    assert np.allclose(balanced.sum(axis=1), 2 * np.pi * ind[faces], atol=1e-9)
    assert np.all(np.abs(balanced[clamped | degenerate]).max(axis=1) >= np.pi - 1e-9)
    assert np.allclose(lam.sum(axis=1), 1.0) and np.all(lam >= 0)


# ---------------------------------------------------------------------------- with the FEM engine
@pytest.mark.parametrize("circulation", [1.0, -1.0])
def test_vortex_ring_field_through_the_engine(circulation):
    """velocity → bundle → Dirichlet/mass → smallest eigenvector → filament: the ring, oriented like Γ."""
    from dhlb import EuclideanComplex
    from dhlb.fem import bundle_matrices, smallest_eigenpairs
    from dhlb.vortex import FilamentField, velocity_bundle

    mesh = box_tet_mesh(12, lower=-1.6, upper=1.6)
    X, P = mesh.complex, mesh.points
    ring = vortex_ring(1.0, center=(0.01, 0.02, 0.03), n=200)
    L = velocity_bundle(X, P, FilamentField([ring], circulation, core_radius=0.15), 1 / (2 * np.pi))
    A, M = bundle_matrices(L, EuclideanComplex(X, points=P))
    res = extract_filaments(L, smallest_eigenpairs(A, M, 1).eigenvectors[:, 0], P)
    assert len(res) == 1 and res[0].closed
    assert hausdorff_distance(res[0].points, ring) < 0.2  # measured 0.143 (h = 0.27, core 0.15)
    probe = vortex_ring(0.4, center=(1.01, 0.02, 0.03), normal=(0, 1.0, 0), n=40)
    assert linking_number(res[0].points, probe) == np.sign(circulation)
