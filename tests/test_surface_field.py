"""Globally optimal n-direction fields (issue 5): index sums, singularity placement, alignment, bad input."""

from __future__ import annotations

import os
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb.errors import (
    DegenerateSimplexError,
    DhlbWarning,
    InconsistentOrientationError,
    InvalidSimplexError,
    NonFiniteError,
    NonManifoldError,
    NonOrientableError,
    UnreferencedVertexWarning,
)
from dhlb.fields import FieldOptions, direction_field, energy_matrices, user_guidance
from dhlb.io import example_path, read_surface
from dhlb.linalg import SolverOptions
from dhlb.mesh import tangent_bundle
from tests.surface_meshes import cylinder, ellipsoid, grid, icosphere

DATA = os.path.join(os.path.dirname(__file__), "data")


def data(name):
    return read_surface(os.path.join(DATA, name))


def mean_edge(V, F):
    E = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    return float(np.linalg.norm(V[E[:, 0]] - V[E[:, 1]], axis=1).mean())


# ----------------------------------------------------------------------------- Poincaré–Hopf
CLOSED = {  # name -> (mesh, χ)
    "sphere": (icosphere(2), 2),
    "torus": (read_surface(example_path("torus.obj")), 0),
    "double-torus": (data("double-torus.obj"), -2),
    "3holes": (data("3holes.off"), -4),
    "fertility": (data("fertility.off"), -6),
}


@pytest.mark.parametrize("name", sorted(CLOSED))
@pytest.mark.parametrize("n", [1, 2, 4])
def test_index_sum_on_closed_meshes(name, n):
    (V, F), chi = CLOSED[name]
    tb = tangent_bundle(V, F, n=n)
    assert tb.mesh.euler_characteristic == chi
    for s in (-1.0, 0.0, 1.0):
        res = direction_field(tb, n=n, s=s)
        assert res.euler_characteristic == chi
        assert res.index_sum == n * chi == res.poincare_hopf
        assert int(res.face_index.sum()) == n * chi
        assert int(res.singularities.index.sum()) == n * chi
        assert res.solver["converged"]


def test_rounded_cube_cross_field_has_eight_corner_singularities():
    V, F = data("rounded_cube.obj")
    res = direction_field(V, F, n=4)
    sing = res.singularities
    assert sing.index.tolist() == [1] * 8
    centre = (V.min(axis=0) + V.max(axis=0)) / 2
    d = sing.points - centre
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]) / np.sqrt(3)
    cos = d @ corners.T
    assert sorted(cos.argmax(axis=1).tolist()) == list(range(8))  # one singularity per corner
    assert cos.max(axis=1).min() > 0.999  # on the diagonal through the corner (the rounded part)


A_, B_, C_ = 3.0, 2.0, 1.0
UMBILICS = np.array([[sx * A_ * np.sqrt((A_**2 - B_**2) / (A_**2 - C_**2)), 0.0,
                      sz * C_ * np.sqrt((B_**2 - C_**2) / (A_**2 - C_**2))] for sx in (1, -1) for sz in (1, -1)])


@pytest.mark.parametrize("level, lam", [(3, 0.0), (4, 0.0), (4, -50.0)])
def test_curvature_aligned_line_field_on_ellipsoid_has_the_four_umbilics(level, lam):
    V, F = ellipsoid(level, (A_, B_, C_))
    res = direction_field(V, F, n=2, align="curvature", lam=lam)
    sing = res.singularities
    assert sing.index.tolist() == [1, 1, 1, 1]  # umbilics: ±1/2 line singularities, index +1 for n = 2
    assert res.index_sum == 2 * 2 == res.poincare_hopf
    dist = np.linalg.norm(sing.points[:, None, :] - UMBILICS[None], axis=2)
    assert sorted(dist.argmin(axis=1).tolist()) == [0, 1, 2, 3]
    h = mean_edge(V, F)
    # λ = 0 trades some alignment for smoothness (a small shift); strong alignment pins them down
    assert dist.min(axis=1).max() < (3 * h if lam == 0 else 1.5 * h)
    assert res.guidance.kind == "curvature-max" and 0 < res.t < 1 and res.eigenvalue is None


