"""Surface mesh validation: every kind of bad input raises a typed error naming the input face/vertex."""

from __future__ import annotations

import os
import warnings

import numpy as np
import pytest

from dhlb.errors import (
    DegenerateSimplexError,
    DhlbWarning,
    EmptyComplexError,
    InconsistentOrientationError,
    InvalidParameterError,
    InvalidSimplexError,
    NonFiniteError,
    NonManifoldError,
    NonOrientableError,
    ShapeError,
    UnreferencedVertexWarning,
)
from dhlb.io import read_surface
from dhlb.mesh import SurfaceMesh, tangent_bundle, validate_surface
from tests.surface_meshes import grid, icosphere

DATA = os.path.join(os.path.dirname(__file__), "data")
SQUARE = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]


def test_valid_mesh_keeps_input_orientation_and_numbering():
    V, F = icosphere(1)
    mesh = validate_surface(V, F)
    assert isinstance(mesh, SurfaceMesh)
    assert mesh.is_closed and mesh.euler_characteristic == 2
    assert np.array_equal(mesh.vertex_labels[mesh.faces], F)
    assert np.array_equal(mesh.face_rows, np.arange(len(F)))
    assert not mesh.flipped.any()
    # the mesh orientation is the fundamental cycle: its boundary vanishes
    assert not np.any(mesh.complex.boundary(2) @ mesh.triangle_sign)
    assert np.array_equal(mesh.face_of_triangle[mesh.triangle_of_face], np.arange(len(F)))


def test_planar_input_is_padded():
    mesh = validate_surface(np.array(SQUARE)[:, :2], [[0, 1, 2], [1, 3, 2]])
    assert mesh.points.shape == (4, 3) and not mesh.points[:, 2].any()


def test_boundary_halfedges_follow_the_faces():
    V, F = grid(3, 2)
    mesh = validate_surface(V, F)
    bd = mesh.boundary_halfedges
    assert len(bd) == 2 * (3 + 2)
    # each boundary half-edge is traversed by its face, and the boundary is a cycle
    h = {tuple(e) for f in mesh.faces.tolist() for e in zip(f, f[1:] + f[:1])}
    assert all(tuple(e) in h for e in bd.tolist())
    assert sorted(bd[:, 0].tolist()) == sorted(bd[:, 1].tolist())


def test_unreferenced_vertices_are_compacted_with_a_warning():
    V = np.array(SQUARE + [[5, 5, 5], [np.nan, 0, 0]], float)
    F = np.array([[0, 1, 2], [1, 3, 2]])
    with pytest.warns(UnreferencedVertexWarning, match="2 vertices"):
        mesh = validate_surface(V, F)  # the NaN vertex is unused: dropped, not an error
    assert mesh.n_vertices == 4 and mesh.n_input_vertices == 6
    values = np.arange(6.0)
    assert np.array_equal(mesh.per_vertex(values), values[:4])
    assert np.isnan(mesh.to_input(np.ones(4))[4:]).all()


def test_compaction_keeps_input_labels_in_complex():
    V = np.array([[9, 9, 9]] + SQUARE, float)
    with pytest.warns(UnreferencedVertexWarning):
        mesh = validate_surface(V, [[1, 2, 3], [2, 4, 3]])
    assert mesh.vertex_labels.tolist() == [1, 2, 3, 4]
    assert mesh.faces.tolist() == [[0, 1, 2], [1, 3, 2]]
    assert np.allclose(mesh.points, SQUARE)


def test_nan_coordinates_name_the_vertex():
    V = np.array(SQUARE, float)
    V[3, 1] = np.nan
    with pytest.raises(NonFiniteError, match="vertex 3"):
        validate_surface(V, [[0, 1, 2], [1, 3, 2]])


@pytest.mark.parametrize("F, err, match", [
    ([[0, 1, 1], [1, 3, 2]], DegenerateSimplexError, "face 0 .* repeats a vertex"),
    ([[0, 1, 2], [1, 3, 7]], InvalidSimplexError, "face 1 .* outside V"),
    ([[0, 1, 2], [1, 3, -1]], InvalidSimplexError, "face 1"),
    ([[0, 1, 2], [1, 2, 0]], InvalidSimplexError, "faces 0 and 1 .* same orientation"),
    ([[0, 1, 2], [0, 2, 1]], InvalidSimplexError, "faces 0 and 1 .* opposite orientations"),
    ([[0.5, 1, 2]], InvalidSimplexError, "non-integer"),
    ([[0, 1, 2, 3]], InvalidSimplexError, r"shape \(m, 3\)"),
    (np.zeros((0, 3), int), EmptyComplexError, "no faces"),
])
def test_bad_faces(F, err, match):
    with pytest.raises(err, match=match):
        validate_surface(SQUARE, F)


def test_bad_vertex_array():
    with pytest.raises(ShapeError):
        validate_surface(np.zeros((4, 4)), [[0, 1, 2]])
    with pytest.raises(ShapeError):
        validate_surface("abc", [[0, 1, 2]])


def test_zero_area_face_is_named():
    V = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [2, 0, 0]]
    with pytest.raises(DegenerateSimplexError, match=r"face 1 \(vertices 0, 1, 3\)"):
        validate_surface(V, [[0, 1, 2], [0, 1, 3]])


def test_non_manifold_edge():
    V = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1]]
    F = [[0, 1, 2], [1, 0, 3], [0, 1, 4]]
    with pytest.raises(NonManifoldError, match=r"edge \(0, 1\).* 3 faces \(rows 0, 1, 2\)"):
        validate_surface(V, F)


def test_non_manifold_vertex_bowtie():
    V = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [-1, 0, 0], [-1, -1, 0]]
    with pytest.raises(NonManifoldError, match="vertex 0"):
        validate_surface(V, [[0, 1, 2], [0, 3, 4]])


