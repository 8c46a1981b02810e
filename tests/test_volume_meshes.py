"""Tetrahedral meshes: generators, orientation, validation errors, and the fTetWild wrapper."""

from __future__ import annotations

import os

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb.errors import (
    DegenerateSimplexError,
    InconsistentOrientationError,
    InvalidParameterError,
    InvalidSimplexError,
    NonFiniteError,
    NonManifoldError,
    ShapeError,
)
from dhlb.mesh import ball_tet_mesh, box_tet_mesh, check_tet_mesh, signed_volumes, tetgen

TET = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)


def quality(P, T):
    """6√2 vol / L_max³ (1 for the regular tetrahedron)."""
    a, b = np.triu_indices(4, 1)
    L = np.linalg.norm(P[T[:, a]] - P[T[:, b]], axis=2).max(axis=1)
    return 6 * np.sqrt(2) * signed_volumes(P, T) / L**3


def enclosed_volume(P, F):
    """Divergence theorem with outward faces: (1/3) Σ centroid · (area normal)."""
    tri = P[F]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]) / 2
    return float(np.einsum("ij,ij->", tri.mean(axis=1), n) / 3)


# ---------------------------------------------------------------------------- generators
@pytest.mark.parametrize("m", [1, 2, (2, 3, 1)])
def test_box_mesh_counts_volume_orientation(m):
    mesh = box_tet_mesh(m, lower=(-1.0, 0.0, 2.0), upper=(1.0, 3.0, 2.5))
    cells = np.prod(np.broadcast_to(m, 3))
    assert mesh.tets.shape == (6 * cells, 4)
    assert np.all(mesh.volumes > 0)
    assert mesh.volumes.sum() == pytest.approx(2 * 3 * 0.5, rel=1e-13)
    assert enclosed_volume(mesh.points, mesh.boundary_faces) == pytest.approx(3.0, rel=1e-13)
    assert mesh.complex.is_manifold() and mesh.complex.euler_characteristic == 1
    assert mesh.points.min(axis=0).tolist() == [-1.0, 0.0, 2.0]
    assert mesh.points.max(axis=0).tolist() == [1.0, 3.0, 2.5]