# ----------------------------------------------------------------------------- boundary
def test_bunny_with_five_holes_satisfies_the_boundary_corrected_sum():
    V, F = data("bunny-7k.obj")
    tb = tangent_bundle(V, F, n=1)
    assert tb.mesh.euler_characteristic == -3 and not tb.mesh.is_closed  # sphere with 5 holes
    for n in (1, 2, 4):
        tbn = tangent_bundle(tb.mesh, n=n)
        for s in (-1.0, 0.0, 1.0):
            res = direction_field(tbn, n=n, s=s)
            assert res.index_sum == res.poincare_hopf  # Σ ind = (Σ Ω + boundary rotation)/2π
            ind = res.indices
            assert ind.poincare_hopf == pytest.approx((ind.total_curvature + ind.boundary_rotation) / (2 * np.pi))
            # Gauss–Bonnet with boundary turning: Σ nσ + n Σ κ = 2π n χ
            assert tbn.total_curvature + tbn.total_boundary_turning == pytest.approx(2 * np.pi * n * -3)
    aligned = direction_field(tb.mesh, n=4, align="boundary", lam=0.0)
    assert aligned.index_sum == aligned.poincare_hopf and aligned.guidance.kind == "boundary"


@pytest.mark.parametrize("n", [1, 2, 4])
def test_boundary_aligned_field_on_a_cylinder_follows_the_boundary(n):
    V, F = cylinder(32, 8)
    for normal in (False, True):
        # strong alignment with the lumped mass (the consistent one oscillates at λ ≪ 0, see the square test)
        res = direction_field(V, F, n=n, align="boundary-normal" if normal else "boundary", lam=-10.0,
                              options=FieldOptions(lumped=True))
        b = res.mesh.is_boundary_vertex
        P = res.mesh.points[b]
        up = np.where(P[:, 2] > 1.0, 1.0, -1.0)[:, None]  # the top circle is traversed clockwise seen from above
        tangent = up * np.stack([P[:, 1], -P[:, 0], 0 * P[:, 0]], axis=1)  # positive boundary orientation
        inward = up * np.array([0.0, 0.0, 1.0]) * -1.0  # the surface is on the left: inward along ∓z
        want = inward * np.ones_like(P) if normal else tangent
        cos = np.einsum("vkd,vd->vk", res.directions[b], want)
        assert np.allclose(cos.max(axis=1), 1.0, atol=1e-12)  # one of the n directions is exactly the guide
        assert res.index_sum == res.poincare_hopf == 0
        if n % 2 == 0:
            # even n: the two boundary circles ask for the same line/cross field, no singularity is needed.
            # (For n = 1 their positive tangents point in opposite directions, so the field must
            # vanish along a whole circle in between: its singular faces are decided by rounding.)
            assert len(res.singularities.faces) == 0


def test_boundary_aligned_cross_field_on_a_square_has_no_singularities():
    V, F = grid(8, 8)
    # the constant axis-aligned cross is tangent to all four sides (the guidance is +1 at the
    # right-angle corners too): no singularity is needed
    res = direction_field(V, F, n=4, align="boundary", lam=-1.0)
    assert len(res.singularities.faces) == 0
    # strong alignment: the consistent mass (not an M-matrix) makes the solve oscillate and creates
    # ±1 pairs, the lumped mass does not
    strong = direction_field(V, F, n=4, align="boundary", lam=-10.0)
    assert len(strong.singularities.faces) > 0 and strong.index_sum == 0
    lumped = direction_field(V, F, n=4, align="boundary", lam=-10.0,
                              options=FieldOptions(lumped=True))
    assert len(lumped.singularities.faces) == 0


def test_user_vectors_3d_and_complex():
    V, F = grid(6, 5)
    vec = np.tile([1.0, 2.0, 0.0], (len(V), 1))
    res = direction_field(V, F, n=1, align=vec, lam=-1.0)
    # a constant field is parallel on a flat mesh: A q = 0, so (A + M) ũ = M q gives ũ = q exactly
    want = vec[0] / np.linalg.norm(vec[0])
    assert np.allclose(res.directions[:, 0], want, atol=1e-12)
    assert res.index_sum == 0 and len(res.singularities.faces) == 0
    tb = tangent_bundle(V, F, n=1)
    values = user_guidance(tb, vec).values
    res_c = direction_field(V, F, n=1, align=values, lam=-1.0)  # the same data as complex values in the frames
    assert np.allclose(res_c.u, res.u, atol=1e-12)
    assert res.guidance.kind == res_c.guidance.kind == "user"