def test_non_manifold_vertex_double_cone():
    V, F = icosphere(0)
    # glue two icosahedra at vertex 0 (the second copy reuses vertex 0)
    V2 = np.vstack([V, V[1:] + [0, 0, 0]])
    V2[12:] = 2 * V[0] - V2[12:]
    F2 = np.where(F == 0, 0, F + 11)
    with pytest.raises(NonManifoldError, match="vertex 0"):
        validate_surface(V2, np.vstack([F, F2[:, ::-1]]))


def test_moebius_band_is_not_orientable():
    V, F = read_surface(os.path.join(DATA, "moebius.obj"))
    for reorient in (False, True):
        with pytest.raises(NonOrientableError, match=r"Möbius band.*future work"):
            validate_surface(V, F, reorient=reorient)


def test_inconsistent_orientation_and_reorient():
    V, F = icosphere(1)
    F = F.copy()
    bad = [3, 17, 40]
    F[bad] = F[bad][:, ::-1]
    with pytest.raises(InconsistentOrientationError, match="reorient=True"):
        validate_surface(V, F)
    mesh = validate_surface(V, F, reorient=True)
    assert sorted(np.nonzero(mesh.flipped)[0].tolist()) == bad  # the majority orientation is kept
    assert not np.any(mesh.complex.boundary(2) @ mesh.triangle_sign)
    tb = tangent_bundle(V, F, 2, reorient=True)
    assert np.isclose(tb.total_curvature, 2 * np.pi * 2 * 2)


def test_several_components():
    V1, F1 = icosphere(1)
    V2, F2 = grid(2, 2)
    V = np.vstack([V1, V2 + 5])
    F = np.vstack([F1, F2 + len(V1)])
    mesh = validate_surface(V, F)
    assert mesh.components[0] == 2 and mesh.euler_characteristic == 3
    tb = tangent_bundle(mesh, n=3)
    assert np.isclose(tb.total_curvature + tb.total_boundary_turning, 2 * np.pi * 3 * 3)
    with pytest.warns(DhlbWarning, match="largest of 2"):
        big = validate_surface(V, F, components="largest")
    assert big.n_faces == len(F1) and np.array_equal(big.face_rows, np.arange(len(F1)))
    with pytest.raises(InvalidParameterError):
        validate_surface(V, F, components="biggest")


def test_tangent_bundle_argument_errors():
    V, F = icosphere(0)
    mesh = validate_surface(V, F)
    with pytest.raises(InvalidParameterError):
        tangent_bundle(mesh, F)
    with pytest.raises(InvalidParameterError):
        tangent_bundle(V)
    for n in (0, -2, 1.5, True):
        with pytest.raises(InvalidParameterError):
            tangent_bundle(mesh, n=n)


def test_no_numpy_warnings_on_bad_input():
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        with pytest.raises(DegenerateSimplexError):
            validate_surface([[0, 0, 0], [1, 0, 0], [2, 0, 0]], [[0, 1, 2]])


def test_messages_use_input_face_rows_after_dropping_components():
    V1, F1 = grid(1, 1)  # 2 faces, dropped by components="largest"
    V2, F2 = icosphere(1)
    F2 = F2.copy()
    F2[10] = F2[10][::-1]
    V = np.vstack([V1 + 5, V2])
    F = np.vstack([F1, F2 + len(V1)])
    with pytest.warns(DhlbWarning):
        with pytest.raises(InconsistentOrientationError, match=r"faces \d+ and \d+") as info:
            validate_surface(V, F, components="largest")
    named = [int(x) for x in str(info.value).split("faces ")[1].split(" traverse")[0].split(" and ")]
    assert 12 in named  # input row 12 = face 10 of the sphere
    with pytest.warns(DhlbWarning):
        mesh = validate_surface(V, F, components="largest", reorient=True)
    assert mesh.face_rows[mesh.flipped].tolist() == [12]


@pytest.mark.parametrize("case", ["sphere", "grid-unused", "largest", "reoriented", "bunny-7k"])
def test_halfedge_tables_agree_with_the_complex(case):
    """The one-sort half-edge tables (twins, edge rows, triangle rows) equal the complex's own look-ups."""
    kw = {}
    if case == "sphere":
        V, F = icosphere(2)
    elif case == "grid-unused":
        V, F = grid(5)
        V = np.vstack([V, [[9.0, 9.0, 9.0]]])[::-1].copy()  # an unused vertex, and labels reversed
        F = len(V) - 1 - F[:, ::-1]
    elif case == "largest":
        V1, F1 = icosphere(1)
        V2, F2 = grid(4)
        V, F = np.vstack([V2, V1]), np.vstack([F2, F1 + len(V2)])
        kw = {"components": "largest"}
    elif case == "reoriented":
        V, F = icosphere(1)
        F = F.copy()
        F[::3] = F[::3, ::-1]
        kw = {"reorient": True}
    else:
        V, F = read_surface(os.path.join(DATA, "bunny-7k.obj"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        m = validate_surface(V, F, **kw)
    X, L = m.complex, m.vertex_labels
    np.testing.assert_array_equal(m.triangle_of_face, X.index(2, L[m.faces]))
    h = np.stack([m.faces, np.roll(m.faces, -1, axis=1)], axis=-1).reshape(-1, 2)
    np.testing.assert_array_equal(m.halfedge_edge, X.index(1, L[h]))
    tw = m.halfedge_twin
    inner = tw >= 0
    np.testing.assert_array_equal(h[tw[inner]], h[inner][:, ::-1])
    assert (~inner).sum() == len(m.boundary_halfedges)
