"""stripe_pattern end to end (seed part 2): exact plane waves, continuity, branch points, App. A, Fig. 3, bad input."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import scipy.linalg as sla
from hypothesis import given, settings
from hypothesis import strategies as st

import dhlb.fields as surface
from dhlb.errors import (
    DegenerateSimplexError,
    DhlbWarning,
    InvalidParameterError,
    NonFiniteError,
    NonManifoldError,
    SectionZeroError,
)
from dhlb.fem import bundle_matrices, connection_laplacian, smallest_eigenpairs
from dhlb.fields import direction_vectors, field_indices
from dhlb.geometry import EuclideanComplex
from dhlb.linalg import SolverOptions
from dhlb.mesh import tangent_bundle
from dhlb.stripes import StripeOptions, stripe_form, stripe_matrices, stripe_pattern, texture_coordinates
from dhlb.topology.complex import SimplicialComplex
from tests.surface_meshes import grid, icosphere, torus
from tests.test_stripes_texture import jittered, side_points, twin_sides


def annulus(nr=6, nt=40, r0=1.0, r1=3.0, jitter=0.0, seed=0):
    i, j = np.meshgrid(np.arange(nt), np.arange(nr + 1), indexing="ij")
    t = 2 * np.pi * (i + 0.5 * (j % 2)) / nt
    r = r0 + (r1 - r0) * j / nr
    V = np.stack([r * np.cos(t), r * np.sin(t), 0 * r], -1).reshape(-1, 3)
    idx = lambda a, b: (a % nt) * (nr + 1) + b  # noqa: E731
    i, j = i[:, :nr], j[:, :nr]
    a, b, c, d = idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)
    F = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    inner = (np.arange(len(V)) % (nr + 1) != 0) & (np.arange(len(V)) % (nr + 1) != nr)
    V[inner, :2] += jitter * np.random.default_rng(seed).uniform(-1, 1, (inner.sum(), 2)) * (r1 - r0) / nr
    return V, F


def flat(name, seed):
    if name == "square":
        V, F = grid(6, 5)
        inner = (V[:, 0] > 0) & (V[:, 0] < 6) & (V[:, 1] > 0) & (V[:, 1] < 5)
        V[inner, :2] += 0.3 * np.random.default_rng(seed).uniform(-1, 1, (inner.sum(), 2))
        return V, F
    return annulus(jitter=0.25, seed=seed)


# ---------------------------------------------------------------------- exact answers
@pytest.mark.parametrize("name", ["square", "annulus"])
@pytest.mark.parametrize("n", [1, 2])
@pytest.mark.parametrize("energy", ["cotan", "fem"])
def test_constant_field_on_flat_meshes_gives_the_exact_plane_wave(name, n, energy):
    V, F = flat(name, seed=3)
    rng = np.random.default_rng(1)
    sgn = rng.choice([-1.0, 1.0], len(V)) if n == 2 else np.ones(len(V))
    d = np.array([np.cos(0.4), np.sin(0.4), 0.0])
    res = stripe_pattern(V, F, sgn[:, None] * d, spacing=4.0, n=n, options=StripeOptions(energy=energy),
                         solver=SolverOptions(tol=1e-13))
    mesh = res.mesh
    assert res.zero_faces.size == 0 and res.branch_faces.size == 0
    assert abs(res.eigenvalue) < 1e-9 and res.solver["converged"]
    nu = 2 * np.pi * res.form.frequency[0]
    E = mesh.complex.simplices(1)
    mean_edge = np.mean(np.linalg.norm(mesh.points[E[:, 1]] - mesh.points[E[:, 0]], axis=1))
    assert np.isclose(2 * np.pi / nu, 4.0 * mean_edge)
    faces = np.repeat(np.arange(mesh.n_faces), 5)
    B = rng.dirichlet(np.ones(3), faces.size)
    x = np.einsum("kc,kcd->kd", B, mesh.points[mesh.faces[faces]]) @ d
    alpha = res.evaluate(faces, B)
    sheet = (res.form.corner_sheet[:, 0] * sgn[mesh.vertex_labels[mesh.faces[:, 0]]])[faces]
    phase = np.exp(1j * (sheet * alpha - nu * x))  # α = ±(ν x + c) (mod 2π): linear with spacing 2π/ν
    assert np.allclose(phase, phase[0], atol=1e-10, rtol=0)


def test_orthogonal_pattern_runs_across():
    V, F = flat("square", seed=2)
    res = stripe_pattern(V, F, np.tile([1.0, 0, 0], (len(V), 1)), frequency=0.3, options=StripeOptions(orthogonal=True))
    ort = res.orthogonal
    assert ort is not None and ort.zero_faces.size == 0
    mesh = ort.mesh
    nu = 2 * np.pi * 0.3
    phase = np.exp(1j * (ort.corner_alpha - nu * mesh.points[mesh.faces][:, :, 1] * np.sign(ort.form.directions[0, 1])))
    assert np.allclose(phase, phase[0, 0], atol=1e-10)
    assert "orthogonal" in res.to_json() and res.to_json()["orthogonal"]["zero_faces"] == []


# ---------------------------------------------------------------------- continuity (App. B) of solved patterns
@settings(max_examples=10, deadline=None)
@given(seed=st.integers(0, 2**31), name=st.sampled_from(["sphere", "torus", "cylinder", "grid"]),
       n=st.sampled_from([1, 2]), energy=st.sampled_from(["cotan", "fem"]), t=st.floats(0, 1))
def test_solved_pattern_is_continuous_across_edges_and_inside_singular_faces(seed, name, n, energy, t):
    mesh = jittered(name, seed)
    rng = np.random.default_rng(seed)
    X, sp = rng.normal(size=(mesh.n_vertices, 3)), rng.uniform(2.0, 8.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DhlbWarning)
        try:
            res = stripe_pattern(mesh, None, X, n=n, spacing=sp, options=StripeOptions(energy=energy))
        except InvalidParameterError as err:  # a vertex only in branch triangles: no lift for the fem energy
            assert energy == "fem" and "only in branch triangles" in str(err)
            res = stripe_pattern(mesh, None, X, n=n, spacing=sp, options=StripeOptions(energy="cotan"))
    tex = res.texture
    a, b = twin_sides(mesh)
    for s in (t, 0.0, 1.0):
        va = tex.evaluate(*side_points(a, s))
        vb = tex.evaluate(*side_points(b, 1 - s))
        assert np.allclose(np.cos(va), np.cos(vb), atol=1e-9, rtol=0)
        assert n == 2 or np.allclose(np.sin(va), np.sin(vb), atol=1e-9, rtol=0)
    # inside zero and branch faces: across the cone boundaries (rays m → corner), away from m
    sing = np.concatenate([res.zero_faces, res.branch_faces])
    m = np.full(3, 1 / 3)
    for c in range(3):
        ray = m + np.linspace(0.05, 1.0, 5)[:, None] * (np.eye(3)[c] - m)
        off = 1e-10 * (np.eye(3)[(c + 1) % 3] - np.eye(3)[(c + 2) % 3])
        p, q = np.clip(ray + off, 0, None), np.clip(ray - off, 0, None)
        f = np.repeat(sing, len(ray))
        vp = tex.evaluate(f, np.tile(p / p.sum(1, keepdims=True), (sing.size, 1)))
        vq = tex.evaluate(f, np.tile(q / q.sum(1, keepdims=True), (sing.size, 1)))
        assert np.allclose(np.cos(vp), np.cos(vq), atol=1e-7)


# ---------------------------------------------------------------------- line fields: branch points
def smoothest_line_field(V, F, seed=None):
    tb = tangent_bundle(V, F, n=2)
    if seed is None:
        A, M = bundle_matrices(tb.bundle, tb.geometry, lumped=True)
        u = smallest_eigenpairs(A, M, 1).eigenvectors[:, 0]
    else:
        rng = np.random.default_rng(seed)
        u = rng.normal(size=tb.mesh.n_vertices) + 1j * rng.normal(size=tb.mesh.n_vertices)
    return tb, u


@pytest.mark.parametrize("name,seed", [("sphere", None), ("sphere", 4), ("torus", 5), ("torus", 6)])
def test_branch_triangles_are_the_half_singularities_of_the_line_field(name, seed):
    V, F = icosphere(2) if name == "sphere" else torus(16, 8)
    tb, u = smoothest_line_field(V, F, seed)
    fi = field_indices(tb, u)
    res = stripe_pattern(tb.mesh, None, direction_vectors(tb, u), n=2, spacing=5.0)
    half = fi.face_index % 2 != 0  # index ±1/2 (in units of 1/2)
    assert half.any()
    assert np.array_equal(np.sort(res.branch_faces), np.nonzero(half)[0])
    assert sorted(res.to_json()["branch_faces"]) == sorted(tb.mesh.face_rows[half].tolist())
    if seed is None:
        assert half.sum() == 4 and np.all(fi.face_index[half] == 1)  # the smoothest line field on a sphere


@pytest.mark.skipif(not hasattr(surface, "direction_field"), reason="dhlb.fields.direction_field not available yet")
def test_direction_field_input():
    V, F = icosphere(2)
    fld = surface.direction_field(V, F, n=2)
    res = stripe_pattern(fld, spacing=5.0)
    assert res.n == 2
    half = fld.indices.face_index % 2 != 0
    assert np.array_equal(np.sort(res.branch_faces), np.nonzero(half)[0])
    res2 = stripe_pattern(V, F, fld, spacing=5.0)
    assert np.array_equal(res2.branch_faces, res.branch_faces)
    with pytest.raises(InvalidParameterError, match="line field"):
        stripe_pattern(V, F, fld, spacing=5.0, n=1)


@pytest.mark.parametrize("n", [1, 2])
def test_a_field_on_the_same_arrays_lends_its_mesh_and_its_angles(n, monkeypatch):
    import dataclasses

    import dhlb.stripes.pattern as pattern

    V, F = icosphere(2)
    V, F = np.vstack([[9.0, 9, 9], V]), F + 1      # row 0 unused: the mesh is compacted
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fld = surface.direction_field(V, F, n=n)
    calls = []
    from dhlb.mesh import repair_surface  # what stripe_pattern calls with its default repair="safe"

    monkeypatch.setattr(pattern, "repair_surface", lambda *a, **k: calls.append(1) or repair_surface(*a, **k))
    res = stripe_pattern(V, F, fld, spacing=5.0)
    assert not calls and res.form.mesh is fld.mesh               # validated once, by direction_field
    assert (res.form.tangent is fld.tangent) == (n == 1)
    # the angles arg u / n of the section, not a round trip through 3D vectors: the same pattern
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = stripe_pattern(V, F, fld.input_directions(), spacing=5.0, n=n)
    assert calls == [1] and ref.form.mesh is not fld.mesh
    d = np.mod(res.form.angles - ref.form.angles + np.pi, 2 * np.pi) - np.pi
    assert np.abs(d).max() <= 1e-12 and np.abs(res.form.directions - ref.form.directions).max() <= 1e-12
    assert np.array_equal(res.branch_faces, ref.branch_faces) and np.array_equal(res.zero_faces, ref.zero_faces)
    assert np.abs(res.psi - ref.psi).max() <= 1e-8
    W = V.copy()
    W[5] += 1e-3                                                  # other arrays: validated again
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert stripe_pattern(W, F, fld, spacing=5.0).form.mesh is not fld.mesh
    assert calls == [1, 1]
    u = fld.u.copy()
    u[3] = 0
    with pytest.raises(SectionZeroError, match="vertex 4 is zero"):
        stripe_pattern(V, F, dataclasses.replace(fld, u=u), spacing=5.0)


@pytest.mark.parametrize("kind", ["unit", "power", "eigenvector"])
def test_the_section_reuses_the_eigensolvers_factorization(kind):
    from dhlb.stripes import SectionOptions

    V, F = icosphere(2)
    res = stripe_pattern(V, F, surface.direction_field(V, F, n=1), spacing=5.0,
                         options=StripeOptions(section=SectionOptions(kind=kind)), solver="superlu")
    st = res.solver
    assert st["factorizations"] == 1 and st["solves"] >= 1 and st["section_factorizations"] == 0
    assert st["section_solves"] == (0 if kind == "eigenvector" else res.iteration.iterations)
    assert kind == "eigenvector" or st["section_solves"] >= 1


# ---------------------------------------------------------------------- App. A: conjugate symmetry
def cover_problem(form):
    """The cotan energy and lumped mass of the full complex problem on the double cover K̃ (2N unknowns)."""
    dc = form.double_cover
    N = dc.n_base_vertices
    lifts = dc.face_lifts[~form.is_branch]
    Xr = SimplicialComplex(np.sort(np.concatenate([lifts, np.where(lifts >= N, lifts - N, lifts + N)]), axis=1))
    assert np.array_equal(Xr.vertex_labels, np.arange(2 * N))
    L = dc.bundle
    from dhlb.bundles import HermitianLineBundle
    Lr = HermitianLineBundle(Xr, L.connection[dc.complex.index(1, Xr.simplices(1))],
                             L.curvature[dc.complex.index(2, Xr.simplices(2))])
    geo = EuclideanComplex(Xr, points=dc.points)
    return dc, connection_laplacian(Lr, geo).toarray(), geo.mass_matrix(lumped=True).toarray()


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_conjugate_symmetric_minimizer_appendix_a(seed):
    V, F = icosphere(1)
    tb, u = smoothest_line_field(V, F, seed)
    form = stripe_form(tb, direction_vectors(tb, u), 2, spacing=3.0, warn_aliasing=False)
    assert form.is_branch.any()
    dc, A, M = cover_problem(form)
    P = dc.embedding().toarray()
    # the base cotan energy (branch triangles removed) is the cover energy restricted to conjugate-symmetric ψ̃
    Ab, _Mb, cplx = stripe_matrices(form, "cotan", complex_form=False)
    assert not cplx
    assert np.allclose(Ab.toarray(), 0.5 * (P.conj().T @ A @ P).real, atol=1e-12)
    rng = np.random.default_rng(seed)
    psi = rng.normal(size=2 * dc.n_base_vertices) + 1j * rng.normal(size=2 * dc.n_base_vertices)
    N = dc.n_base_vertices
    T = lambda z: np.conj(np.concatenate([z[N:], z[:N]]))  # noqa: E731  (T ψ = conj(ψ ∘ τ), antilinear)
    E = lambda z: float(np.real(z.conj() @ A @ z))  # noqa: E731
    nrm = lambda z: float(np.real(z.conj() @ M @ z))  # noqa: E731
    psi1, psi2 = 0.5 * (psi + T(psi)), 0.5 * (-1j * psi + T(-1j * psi))
    assert np.allclose(psi, psi1 + 1j * psi2) and np.allclose(T(psi1), psi1) and np.allclose(T(psi2), psi2)
    assert np.isclose(E(T(psi)), E(psi)) and np.isclose(E(psi), E(psi1) + E(psi2))
    assert np.isclose(nrm(psi), nrm(psi1) + nrm(psi2))
    # the minimum over all functions on K̃ equals the minimum over conjugate-symmetric ones
    lam_all, vec = sla.eigh(A, M)
    Mr = 0.5 * (P.conj().T @ M @ P).real
    lam_sym = sla.eigh(Ab.toarray(), Mr, eigvals_only=True)
    assert np.isclose(lam_all[0], lam_sym[0], rtol=1e-10, atol=1e-12)
    w = vec[:, 0]
    parts = [0.5 * (w + T(w)), 0.5 * (-1j * w + T(-1j * w))]
    best = max(parts, key=nrm)
    assert np.isclose(E(best) / nrm(best), lam_all[0], rtol=1e-8)


def test_fem_energy_on_the_cover_equals_the_base_line_bundle_for_oriented_fields():
    mesh = jittered("torus", 3)
    rng = np.random.default_rng(3)
    form = stripe_form(mesh, rng.normal(size=(mesh.n_vertices, 3)), 1, spacing=4.0, warn_aliasing=False)
    for energy in ("cotan", "fem"):
        Ac, Mc, c1 = stripe_matrices(form, energy)
        Ar, Mr, c2 = stripe_matrices(form, energy, complex_form=False)
        assert c1 and not c2
        lc = sla.eigh(Ac.toarray(), Mc.toarray(), eigvals_only=True)[:3]
        lr = sla.eigh(Ar.toarray(), Mr.toarray(), eigvals_only=True)[:6]
        assert np.allclose(np.repeat(lc, 2), lr, rtol=1e-9)  # realification: every eigenvalue twice


# ---------------------------------------------------------------------- Fig. 3: surfaces of revolution
def cone(nu=120, nz=12, r0=3.0, r1=4.0, seed=0):
    i, j = np.meshgrid(np.arange(nu), np.arange(nz + 1), indexing="ij")
    t = 2 * np.pi * (i + 0.5 * (j % 2)) / nu
    r = r0 + (r1 - r0) * j / nz
    V = np.stack([r * np.cos(t), r * np.sin(t), 0.5 * (r - r0)], -1).reshape(-1, 3)
    idx = lambda a, b: (a % nu) * (nz + 1) + b  # noqa: E731
    i, j = i[:, :nz], j[:, :nz]
    a, b, c, d = idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)
    return V, np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])


def ring_windings(psi, nu, nz):
    out = []
    for j in range(nz + 1):
        z = psi[np.arange(nu) * (nz + 1) + j]
        out.append(np.sum(np.angle(np.roll(z, -1) / z)) / (2 * np.pi))
    return np.round(out, 9)


def test_surface_of_revolution_dislocations():
    nu, nz, f = 120, 12, 1.0
    V, F = cone(nu, nz)
    X = np.stack([-V[:, 1], V[:, 0], 0 * V[:, 0]], 1)  # around the axis: stripes along the meridians
    res = stripe_pattern(V, F, X, frequency=f)
    # the minimizer of a rotation-invariant problem is one Fourier mode: a constant number of stripes, no zero
    w = ring_windings(res.psi, nu, nz)
    assert np.all(w == w[0]) and res.zero_faces.size == 0
    # two modes of neighbouring winding k, k+1 mixed (as any symmetry breaking does near their degeneracy):
    A, M, _ = stripe_matrices(res.form)
    ep = smallest_eigenpairs(A, M, 2)
    ks = [ring_windings(ep.eigenvectors[:, q], nu, nz)[0] for q in range(2)]
    assert abs(ks[0] - ks[1]) == 1
    lo, hi = ep.eigenvectors[:, np.argsort(ks)].T
    amp = lambda u, j: np.mean(np.abs(u[np.arange(nu) * (nz + 1) + j]))  # noqa: E731
    j0 = nz // 2
    psi = lo / amp(lo, j0) + hi / amp(hi, j0)
    tex = texture_coordinates(res.form, psi)
    w = ring_windings(psi, nu, nz)
    assert set(w[:j0 - 1]) == {min(ks)} and set(w[j0 + 2:]) == {max(ks)}
    assert tex.zero_faces.size == 1 and abs(tex.zero_index[tex.zero_faces[0]]) == 1  # one edge dislocation
    r_zero = np.linalg.norm(res.mesh.points[res.mesh.faces[tex.zero_faces[0]], :2].mean(0))
    assert abs(r_zero - (3.0 + j0 / nz)) < 2.0 / nz  # ... at the height between the two bands
    count = 2 * np.pi * np.array([3.0, 4.0]) * f  # stripes around the rims: the winding lies between
    assert count[0] - 1 < min(ks) and max(ks) < count[1] + 1


# ---------------------------------------------------------------------- bad input
def test_bad_input_is_named():
    V, F = grid(4, 3)
    X = np.tile([1.0, 0.0, 0.0], (len(V), 1))
    Xz = X.copy()
    Xz[7] = 0
    with pytest.raises(SectionZeroError, match="vertex 7"):
        stripe_pattern(V, F, Xz, frequency=0.2)
    Xz[7] = [0, 0, 1]  # normal to the surface
    with pytest.raises(SectionZeroError, match="vertex 7"):
        stripe_pattern(V, F, Xz, frequency=0.2)
    Xz[7] = np.nan
    with pytest.raises(NonFiniteError, match="vertex 7"):
        stripe_pattern(V, F, Xz, frequency=0.2)
    for bad in (0.0, -1.0):
        with pytest.raises(InvalidParameterError, match="positive"):
            stripe_pattern(V, F, X, frequency=bad)
    freq = np.full(len(V), 0.2)
    freq[5] = -0.1
    with pytest.raises(InvalidParameterError, match="vertex 5"):
        stripe_pattern(V, F, X, frequency=freq)
    with pytest.raises(InvalidParameterError, match="exactly one"):
        stripe_pattern(V, F, X)
    with pytest.raises(InvalidParameterError, match="energy"):
        stripe_pattern(V, F, X, frequency=0.2, options=StripeOptions(energy="dirichlet"))
    with pytest.raises(InvalidParameterError, match="n must be"):
        stripe_pattern(V, F, X, frequency=0.2, n=3)
    with pytest.raises(InvalidParameterError, match="directions"):
        stripe_pattern(V, F, None, frequency=0.2)
    F2 = F.copy()
    F2[3] = [F2[3, 0], F2[3, 0], F2[3, 1]]
    strict = StripeOptions(repair="none")   # the defects below are repaired by default (tests/test_mesh_repair.py)
    with pytest.raises(DegenerateSimplexError, match="face 3"):
        stripe_pattern(V, F2, X, frequency=0.2, options=strict)
    Vn = np.vstack([V, [[0.5, 0.5, 1.0], [0.5, 0.5, -1.0]]])
    Fn = np.vstack([F, [[F[0, 1], F[0, 0], len(V)], [F[0, 1], F[0, 0], len(V) + 1]]])  # 3 faces on an edge
    with pytest.raises(NonManifoldError):
        stripe_pattern(Vn, Fn, np.vstack([X, [[1.0, 0, 0]] * 2]), frequency=0.2, options=strict)


def test_too_high_frequency_warns_and_stays_correct():
    V, F = grid(6, 5)
    X = np.tile([1.0, 0.0, 0.0], (len(V), 1))
    with pytest.warns(DhlbWarning, match="narrower"):
        res = stripe_pattern(V, F, X, frequency=0.8)  # a period of 1.25 edge lengths
    mesh = res.mesh
    nu = 2 * np.pi * 0.8
    assert res.zero_faces.size == 0
    rng = np.random.default_rng(0)
    faces = np.repeat(np.arange(mesh.n_faces), 4)
    B = rng.dirichlet(np.ones(3), faces.size)
    x = np.einsum("kc,kc->k", B, mesh.points[mesh.faces[faces], 0])
    phase = np.exp(1j * (res.evaluate(faces, B) - nu * x))
    assert np.allclose(phase, phase[0], atol=1e-9)


def test_to_json_uses_input_face_rows():
    V, F = torus(12, 6)
    V = np.vstack([[[9.0, 9, 9]], V])  # an unreferenced first row: compact numbering differs from the input
    F = F[::-1] + 1
    rng = np.random.default_rng(2)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = stripe_pattern(V, F, rng.normal(size=(len(V), 3)), spacing=3.0)
    out = res.to_json()
    assert {"zero_faces", "branch_faces", "timings", "eigenvalue", "solver"} <= set(out)
    assert set(out["timings"]) == {"setup", "solve", "section", "texture", "total"}
    assert len(out["zero_faces"]) == res.zero_faces.size > 0
    mesh = res.mesh
    for z, f in zip(out["zero_faces"], res.zero_faces):
        assert sorted(F[z["face"]]) == sorted(mesh.vertex_labels[mesh.faces[f]])
        assert z["index"] == res.zero_index[f] != 0
    assert sum(z["index"] for z in out["zero_faces"]) == 0  # e^{iω̂}: a trivial bundle on a closed surface


def test_an_indefinite_cotan_energy_is_solved_at_a_shift_just_below_its_smallest_eigenvalue():
    # a patch of the ogre where obtuse triangles make the cotan stripe energy indefinite: the Gershgorin
    # bound is far below the smallest eigenvalue; the shift is the first low·10⁻ᵏ where A − σM is definite
    import os

    import scipy.linalg as la

    from dhlb.io import read_surface

    V, F = read_surface(os.path.join(os.path.dirname(__file__), "data", "ogre-obtuse.obj"))
    fld = surface.direction_field(V, F, n=1)
    with pytest.warns(DhlbWarning, match="indefinite.*shift-invert at"):
        res = stripe_pattern(V, F, fld, spacing=6.0)
    A, M, _ = stripe_matrices(res.form, "cotan")
    exact = la.eigh(A.toarray(), M.toarray(), eigvals_only=True)[0]
    assert exact < 0 and res.solver["indefinite"] and res.solver["converged"]
    assert res.eigenvalue == pytest.approx(exact, rel=1e-8)
    assert 10 * exact <= res.solver["shift"] < exact             # within 10x, not at the Gershgorin bound