def test_t_of_lambda_is_monotone():
    """Appendix A: t = (1 + ‖ũ‖)⁻¹ decreases from 1 (λ → −∞, pure alignment) to 0 (λ → λ₁, smoothest)."""
    V, F = ellipsoid(3, (A_, B_, C_))
    tb = tangent_bundle(V, F, n=2)
    lam1 = direction_field(tb, n=2).eigenvalue
    lams = lam1 * np.array([-1e4, -100, -10, -1, 0, 0.5, 0.9, 0.99, 0.999])
    fields = [direction_field(tb, n=2, align="curvature", lam=float(lam)) for lam in lams]
    t = np.array([f.t for f in fields])
    assert np.all(np.diff(t) < 0)
    assert t[0] > 0.99 and t[-1] < 0.05
    # the aligned field tends to the smoothest one as λ → λ₁ (energy → λ₁ from above)
    energy = np.array([f.energy for f in fields])
    assert np.all(np.diff(energy) < 0) and energy[-1] == pytest.approx(lam1, rel=1e-3)


# ----------------------------------------------------------------------------- robustness (Fig. 16)
def split_faces(V, F, rng, fraction=0.5):
    """Poor triangulation of the same surface: 1-to-3 splits of random faces at random (skewed) points."""
    pick = rng.random(len(F)) < fraction
    w = rng.dirichlet([0.3, 0.3, 0.3], pick.sum()) * 0.94 + 0.02  # slivers, but no zero area
    P = np.einsum("kp,kpd->kd", w, V[F[pick]])
    p = len(V) + np.arange(pick.sum())
    a, b, c = F[pick].T
    newF = np.concatenate([F[~pick], np.stack([a, b, p], 1), np.stack([b, c, p], 1), np.stack([c, a, p], 1)])
    return np.vstack([V, P]), newF


def test_singularities_are_stable_under_poor_triangulation_and_noise():
    V, F = data("rounded_cube.obj")
    h = mean_edge(V, F)
    ref = direction_field(V, F, n=4).singularities
    rng = np.random.default_rng(7)
    V2, F2 = split_faces(V, F, rng)
    V3 = V + 0.05 * h * rng.standard_normal(V.shape)
    for W, G in ((V2, F2), (V3, F)):
        sing = direction_field(W, G, n=4).singularities
        assert sing.index.tolist() == ref.index.tolist()
        dist = np.linalg.norm(sing.points[:, None, :] - ref.points[None], axis=2)
        assert sorted(dist.argmin(axis=1).tolist()) == list(range(8))  # nearest-neighbour matching
        assert dist.min(axis=1).max() < 2 * h


# ----------------------------------------------------------------------------- components, flat meshes
def test_two_disjoint_spheres_each_get_their_own_field():
    V, F = icosphere(2)
    W = np.vstack([V, V * 0.5 + [3.0, 0, 0]])
    G = np.vstack([F, F + len(V)])
    for n in (1, 2, 4):
        res = direction_field(W, G, n=n)
        assert res.euler_characteristic == 4 and res.index_sum == n * 4 == res.poincare_hopf
        assert len(res.component_eigenvalues) == 2 and res.solver["components"] == 2
        first = res.singularities.faces < len(F)
        assert res.singularities.index[first].sum() == 2 * n == res.singularities.index[~first].sum()
        assert np.all(np.abs(res.u) > 0)  # nowhere zero on either component
        # the smaller sphere has the larger eigenvalue (λ scales like 1/area); M-norm² of each = its area share
        assert res.component_eigenvalues[1] > res.component_eigenvalues[0]
        _, M = energy_matrices(res.tangent, s=0.0)
        mass = [float((res.u[k].conj() @ (M[k][:, k] @ res.u[k])).real) for k in (slice(0, len(V)),
                                                                                   slice(len(V), None))]
        assert mass == pytest.approx([0.8, 0.2], rel=1e-9)


