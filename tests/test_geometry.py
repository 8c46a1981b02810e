"""Tests of dhlb.geometry: per-simplex metric quantities and Euclidean complexes."""

from itertools import combinations, permutations
from math import factorial

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from scipy.spatial import Delaunay

from dhlb import SimplicialComplex
from dhlb.errors import (
    DegenerateSimplexError,
    InvalidMetricError,
    InvalidParameterError,
    NonFiniteError,
    NonManifoldError,
    ShapeError,
)
from dhlb.examples import cube_nd
from dhlb.geometry import EuclideanComplex, SimplexStack, metric_from_squared_lengths, squared_lengths_from_points

SETTINGS = settings(max_examples=40, deadline=None)


# ---------------------------------------------------------------------- helpers
def kuhn_grid(n, m, jitter=0.0, seed=0):
    """Kuhn (Freudenthal) triangulation of [0,1]^n with m cells per side: (points, simplices)."""
    idx = np.indices((m + 1,) * n).reshape(n, -1).T
    points = idx / m
    strides = (m + 1) ** np.arange(n)[::-1]
    corners = np.indices((m,) * n).reshape(n, -1).T
    simplices = []
    for perm in permutations(range(n)):
        steps = np.zeros((n + 1, n), int)
        for a, axis in enumerate(perm):
            steps[a + 1:, axis] += 1
        simplices.append((corners[:, None, :] + steps[None, :, :]) @ strides)
    if jitter:
        rng = np.random.default_rng(seed)
        interior = np.all((idx > 0) & (idx < m), axis=1)
        points = points + interior[:, None] * rng.uniform(-jitter, jitter, points.shape) / m
    return points, np.concatenate(simplices)


def simplex_points(n, d, draw_or_rng):
    return draw_or_rng.normal(size=(n + 1, d))


def facet_geometry(P):
    """Brute force on one simplex P (n+1, d): outward unit normals N_i, heights h_i (ambient)."""
    n = P.shape[0] - 1
    N, h = [], []
    for i in range(n + 1):
        rest = np.delete(P, i, axis=0)
        base = rest[0]
        E = (rest[1:] - base).T
        x = P[i] - base
        coef = np.linalg.lstsq(E, x, rcond=None)[0] if E.size else np.zeros(0)
        perp = x - (E @ coef if E.size else 0)
        h.append(np.linalg.norm(perp))
        N.append(-perp / np.linalg.norm(perp))
    return np.array(N), np.array(h)


def gram_volume(Q):
    """Volume of the simplex spanned by the rows of Q via the Gram determinant."""
    k = Q.shape[0] - 1
    if k == 0:
        return 1.0
    E = Q[1:] - Q[0]
    return np.sqrt(np.linalg.det(E @ E.T)) / factorial(k)


well_shaped = st.integers(1, 6).flatmap(
    lambda n: st.tuples(st.just(n), st.integers(0, 2),
                        arrays(np.float64, (n + 1, n + 2), elements=st.floats(-2, 2))))


# ---------------------------------------------------------------------- SimplexStack
@SETTINGS
@given(well_shaped)
def test_length_route_equals_point_route(data):
    n, extra, P = data
    P = P[:, : n + extra]
    S = SimplexStack.from_points(P[None])
    assume(S.condition_numbers[0] < 1e6)
    T = SimplexStack.from_squared_lengths(squared_lengths_from_points(P[None]))
    E = P[1:] - P[0]
    np.testing.assert_allclose(T.metric[0], E @ E.T, rtol=1e-12, atol=1e-12 * np.abs(E @ E.T).max())
    np.testing.assert_allclose(T.volumes, S.volumes, rtol=1e-9)
    scale = np.abs(S.cotan_weights).max()
    np.testing.assert_allclose(T.cotan_weights, S.cotan_weights, atol=1e-8 * scale)
    assert T.positive_definite[0] and S.positive_definite[0]


