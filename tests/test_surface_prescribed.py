"""Fields with prescribed singularities (issue 21): exactness, flatness, the rotation field, minimality, errors."""

from __future__ import annotations

import os
from functools import cache

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from dhlb.errors import InvalidParameterError
from dhlb.fields import locate_faces, prescribed_field
from dhlb.io import example_path, read_surface
from dhlb.mesh import validate_surface
from tests.surface_meshes import cylinder, icosphere

DATA = os.path.join(os.path.dirname(__file__), "data")
MESHES = {"spot": example_path("spot.obj"), "kitten": os.path.join(DATA, "kitten.obj"),
          "double-torus": os.path.join(DATA, "double-torus.obj")}


@cache
def load(name):
    V, F = read_surface(MESHES[name])
    mesh = validate_surface(V, F)
    C = mesh.points[mesh.faces].mean(axis=1)
    h = float(np.linalg.norm(mesh.points[mesh.faces[:, 0]] - mesh.points[mesh.faces[:, 1]], axis=1).mean())
    return V, F, mesh, C, h


@st.composite
def prescriptions(draw, name):
    """Random admissible prescriptions: |k| = 1 on faces at least 4 mean edge lengths apart, Σ k = n χ."""
    _, F, mesh, C, h = load(name)
    n = draw(st.sampled_from([1, 2, 4]))
    total = n * mesh.euler_characteristic
    pairs = draw(st.integers(0, 3))
    ks = [int(np.sign(total))] * abs(total) + [1, -1] * pairs
    seeds = draw(st.lists(st.integers(0, len(F) - 1), min_size=len(ks), max_size=len(ks)))
    chosen = []
    for s in seeds:  # walk from the drawn face to the next one far enough from the chosen ones
        for f in (np.arange(len(F)) + s) % len(F):
            if all(np.linalg.norm(C[f] - C[g]) > 4 * h for g in chosen):
                chosen.append(int(f))
                break
    return n, {int(mesh.face_rows[f]): k for f, k in zip(chosen, ks)}


def _check_exact(name, n, pres):
    V, F, *_ = load(name)
    res = prescribed_field(V, F, n, pres)
    got = dict(zip(res.singularities.input_faces.tolist(), res.singularities.index.tolist()))
    assert got == pres                                     # exactly these faces and indices, no others
    assert res.index_sum == n * res.euler_characteristic == round(res.poincare_hopf)
    assert np.max(np.abs(res.delta)) < np.pi
    assert res.flatness_defect < 1e-10