def test_flat_mesh_with_curvature_alignment_warns_and_gives_the_smoothest_field():
    V, F = grid(5, 4)
    with pytest.warns(DhlbWarning, match="flat"):
        res = direction_field(V, F, n=2, align="curvature")
    smooth = direction_field(V, F, n=2)
    assert res.guidance is None and res.eigenvalue == pytest.approx(smooth.eigenvalue, abs=1e-12)
    assert np.all(np.isfinite(res.u)) and np.all(np.isfinite(res.directions))
    assert res.index_sum == res.poincare_hopf


# ----------------------------------------------------------------------------- bad input
SQUARE = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)


# with repair="none" every defect is refused with the messages of dhlb 0.x (the default repairs them:
# tests/test_mesh_repair.py)
STRICT = FieldOptions(repair="none")


def test_non_manifold_edge_and_vertex():
    V = np.vstack([SQUARE, [[0.5, 0.5, 1.0]]])
    with pytest.raises(NonManifoldError, match="non-manifold edge \\(1, 2\\)"):
        direction_field(V, [[0, 1, 2], [1, 3, 2], [1, 2, 4]], options=STRICT)
    bowtie = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0]], float)
    with pytest.raises(NonManifoldError, match="non-manifold vertex 0"):
        direction_field(bowtie, [[0, 1, 2], [0, 3, 4]], options=STRICT)


def test_moebius_strip_is_refused_as_non_orientable():
    V, F = data("moebius-160-10.ply")
    with pytest.raises(NonOrientableError, match="not orientable") as err:
        direction_field(V, F, n=2)
    assert "non-orientable surfaces" in str(err.value) and "future work" in str(err.value)


def test_inconsistent_orientation_offers_reorient():
    V, F = icosphere(1)
    F = F.copy()
    F[3] = F[3, ::-1]
    with pytest.raises(InconsistentOrientationError, match="reorient=True"):
        direction_field(V, F, n=1, options=STRICT)
    res = direction_field(V, F, n=1, options=FieldOptions(reorient=True, repair="none"))
    assert res.mesh.flipped.sum() == 1 and res.index_sum == 2 == res.poincare_hopf


def test_degenerate_and_duplicate_faces_and_nan():
    V = np.vstack([SQUARE, [[2, 0, 0]]])
    with pytest.raises(DegenerateSimplexError, match="zero area"):
        direction_field(V, [[0, 1, 2], [1, 3, 2], [0, 1, 4]], options=STRICT)  # 0, 1, 4 are collinear
    with pytest.raises(DegenerateSimplexError, match="repeats a vertex"):
        direction_field(SQUARE, [[0, 1, 2], [1, 3, 3]], options=STRICT)
    with pytest.raises(InvalidSimplexError, match="faces 0 and 2 are the same triangle"):
        direction_field(SQUARE, [[0, 1, 2], [1, 3, 2], [1, 2, 0]], options=STRICT)
    bad = SQUARE.copy()
    bad[2, 0] = np.nan
    with pytest.raises(NonFiniteError, match="vertex 2"):
        direction_field(bad, [[0, 1, 2], [1, 3, 2]])


def test_unreferenced_vertices_are_compacted_with_a_warning():
    V, F = icosphere(1)
    W = np.vstack([[[9.0, 9, 9]], V, [[np.nan, 0, 0]]])
    with pytest.warns(UnreferencedVertexWarning, match="2 vertices"):
        res = direction_field(W, F + 1, n=2)
    assert res.mesh.n_vertices == len(V) and res.index_sum == 4
    D = res.input_directions()
    assert D.shape == (len(W), 2, 3) and np.isnan(D[[0, -1]]).all() and np.isfinite(D[1:-1]).all()
    ref = direction_field(V, F, n=2)
    assert res.input_face_index().tolist() == ref.face_index.tolist()


def test_no_numpy_warnings_on_good_and_bad_input():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        direction_field(*grid(3, 3), n=4, align="boundary")
        with pytest.raises(DegenerateSimplexError):
            direction_field(SQUARE, [[0, 1, 2], [1, 3, 2], [0, 3, 3]], options=STRICT)