@SETTINGS
@given(st.integers(1, 6), st.integers(0, 10**6))
def test_gradient_gram_against_barycentric_system(n, seed):
    """∇λ_i from inverting [[Pᵀ], [1]] (full-dimensional) -- an independent computation."""
    P = np.random.default_rng(seed).normal(size=(n + 1, n))
    S = SimplexStack.from_points(P[None])
    assume(S.condition_numbers[0] < 1e6)
    B = np.linalg.inv(np.vstack([P.T, np.ones(n + 1)]))
    grads = B[:, :n]
    G = grads @ grads.T
    np.testing.assert_allclose(S.barycentric_gradient_gram[0], G, atol=1e-9 * np.abs(G).max())
    np.testing.assert_allclose(S.barycentric_gradient_gram[0].sum(axis=1), 0, atol=1e-9 * np.abs(G).max())
    ev = np.linalg.eigvalsh(S.barycentric_gradient_gram[0])
    assert ev[0] > -1e-9 * ev[-1] and ev[1] > 1e-9 * ev[-1]  # PSD of rank exactly n
    assert S.volumes[0] == pytest.approx(abs(np.linalg.det(P[1:] - P[0])) / factorial(n), rel=1e-10)


@SETTINGS
@given(st.integers(2, 6), st.integers(0, 2), st.integers(0, 10**6))
def test_theorem16_cotangent_formula(n, extra, seed):
    """vol·G_ij = -cot(α_ij) vol(σ∖{i,j}) / (n(n-1)) and vol·G_ii = vol(σ∖{i}) / (n h_i)."""
    P = np.random.default_rng(seed).normal(size=(n + 1, n + extra))
    S = SimplexStack.from_points(P[None])
    assume(S.condition_numbers[0] < 1e5)
    N, h = facet_geometry(P)
    c = S.cotan_weights[0]
    scale = np.abs(c).max()
    for i in range(n + 1):
        face_i = gram_volume(np.delete(P, i, axis=0))
        assert c[i, i] == pytest.approx(face_i / (n * h[i]), rel=1e-8)
        for j in range(i + 1, n + 1):
            alpha = np.arccos(np.clip(-N[i] @ N[j], -1, 1))
            face_ij = gram_volume(np.delete(P, [i, j], axis=0))
            expected = -face_ij / (n * (n - 1) * np.tan(alpha))
            assert c[i, j] == pytest.approx(expected, abs=1e-8 * scale)
            assert S.dihedral_angles[0, i, j] == pytest.approx(alpha, abs=1e-7)
    np.testing.assert_allclose(S.heights[0], h, rtol=1e-9)


def test_cotangent_formula_n2_and_n3_classic():
    P = np.array([[0.0, 0.0], [4.0, 0.0], [1.0, 2.0]])
    c = SimplexStack.from_points(P[None]).cotan_weights[0]
    for i, j in combinations(range(3), 2):
        k = 3 - i - j
        u, v = P[i] - P[k], P[j] - P[k]
        theta = np.arctan2(abs(u[0] * v[1] - u[1] * v[0]), u @ v)
        assert c[i, j] == pytest.approx(-0.5 / np.tan(theta), rel=1e-13)
    T = np.array([[0.0, 0, 0], [1, 0, 0], [0, 2, 0], [0.3, 0.4, 1.5]])
    S = SimplexStack.from_points(T[None])
    c = S.cotan_weights[0]
    for i, j in combinations(range(4), 2):
        k, l = (v for v in range(4) if v not in (i, j))
        e = T[l] - T[k]
        # dihedral angle at edge kl: between the planes (k,l,i) and (k,l,j), measured around e
        ui = (T[i] - T[k]) - (T[i] - T[k]) @ e / (e @ e) * e
        uj = (T[j] - T[k]) - (T[j] - T[k]) @ e / (e @ e) * e
        theta = np.arctan2(np.linalg.norm(np.cross(ui, uj)), ui @ uj)
        assert c[i, j] == pytest.approx(-np.linalg.norm(e) / (6 * np.tan(theta)), rel=1e-12)