@pytest.mark.parametrize("name", sorted(MESHES))
def test_random_prescriptions_are_realised_exactly(name):
    @settings(max_examples=10, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
    @given(prescriptions(name))
    def check(case):
        _check_exact(name, *case)

    check()


def test_flat_cylinder_zero_holonomy_gives_a_parallel_field():
    # an intrinsically flat surface (a prism of planar rectangles) with one generator of H₁ around it
    V, F = cylinder(24, 6)
    res = prescribed_field(V, F, 4, {}, holonomy=[0.0])
    assert res.generators.shape[0] == 1 and abs(res.admissible_holonomy[0]) < 1e-12
    assert res.delta_norm < 1e-12 and len(res.singularities.faces) == 0
    assert res.energy < 1e-24                                    # parallel: A u = 0 up to round-off
    cosines = np.sort(res.directions @ np.array([0.0, 0.0, 1.0]), axis=1)   # (N, 4): the cross's angles to the axis
    assert np.max(np.ptp(cosines, axis=0)) < 1e-12               # parallel: the same at every vertex


N_FIXED = 42  # the vertices of icosphere(1): rows 0..41 of every finer icosphere, at the same positions


def _rotation_error(level, weights="cotan"):
    """``h`` and the angle errors of the rotation field: max over far vertices, RMS over far vertices, max
    over the far vertices of icosphere(1) (a point set that is the same on every level)."""
    V, F = icosphere(level)
    V, F = np.asarray(V), np.asarray(F)
    C = V[F].mean(axis=1)
    f0 = int(np.argmax(C[:, 2]))
    f1 = int(np.argmin(np.linalg.norm(C + C[f0], axis=1)))      # the antipodal face
    assert np.allclose(C[f1], -C[f0])
    res = prescribed_field(V, F, 1, {f0: 1, f1: 1}, weights=weights)
    assert res.singularities.input_faces.tolist() == sorted([f0, f1]) and res.weights == weights
    axis = C[f0] / np.linalg.norm(C[f0])
    P, N = res.mesh.points, res.frames[:, 2]
    rot = np.cross(axis, P)
    rot -= np.sum(rot * N, axis=1)[:, None] * N
    far = np.linalg.norm(rot, axis=1) > 0.3                      # away from the two singular faces
    rot = rot[far] / np.linalg.norm(rot[far], axis=1)[:, None]
    d = res.directions[far, 0]
    ang = np.arctan2(np.sum(np.cross(rot, d) * N[far], axis=1), np.sum(rot * d, axis=1))
    ang = np.angle(np.exp(1j * (ang - np.angle(np.exp(1j * ang).mean()))))   # up to one global rotation
    err = np.abs(ang)
    h = np.linalg.norm(P[res.mesh.faces[:, 0]] - P[res.mesh.faces[:, 1]], axis=1).mean()
    at_fixed = err[np.flatnonzero(res.mesh.vertex_labels[far] < N_FIXED)]
    assert at_fixed.size >= 30
    return h, float(err.max()), float(np.sqrt(np.mean(err ** 2))), float(at_fixed.max())


def test_sphere_two_antipodal_plus_one_is_the_rotation_field():
    hs, errs, rms, fixed = map(np.array, zip(*[_rotation_error(level) for level in (2, 3, 4, 5)]))

    def rates(e):
        return np.diff(np.log(e)) / np.diff(np.log(hs))

    # first order, away from the singular faces (docs/fields.md, "Prescribed singularities", measured table):
    # the error at the same points (rates 1.34, 1.14, 1.10) and its RMS (1.11, 1.05, 1.00) hold rate >= 0.9.
    # The max over the far vertices (0.3 from the axis) is attained at that moving cut-off, where the error
    # is the h/ρ tail of the singular faces; its rates oscillate (1.06, 1.10, 0.88) around 1.
    assert np.all(rates(fixed) >= 0.9) and np.all(rates(rms) >= 0.9), (fixed, rates(fixed), rms, rates(rms))
    assert errs[-1] < 1e-2 and np.all(rates(errs) > 0.8), (errs, rates(errs))


def _weighted_codifferential(res):
    X = res.mesh.complex
    d0 = X.coboundary(0).astype(float)
    return d0.T @ (res.edge_weights * res.delta), d0


@pytest.mark.parametrize("name, n, pres", [("kitten", 4, {10: 1, 9000: -1, 15000: 1, 3: -1}),
                                           ("double-torus", 2, {0: -1, 1000: -1, 2000: -1, 3000: -1})])
def test_delta_is_minimal_orthogonal_to_the_corrections_that_change_no_holonomy(name, n, pres):
    V, F, *_ = load(name)
    res = prescribed_field(V, F, n, pres)
    dstar, d0 = _weighted_codifferential(res)
    w = res.edge_weights
    scale = np.sqrt(np.sum(w * res.delta ** 2) * np.sum(w * (d0 @ np.ones(d0.shape[1])) ** 2) + 1.0)
    assert np.max(np.abs(dstar)) < 1e-9 * max(scale, 1.0) * np.sqrt(w.max())
    rng = np.random.default_rng(0)
    for _ in range(3):                                         # ⟨δ, d₀f⟩_W = 0, so any such change is larger
        f = rng.standard_normal(d0.shape[1])
        g = d0 @ f
        assert abs(np.sum(w * res.delta * g)) < 1e-9 * np.sqrt(np.sum(w * g * g)) * res.delta_norm
        assert np.sum(w * (res.delta + 1e-3 * g) ** 2) > res.delta_norm ** 2
    # the conditions themselves: faces (2πk − Ω) and the chosen generator periods
    m = res.mesh
    a, b = m.faces.ravel(), np.roll(m.faces, -1, axis=1).ravel()
    flux = (np.where(a < b, 1.0, -1.0) * res.delta[m.halfedge_edge]).reshape(-1, 3).sum(axis=1)
    assert np.allclose(flux, 2 * np.pi * res.prescribed - n * res.tangent.face_curvature, atol=1e-9)
    assert np.allclose(res.generators @ res.delta, res.holonomy, atol=1e-9)
    rho_hol = res.generators @ res.tangent.transport_angles
    assert np.allclose(np.exp(1j * (rho_hol + res.holonomy)), 1.0, atol=1e-9)   # trivial holonomy


def test_boundary_free_sum_and_poincare_hopf_with_boundary_rotation():
    V, F = read_surface(os.path.join(DATA, "bunny-7k.obj"))
    mesh = validate_surface(V, F)
    assert not mesh.is_closed
    for pres in ({}, {10: 1}, {10: 1, 4000: 1, 6000: -1, 200: 1}):
        res = prescribed_field(V, F, 2, pres)
        assert dict(zip(res.singularities.input_faces.tolist(), res.singularities.index.tolist())) == pres
        assert res.index_sum == sum(pres.values()) == round(res.poincare_hopf)
        assert abs(res.poincare_hopf - res.index_sum) < 1e-9
        assert res.generators.shape[0] == 4                   # 5 boundary loops, genus 0: 2g + b − 1


def test_points_locate_faces_and_to_json():
    V, F, mesh, C, h = load("spot")
    f0, f1 = 100, 4000
    res = prescribed_field(V, F, 1, {tuple(C[f0] + 1e-3 * h): 1, f1: 1})
    assert res.prescribed_singularities == {int(mesh.face_rows[f0]): 1, int(mesh.face_rows[f1]): 1}
    faces, dist = locate_faces(mesh, C[[f0, f1]])
    assert faces.tolist() == [f0, f1] and np.all(dist < 1e-12)
    js = res.to_json()
    assert js["prescribed"] and js["delta_norm"] == res.delta_norm and js["index_sum"] == 2
    assert {"holonomy", "admissible_holonomy", "weights", "flatness_defect"} <= set(js)


def test_locate_faces_matches_brute_force_sampling():
    V, F = icosphere(1)
    mesh = validate_surface(V, F)
    rng = np.random.default_rng(3)
    Q = rng.normal(size=(20, 3)) * 1.3
    faces, dist = locate_faces(mesh, Q)
    T = mesh.points[mesh.faces]
    uv = rng.dirichlet([1, 1, 1], size=4000)
    S = np.einsum("sk,fkd->fsd", uv, T)                        # samples in every face
    for q, f, d in zip(Q, faces, dist):
        ds = np.linalg.norm(S - q, axis=2).min(axis=1)
        assert d <= ds.min() + 1e-12 and d >= ds.min() - 0.05 and ds[f] <= ds.min() + 0.05


@pytest.mark.parametrize("pres, match", [
    ({0: 1}, r"sum to 1.*n·χ = 1·2 = 2"),
    ({0: 1, 1: 1, 2: 1}, r"sum to 3.*n·χ = 1·2 = 2"),
    ({0: 1, 99999: 1}, r"face 99999 is out of range"),
    ({0: 1, 1: 0.5, 2: 0.5}, r"must be an integer"),
    ({0: 2}, r"cannot be realised on one triangle"),
    ({0: True, 500: 1}, r"must be an integer"),
    ({"x": 1, 500: 1}, r"located by a face"),
])
def test_bad_prescriptions_raise(pres, match):
    V, F, *_ = load("spot")
    with pytest.raises(InvalidParameterError, match=match):
        prescribed_field(V, F, 1, pres)


def test_holonomy_must_be_admissible():
    V, F, *_ = load("kitten")
    res = prescribed_field(V, F, 1, {})
    again = prescribed_field(V, F, 1, {}, holonomy=res.holonomy + 2 * np.pi * np.array([1, 0]))
    assert np.allclose(again.holonomy, res.holonomy + [2 * np.pi, 0]) and len(again.singularities.faces) == 0
    assert again.delta_norm > res.delta_norm                  # the default is the closest (smoothest) choice
    with pytest.raises(InvalidParameterError, match=r"holonomy\[0\].*not admissible"):
        prescribed_field(V, F, 1, {}, holonomy=res.holonomy + [0.5, 0])
    with pytest.raises(InvalidParameterError, match="one angle per generator"):
        prescribed_field(V, F, 1, {}, holonomy=[0.0])
    with pytest.raises(InvalidParameterError, match="weights"):
        prescribed_field(V, F, 1, {}, weights="bad")