# ----------------------------------------------------------------------------- properties
def perturbed(kind, seed):
    rng = np.random.default_rng(seed)
    V, F = icosphere(1) if kind == "sphere" else grid(4, 4, z=lambda x, y: 0.2 * np.sin(x + y))
    return V + 0.1 * mean_edge(V, F) * rng.standard_normal(V.shape), F


@settings(max_examples=15, deadline=None)
@given(kind=st.sampled_from(["sphere", "disk"]), seed=st.integers(0, 2**32 - 1), n=st.integers(1, 4),
       s=st.floats(-1.0, 1.0))
def test_energy_matrix_is_hermitian_psd(kind, seed, n, s):
    A, M = energy_matrices(*perturbed(kind, seed), n=n, s=s)
    A = A.toarray()
    scale = np.abs(A).max()
    assert np.abs(A - A.conj().T).max() <= 1e-13 * scale
    assert np.linalg.eigvalsh(A).min() >= -1e-10 * scale
    assert np.linalg.eigvalsh(M.toarray()).min() > 0


@settings(max_examples=8, deadline=None)
@given(kind=st.sampled_from(["sphere", "disk"]), seed=st.integers(0, 2**32 - 1), n=st.integers(1, 4),
       s=st.sampled_from([-1.0, -0.5, 0.0, 0.5, 1.0]))
def test_energy_of_the_smoothest_field_is_its_eigenvalue(kind, seed, n, s):
    V, F = perturbed(kind, seed)
    res = direction_field(V, F, n=n, s=s)
    A, M = energy_matrices(V, F, n=n, s=s)
    u = res.u
    assert (u.conj() @ (M @ u)).real == pytest.approx(1.0, rel=1e-10)
    assert res.energy == pytest.approx((u.conj() @ (A @ u)).real, rel=1e-12, abs=1e-14)
    lam = np.linalg.eigvalsh(np.linalg.solve(np.linalg.cholesky(M.toarray()), np.linalg.solve(
        np.linalg.cholesky(M.toarray()), A.toarray()).conj().T).conj().T)[0]
    assert res.eigenvalue == pytest.approx(lam, rel=1e-7, abs=1e-10)
    assert res.energy == pytest.approx(res.eigenvalue, rel=1e-7, abs=1e-10)


@settings(max_examples=8, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 4), s=st.sampled_from([-1.0, 0.0, 1.0]))
def test_indices_do_not_depend_on_the_frames(seed, n, s):
    """Relabelling vertices and rotating face rows changes every frame (a gauge transformation), not the field."""
    V, F = perturbed("sphere", seed)
    rng = np.random.default_rng(seed)
    perm = rng.permutation(len(V))  # new vertex k is old vertex perm[k]
    inv = np.argsort(perm)
    shift = rng.integers(0, 3, len(F))
    F2 = np.take_along_axis(inv[F], (np.arange(3)[None, :] + shift[:, None]) % 3, axis=1)
    a, b = direction_field(V, F, n=n, s=s), direction_field(V[perm], F2, n=n, s=s)
    assert a.index_sum == b.index_sum == 2 * n
    assert a.input_face_index().tolist() == b.input_face_index().tolist()
    # |u| is gauge invariant: the same field up to a global phase
    assert np.allclose(np.abs(a.u[perm]), np.abs(b.u), rtol=1e-6, atol=1e-9)


def test_aligned_field_refuses_lambda_above_the_smallest_eigenvalue():
    from dhlb.errors import InvalidOperatorError

    V, F = grid(6, 6)
    lam1 = direction_field(V, F, n=4, s=0.0).eigenvalue          # a flat square: λ₁ = 0 (parallel fields)
    with pytest.raises(InvalidOperatorError, match="below the smallest eigenvalue"):
        direction_field(V, F, n=4, align="boundary", lam=lam1 + 1.0)


def test_aligned_field_reports_the_backend_it_used():
    from dhlb.fem import available_backends

    V, F = grid(5, 5)
    res = direction_field(V, F, n=4, align="boundary", lam=-1.0)
    assert res.solver["backend"] in available_backends()
    assert direction_field(V, F, n=4, align="boundary", lam=-1.0, solver="superlu").solver["backend"] == "superlu"