def test_one_simplex_and_regular_simplices():
    c = SimplexStack.from_squared_lengths([[[0, 4.0], [4.0, 0]]]).cotan_weights[0]
    np.testing.assert_allclose(c, [[0.5, -0.5], [-0.5, 0.5]], rtol=1e-15)
    for n in range(1, 7):
        L2 = (np.ones((n + 1, n + 1)) - np.eye(n + 1))[None]
        S = SimplexStack.from_squared_lengths(L2)
        assert S.volumes[0] == pytest.approx(np.sqrt(n + 1) / (factorial(n) * 2 ** (n / 2)), rel=1e-13)
        if n >= 2:  # all dihedral angles of the regular simplex are arccos(1/n)
            off = S.dihedral_angles[0][~np.eye(n + 1, dtype=bool)]
            np.testing.assert_allclose(off, np.arccos(1 / n), rtol=1e-12)


def test_polarization_identity_doctest_values():
    g = metric_from_squared_lengths([[[0, 9, 16], [9, 0, 25], [16, 25, 0]]])[0]
    np.testing.assert_array_equal(g, [[9, 0], [0, 16]])


def test_status_degenerate_and_indefinite():
    L2 = np.array([[[0, 1, 4], [1, 0, 1], [4, 1, 0]],       # collinear 1 + 1 = 2
                   [[0, 1, 9], [1, 0, 1], [9, 1, 0]],       # 3 > 1 + 1
                   [[0, 1, 1], [1, 0, 1], [1, 1, 0]]], float)
    S = SimplexStack.from_squared_lengths(L2)
    assert S.status.tolist() == [1, 2, 0]
    assert S.volumes[0] == 0 and np.isnan(S.volumes[1]) and S.volumes[2] > 0
    assert np.isinf(S.condition_numbers[:2]).all()
    with pytest.raises(InvalidMetricError, match=r"triangle inequality fails on the face \(7, 8, 9\)"):
        S.check(labels=[[1, 2, 3], [7, 8, 9], [4, 5, 6]])
    with pytest.raises(DegenerateSimplexError, match=r"simplex \(1, 2, 3\): zero volume"):
        SimplexStack.from_squared_lengths(L2[[0, 2]]).check(labels=[[1, 2, 3], [4, 5, 6]])
    flat = SimplexStack.from_points([[[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]])
    assert flat.status.tolist() == [1]


def test_stack_input_errors():
    with pytest.raises(ShapeError):
        SimplexStack.from_points(np.zeros((2, 4, 2)))  # 3-simplices in R^2
    with pytest.raises(NonFiniteError):
        SimplexStack.from_points([[[0, 0], [np.nan, 0], [0, 1]]])
    with pytest.raises(InvalidMetricError):
        SimplexStack.from_squared_lengths([[[0, -1], [-1, 0]]])
    with pytest.raises(InvalidMetricError):
        SimplexStack.from_squared_lengths([[[0, 1], [2, 0]]])
    with pytest.raises(ShapeError):
        SimplexStack.from_squared_lengths(np.zeros((1, 2, 3)))


@SETTINGS
@given(st.integers(2, 5), st.integers(0, 10**6))
def test_stack_relabel_and_rigid_motion(n, seed):
    rng = np.random.default_rng(seed)
    P = rng.normal(size=(n + 1, n + 1))
    S = SimplexStack.from_points(P[None])
    assume(S.condition_numbers[0] < 1e6)
    perm = rng.permutation(n + 1)
    Q, _ = np.linalg.qr(rng.normal(size=(n + 1, n + 1)))
    moved = SimplexStack.from_points((P[perm] @ Q.T + rng.normal(size=n + 1))[None])
    scale = np.abs(S.cotan_weights).max()
    np.testing.assert_allclose(moved.cotan_weights[0], S.cotan_weights[0][np.ix_(perm, perm)], atol=1e-9 * scale)
    np.testing.assert_allclose(moved.dihedral_angles[0], S.dihedral_angles[0][np.ix_(perm, perm)], atol=1e-8)
    assert moved.volumes[0] == pytest.approx(S.volumes[0], rel=1e-10)


# ---------------------------------------------------------------------- EuclideanComplex
def test_triangle_mesh_cotan_laplacian_classic():
    rng = np.random.default_rng(3)
    pts = rng.uniform(size=(60, 2))
    tri = Delaunay(pts).simplices
    E = EuclideanComplex(SimplicialComplex(tri), points=pts)
    K = E.stiffness_matrix()
    W = {}
    for t in tri:
        for k in range(3):
            i, j = (v for v in t if v != t[k])
            u, v = pts[i] - pts[t[k]], pts[j] - pts[t[k]]
            theta = np.arctan2(abs(u[0] * v[1] - u[1] * v[0]), u @ v)
            key = (min(i, j), max(i, j))
            W[key] = W.get(key, 0.0) + 0.5 / np.tan(theta)
    ref = np.zeros((60, 60))
    for (i, j), w in W.items():
        ref[i, j] = ref[j, i] = -w
    ref[np.diag_indices(60)] = -ref.sum(axis=1)
    np.testing.assert_allclose(K.toarray(), ref, atol=1e-12 * np.abs(ref).max())
    assert isinstance(K, sp.csr_matrix)


@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_kernel_psd_and_linear_precision(n):
    pts, simp = kuhn_grid(n, {1: 7, 2: 5, 3: 3, 4: 2}[n], jitter=0.2, seed=n)
    E = EuclideanComplex(SimplicialComplex(simp), points=pts)
    K = E.stiffness_matrix().toarray()
    np.testing.assert_allclose(K, K.T, atol=0)
    scale = np.abs(K).max()
    np.testing.assert_allclose(K @ np.ones(len(pts)), 0, atol=1e-13 * scale)
    ev = np.linalg.eigvalsh(K)
    assert ev[0] > -1e-12 * ev[-1] and ev[1] > 1e-6 * ev[-1]     # PSD, kernel = constants
    a = np.arange(1.0, n + 1)
    u = pts @ a                                                 # linear function
    assert u @ K @ u == pytest.approx(a @ a, rel=1e-11)          # exact energy |a|² vol
    interior = np.all((pts > 1e-9) & (pts < 1 - 1e-9), axis=1)
    np.testing.assert_allclose((K @ u)[interior], 0, atol=1e-12 * scale)
    assert E.volumes().sum() == pytest.approx(1.0, rel=1e-13)
    Mc, Ml = E.mass_matrix(), E.mass_matrix(lumped=True)
    assert Mc.sum() == pytest.approx(1.0, rel=1e-13) and Ml.sum() == pytest.approx(1.0, rel=1e-13)
    assert u @ Mc @ np.ones(len(pts)) == pytest.approx(a.sum() / 2, rel=1e-12)  # ∫ a·x over the cube
    assert np.linalg.eigvalsh(Mc.toarray())[0] > 0


@pytest.mark.parametrize("n, m", [(1, 5), (2, 4), (3, 3), (4, 2), (5, 1)])
def test_cube_nd_volumes_sum_to_one(n, m):
    X, P = cube_nd(n, m, return_points=True)
    E = EuclideanComplex(X, points=P)
    assert E.volumes().sum() == pytest.approx(1.0, rel=1e-13)
    np.testing.assert_allclose(E.volumes(), 1.0 / (factorial(n) * m**n), rtol=1e-13)
    if n >= 2:   # the boundary (n-1)-faces have total volume 2n
        bd = np.bincount(X.faces(n).ravel(), minlength=X.n_simplices(n - 1)) == 1
        assert E.volumes(n - 1)[bd].sum() == pytest.approx(2 * n, rel=1e-13)


def test_stiffness_3d_against_brute_force():
    pts, simp = kuhn_grid(3, 2, jitter=0.25, seed=7)
    E = EuclideanComplex(SimplicialComplex(simp), points=pts)
    N = len(pts)
    ref = np.zeros((N, N))
    for t in simp:
        P = pts[t]
        B = np.linalg.inv(np.vstack([P.T, np.ones(4)]))
        grads = B[:, :3]
        vol = abs(np.linalg.det(P[1:] - P[0])) / 6
        for a in range(4):
            for b in range(4):
                ref[t[a], t[b]] += vol * grads[a] @ grads[b]
    np.testing.assert_allclose(E.stiffness_matrix().toarray(), ref, atol=1e-12 * np.abs(ref).max())


def test_edge_length_route_equals_point_route_on_embedded_surface():
    rng = np.random.default_rng(11)
    pts2, tri = kuhn_grid(2, 4, jitter=0.2, seed=1)
    z = np.sin(3 * pts2[:, 0]) * pts2[:, 1]
    P = np.column_stack([pts2, z]) @ np.linalg.qr(rng.normal(size=(3, 3)))[0]   # surface in R^3
    X = SimplicialComplex(tri)
    A = EuclideanComplex(X, points=P)
    B = EuclideanComplex(X, edge_lengths=A.edge_lengths)
    for k in range(3):
        np.testing.assert_allclose(B.volumes(k), A.volumes(k), rtol=1e-12)
    np.testing.assert_allclose(B.stiffness_matrix().toarray(), A.stiffness_matrix().toarray(), atol=1e-12)
    np.testing.assert_allclose(B.mass_matrix().toarray(), A.mass_matrix().toarray(), rtol=1e-12)
    np.testing.assert_allclose(B.dihedral_angles, A.dihedral_angles, atol=1e-10)
    np.testing.assert_allclose(B.metric, A.metric, atol=1e-13)
    assert A.metric_condition.max() < 100
    assert B.points is None and A.points.shape == (25, 3)


def test_relabeling_and_rigid_motion_invariance():
    pts, tets = kuhn_grid(3, 2, jitter=0.2, seed=5)
    rng = np.random.default_rng(0)
    N = len(pts)
    perm = rng.permutation(N)               # new label of old vertex v is perm[v]
    Q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    A = EuclideanComplex(SimplicialComplex(tets), points=pts)
    new_pts = np.empty_like(pts)
    new_pts[perm] = pts @ Q.T + [1.0, -2.0, 0.5]
    B = EuclideanComplex(SimplicialComplex(perm[tets]), points=new_pts)
    KA, KB = A.stiffness_matrix().toarray(), B.stiffness_matrix().toarray()
    np.testing.assert_allclose(KB[np.ix_(perm, perm)], KA, atol=1e-12 * np.abs(KA).max())
    MA, MB = A.mass_matrix().toarray(), B.mass_matrix().toarray()
    np.testing.assert_allclose(MB[np.ix_(perm, perm)], MA, rtol=1e-12, atol=1e-16)


def test_dihedral_angles_of_corner_tet_and_small_complexes():
    X = SimplicialComplex([(0, 1, 2, 3)])
    E = EuclideanComplex(X, points=np.vstack([np.zeros(3), np.eye(3)]))
    alpha = E.dihedral_angles[0]
    # facets opposite vertices 1, 2, 3 are the coordinate planes: pairwise right angles
    for i, j in [(1, 2), (1, 3), (2, 3)]:
        assert alpha[i, j] == pytest.approx(np.pi / 2, abs=1e-14)
    assert alpha[0, 1] == pytest.approx(np.arccos(1 / np.sqrt(3)), abs=1e-14)
    assert E.volumes(3)[0] == pytest.approx(1 / 6, rel=1e-15)
    assert E.volumes(2).sum() == pytest.approx(1.5 + np.sqrt(3) / 2, rel=1e-14)
    # 0-dimensional complex: volumes 1, zero stiffness, identity mass
    P = EuclideanComplex(SimplicialComplex([(0,), (1,)]), points=np.zeros((2, 1)))
    assert P.volumes(0).tolist() == [1.0, 1.0]
    assert P.stiffness_matrix().shape == (2, 2) and not P.stiffness_matrix().toarray().any()
    np.testing.assert_array_equal(P.mass_matrix().toarray(), np.eye(2))


def test_points_indexed_by_input_label():
    X = SimplicialComplex([(2, 5, 9)])
    by_label = np.zeros((10, 2))
    by_label[[2, 5, 9]] = [[0, 0], [1, 0], [0, 1]]
    by_label[0] = np.nan                      # unused row: ignored
    A = EuclideanComplex(X, points=by_label)
    B = EuclideanComplex(X, points=[[0, 0], [1, 0], [0, 1]])
    np.testing.assert_array_equal(A.stiffness_matrix().toarray(), B.stiffness_matrix().toarray())


def test_euclidean_complex_input_errors():
    X = SimplicialComplex([(10, 11, 12), (11, 12, 13)])
    good = np.array([[0, 0], [1, 0], [0, 1], [1, 1.0]])
    with pytest.raises(NonFiniteError, match="vertex 12"):
        EuclideanComplex(X, points=np.where(np.arange(4)[:, None] == 2, np.inf, good))
    with pytest.raises(ShapeError):
        EuclideanComplex(X, points=good[:3])
    with pytest.raises(ShapeError):
        EuclideanComplex(X, points=good[:, :1])
    with pytest.raises(ShapeError):
        EuclideanComplex(X, edge_lengths=np.ones(4))
    with pytest.raises(InvalidMetricError):
        EuclideanComplex(X)
    with pytest.raises(InvalidMetricError):
        EuclideanComplex(X, points=good, edge_lengths=np.ones(5))
    with pytest.raises(NonFiniteError, match=r"edge \(10, 11\)"):
        EuclideanComplex(X, edge_lengths=[np.nan, 1, 1, 1, 1])
    with pytest.raises(InvalidMetricError, match=r"edge \(11, 12\)"):
        EuclideanComplex(X, edge_lengths=[1, 1, 0, 1, 1])
    with pytest.raises(DegenerateSimplexError, match=r"\(11, 12, 13\)"):
        EuclideanComplex(X, points=[[0, 0], [1, 0], [0, 1], [-1, 2.0]])
    # rows of simplices(1): (10,11) (10,12) (11,12) (11,13) (12,13)
    with pytest.raises(InvalidMetricError, match=r"triangle inequality fails on the face \(11, 12, 13\)"):
        EuclideanComplex(X, edge_lengths=[1, 1, 1.2, 5, 1])
    with pytest.raises(NonManifoldError, match=r"\(3, 4\)"):
        EuclideanComplex(SimplicialComplex([(0, 1, 2), (3, 4)]), points=np.zeros((5, 2)))
    with pytest.raises(InvalidParameterError):
        EuclideanComplex(X, points=good).volumes(3)


def test_non_realizable_tetrahedron():
    """Every face satisfies the triangle inequality but no Euclidean tetrahedron has these lengths."""
    X = SimplicialComplex([(0, 1, 2, 3)])
    lengths = np.ones(6)
    lengths[-1] = 1.9          # edge (2, 3); the largest realizable value is sqrt(3)
    with pytest.raises(InvalidMetricError, match="not realizable"):
        EuclideanComplex(X, edge_lengths=lengths)
    lengths[-1] = 1.7
    assert EuclideanComplex(X, edge_lengths=lengths).volumes()[0] > 0