@pytest.mark.parametrize("n", [1, 2, 3, 5])
def test_ball_mesh_is_a_good_ball(n):
    R, c = 1.5, np.array([0.2, -0.1, 3.0])
    mesh = ball_tet_mesh(n, radius=R, center=c)
    K = -(-n // 2)
    assert mesh.tets.shape[0] == 6 * n**3 + 36 * n**2 * K
    assert np.all(mesh.volumes > 0)
    assert quality(mesh.points, mesh.tets).min() > 0.059  # measured: 0.0593 (n = 1), 0.067-0.0688 (n = 2..12)
    X = mesh.complex
    assert X.is_manifold() and X.euler_characteristic == 1
    B = mesh.boundary_faces
    assert np.allclose(np.linalg.norm(mesh.points[np.unique(B)] - c, axis=1), R, rtol=0, atol=1e-13)
    assert enclosed_volume(mesh.points - c, B) == pytest.approx(mesh.volumes.sum(), rel=1e-12)
    # the boundary is a closed surface of genus 0
    edges = np.unique(np.sort(B[:, [0, 1, 1, 2, 0, 2]].reshape(-1, 2), axis=1), axis=0)
    V, E, F = np.unique(B).size, edges.shape[0], B.shape[0]
    assert V - E + F == 2


def test_ball_volume_converges_quadratically():
    exact = 4 * np.pi / 3
    err = [exact - ball_tet_mesh(n).volumes.sum() for n in (4, 8, 16)]
    assert all(e > 0 for e in err)  # inscribed polyhedron
    rates = np.log2(np.array(err[:-1]) / np.array(err[1:]))
    assert np.all(np.abs(rates - 2) < 0.15), rates


def test_generators_reject_bad_parameters():
    with pytest.raises(InvalidParameterError):
        box_tet_mesh(2, lower=1.0, upper=0.0)
    with pytest.raises(InvalidParameterError):
        box_tet_mesh(0)
    with pytest.raises(ShapeError):
        box_tet_mesh(2, lower=(0, 0))
    with pytest.raises(NonFiniteError):
        box_tet_mesh(2, upper=(1, np.nan, 1))
    with pytest.raises(InvalidParameterError):
        ball_tet_mesh(2, radius=-1.0)
    with pytest.raises(InvalidParameterError):
        ball_tet_mesh(2.5)


# ---------------------------------------------------------------------------- orientation
@settings(max_examples=15, deadline=None)
@given(st.lists(st.booleans(), min_size=48, max_size=48), st.permutations(range(4)))
def test_orientation_is_fixed_per_tet(flip, perm):
    mesh = box_tet_mesh(2)
    T = mesh.tets[:, list(perm)].copy()
    f = np.array(flip)
    T[f] = T[f][:, [1, 0, 2, 3]]
    out = check_tet_mesh(mesh.points, T)
    assert np.all(out.volumes > 0)
    assert np.array_equal(out.flipped, signed_volumes(mesh.points, T) < 0)
    assert np.array_equal(np.sort(out.tets, axis=1), np.sort(T, axis=1))  # same tets, same rows
    assert np.array_equal(out.complex.simplices(3)[out.index], np.sort(T, axis=1))


def test_require_orientation_names_the_inverted_tet():
    mesh = box_tet_mesh(1)
    T = mesh.tets.copy()
    T[3] = T[3][[0, 2, 1, 3]]
    with pytest.raises(InconsistentOrientationError, match=r"tetrahedron #3 .*negatively oriented") as err:
        check_tet_mesh(mesh.points, T, orientation="require")
    assert err.value.element == 3
    with pytest.raises(InvalidParameterError):
        check_tet_mesh(mesh.points, T, orientation="maybe")


# ---------------------------------------------------------------------------- bad meshes
def test_degenerate_tet_is_named():
    P = np.vstack([TET, [1, 1, 0]])  # tet (1, 2, 4, 3) fine; (1, 2, 4, 0) flat: all in z = 0
    with pytest.raises(DegenerateSimplexError, match=r"tetrahedron #1 \(vertices \(0, 1, 2, 4\)\)") as err:
        check_tet_mesh(P, [[0, 1, 2, 3], [0, 1, 2, 4]])
    assert err.value.element == 1
    with pytest.raises(DegenerateSimplexError):  # nearly flat counts as flat
        check_tet_mesh(np.vstack([TET[:3], [0.3, 0.3, 1e-12]]), [[0, 1, 2, 3]])


def test_folded_mesh_is_rejected():
    P = np.vstack([TET, [0.1, 0.1, 0.5]])  # vertex 4 on the same side of triangle 012 as vertex 3
    with pytest.raises(InconsistentOrientationError, match=r"same side of their common triangle \(0, 1, 2\)") as err:
        check_tet_mesh(P, [[0, 1, 2, 3], [0, 2, 1, 4]])
    assert set(err.value.element) == {0, 1}


def test_non_manifold_meshes_are_rejected():
    P = np.vstack([TET, [-1, 0, 0], [0, -1, 0], [0, 0, -1]])
    # two tetrahedra meeting in the vertex 0 only
    with pytest.raises(NonManifoldError, match=r"vertex \(0,\)") as err:
        check_tet_mesh(P, [[0, 1, 2, 3], [0, 4, 6, 5]])
    assert err.value.k == 0 and err.value.element in (0, 1)
    # a triangle in three tetrahedra
    P3 = np.vstack([TET, [0.3, 0.3, -1], [2, 2, 0.5]])
    with pytest.raises(NonManifoldError, match="triangle"):
        check_tet_mesh(P3, [[0, 1, 2, 3], [0, 2, 1, 4], [0, 1, 2, 5]], orientation="fix")
    # a duplicated tetrahedron
    with pytest.raises(NonManifoldError, match=r"#1 .* repeats .*#0"):
        check_tet_mesh(TET, [[0, 1, 2, 3], [3, 2, 1, 0]])


def test_bad_arrays_are_typed_errors():
    with pytest.raises(ShapeError):
        check_tet_mesh(TET[:, :2], [[0, 1, 2, 3]])
    with pytest.raises(NonFiniteError, match="vertex 2"):
        check_tet_mesh(np.where(np.arange(12).reshape(4, 3) == 7, np.nan, TET), [[0, 1, 2, 3]])
    with pytest.raises(InvalidSimplexError):
        check_tet_mesh(TET, [[0, 1, 2]])
    with pytest.raises(InvalidSimplexError, match="refers to vertex 7"):
        check_tet_mesh(TET, [[0, 1, 2, 7]])
    with pytest.raises(InvalidSimplexError):
        check_tet_mesh(TET, [[0, 1, 1, 3]])
    with pytest.raises(InvalidParameterError):
        check_tet_mesh(TET, [[0, 1, 2, 3]], rtol=-1)


# ---------------------------------------------------------------------------- fTetWild
def test_tetrahedralize_rejects_open_surface_without_backend():
    F = np.array([[0, 1, 2], [0, 1, 3], [0, 2, 3]])  # tetrahedron boundary minus one face
    with pytest.raises(NonManifoldError, match=r"edge \(1, 2\) lies in 1 triangle"):
        tetgen.tetrahedralize(TET, F)
    with pytest.raises(ShapeError):
        tetgen.tetrahedralize(TET[:, :2], F)


@pytest.mark.skipif(not tetgen.available(), reason="pytetwild is not installed (optional extra dhlb[tet])")
def test_tetrahedralize_ball_surface(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    ball = ball_tet_mesh(3)
    V, F = ball.points, ball.boundary_faces  # V has interior vertices too: they are dropped
    mesh = tetgen.tetrahedralize(V, F, edge_length_fac=0.15, epsilon=1e-3)
    assert os.listdir(tmp_path) == []  # the scratch file went elsewhere
    assert np.all(mesh.volumes > 0) and mesh.flipped.any()
    assert mesh.complex.is_manifold() and mesh.complex.euler_characteristic == 1
    diag = np.linalg.norm(np.ptp(V, axis=0))
    # the envelope is epsilon * diagonal: volume within (area * envelope) of the input's
    assert abs(mesh.volumes.sum() - ball.volumes.sum()) < 4 * np.pi * 1e-3 * diag
    with pytest.raises(InvalidParameterError):
        tetgen.tetrahedralize(V, F, edge_length_fac=2.0)