@pytest.mark.parametrize("path", [example_path("spot.obj"), os.path.join(os.path.dirname(__file__), "data",
                                                                         "fertility.off")])
def test_default_tolerance_gives_the_singularities_of_a_tight_solve(path):
    """Issue 15 point 4: the scaled default tol places every singularity where a tol = 1e-14 solve does."""
    V, F = read_surface(path)
    default = direction_field(V, F, n=4)
    tight = direction_field(V, F, n=4, solver=SolverOptions(tol=1e-14))
    assert tight.solver["residual"] <= 1e-14 and default.solver["residual"] <= 1e-10
    np.testing.assert_array_equal(default.indices.face_index, tight.indices.face_index)
    assert np.count_nonzero(default.indices.face_index) > 0


@pytest.mark.parametrize(("name", "n"), [("octahedron", 6), ("tetrahedron", 5), ("coarse sphere", 2)])
def test_small_meshes_always_converge(name, n):
    """Issue 19 point 5: these gave ConvergenceError with advice to raise a block_size no API exposed."""
    from dhlb.examples import meshes  # noqa: F401  (the bundled small meshes, if any)

    if name == "octahedron":
        V = np.array([[1.0, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]])
        F = [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]]
    elif name == "tetrahedron":
        V = np.array([[1.0, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]])
        F = [[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]]
    else:
        u, v = np.meshgrid(np.linspace(0.3, np.pi - 0.3, 4), np.linspace(0, 2 * np.pi, 7)[:-1], indexing="ij")
        V = np.c_[np.sin(u).ravel() * np.cos(v).ravel(), np.sin(u).ravel() * np.sin(v).ravel(), np.cos(u).ravel()]
        V = np.vstack([V, [0, 0, 1], [0, 0, -1]])
        F = []
        for i in range(3):
            for j in range(6):
                a, b, c, d = i * 6 + j, i * 6 + (j + 1) % 6, (i + 1) * 6 + j, (i + 1) * 6 + (j + 1) % 6
                F += [[a, c, b], [b, c, d]]
        F += [[24, j, (j + 1) % 6] for j in range(6)] + [[25, 18 + (j + 1) % 6, 18 + j] for j in range(6)]
        F = [f[::-1] for f in F] if np.dot(np.cross(V[F[0][1]] - V[F[0][0]], V[F[0][2]] - V[F[0][0]]),
                                          V[F[0]].mean(axis=0)) < 0 else F
    res = direction_field(V, np.asarray(F), n=n)
    assert res.solver["converged"] and res.index_sum == n * 2


def test_progress_reports_the_phases_only_when_asked(monkeypatch, capsys):
    """Issue 23: progress on stderr for long runs (here forced by a zero threshold), silent by default."""
    pytest.importorskip("tqdm")
    import dhlb._progress as P

    V, F = read_surface(example_path("torus.obj"))
    monkeypatch.setattr(P, "MIN_SECONDS", 0.0)
    direction_field(V, F, n=2)
    assert "direction field" not in capsys.readouterr().err
    direction_field(V, F, n=2, options=FieldOptions(progress=True))
    assert "direction field" in capsys.readouterr().err


@pytest.mark.parametrize("scale", [1e-150, 1e150])
def test_the_answer_does_not_depend_on_the_unit(scale):
    """Issue 19 point 8: a mesh measured in units of 1e∓150 has the same field (geometry and solver are scale-free)."""
    V, F = read_surface(example_path("spot.obj"))
    ref = direction_field(V, F, n=4)
    res = direction_field(V * scale, F, n=4)
    np.testing.assert_array_equal(res.indices.face_index, ref.indices.face_index)
    assert res.eigenvalue * scale**2 == pytest.approx(ref.eigenvalue, rel=1e-12)
    u, u0 = res.u / np.linalg.norm(res.u), ref.u / np.linalg.norm(ref.u)
    assert abs(np.vdot(u0, u)) == pytest.approx(1.0, abs=1e-9)        # the same section up to a global phase
    # and the same directions: the unit normals overflowed (|n|² of 1e300) to zero at 1e150
    assert np.allclose(np.abs(np.einsum("vkd,vkd->vk", res.directions, ref.directions)), 1.0, atol=1e-6)
