"""dhlb.strategies: the records agree with dhlb's algorithms, bundles are integral, meshes are valid."""

from __future__ import annotations

import inspect
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import dhlb.strategies as S
from dhlb import SimplicialComplex
from dhlb.bundles import index_sum
from dhlb.errors import InvalidParameterError
from dhlb.examples import projective_plane, torus
from dhlb.mesh import validate_surface
from dhlb.topology import homology, manifold_report
from dhlb.topology.orientation import is_orientable
from tests import strategies as legacy

MANY = settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
SOME = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
ROOT = Path(__file__).resolve().parents[1]


def check_known(k: S.Known):
    X = k.complex
    assert X.dim == k.dim == len(k.homology) - 1
    assert tuple((h.rank, tuple(int(t) for t in h.torsion)) for h in homology(X)) == k.homology
    assert X.euler_characteristic == k.euler_characteristic
    assert k.euler_characteristic == sum((-1) ** i * r for i, r in enumerate(k.betti_numbers))
    assert is_orientable(X) == k.orientable
    if k.dim <= 3:  # (the link checks of manifold_report are slow in dimension 4)
        rep = manifold_report(X)
        assert rep.is_manifold and rep.has_boundary == k.name.startswith("B^")


# ----------------------------------------------------------------------------- Known records
@MANY
@given(S.closed_surfaces())
def test_closed_surfaces_match_dhlb(k):
    check_known(k)


@pytest.mark.parametrize("dim", [1, 2, 3, 4])
def test_closed_manifolds_match_dhlb(dim):
    seen = set()

    @MANY
    @given(S.closed_manifolds(dim))
    def run(k):
        check_known(k)
        seen.add(k.name)

    run()
    assert f"S^{dim}" in seen and (dim == 1 or len(seen) >= 2)


@pytest.mark.parametrize("dim", [1, 2, 3, 4])
def test_balls_match_dhlb(dim):
    @MANY
    @given(S.balls(dim))
    def run(k):
        check_known(k)

    run()


def test_known_filters_and_records():
    k = S.Known(((0, 1, 2),), "B^2", 2, 1, True, ((1, ()), (0, ()), (0, ())))
    assert k.complex.counts == (3, 3, 1) and k.betti_numbers == (1, 0, 0) and k.torsion == ((), (), ())
    assert "B^2" in repr(k)
    names = set()

    @settings(max_examples=30, deadline=None)
    @given(S.closed_surfaces(orientable=False, names=["RP^2", "klein"]))
    def run(k):
        assert not k.orientable
        names.add(k.name)

    run()
    assert names <= {"RP^2", "Klein bottle"}
    with pytest.raises(InvalidParameterError, match="unknown space 'RP\\^5'"):
        S.closed_surfaces(names="RP^5")
    with pytest.raises(InvalidParameterError, match="dim must be"):
        S.closed_manifolds(5)
    with pytest.raises(InvalidParameterError, match="no known"):
        S.closed_manifolds(1, orientable=False)
    with pytest.raises(InvalidParameterError, match="max_moves"):
        S.balls(2, max_moves=-1)


# ----------------------------------------------------------------------------- complexes
@SOME
@given(S.simplicial_complexes(max_dim=3, max_vertices=6))
def test_simplicial_complexes(X):
    assert isinstance(X, SimplicialComplex) and X.dim <= 3 and X.n_vertices <= 6


def test_simplicial_complexes_errors():
    with pytest.raises(InvalidParameterError, match="max_simplices"):
        S.simplicial_complexes(min_simplices=5, max_simplices=2)
    with pytest.raises(InvalidParameterError, match="max_vertices"):
        S.simplicial_complexes(max_vertices=0)


# ----------------------------------------------------------------------------- line bundles
@MANY
@given(st.integers(-5, 5).flatmap(
    lambda d: st.tuples(st.just(d), S.hermitian_line_bundles(S.closed_surfaces(orientable=True), degree=d))))
def test_line_bundles_weil_and_degree(case):
    d, L = case
    assert L.degree() == d
    assert L.check_integrality().tolist() == [d]  # the fundamental cycle with o = +1 on triangle 0


@SOME
@given(S.hermitian_line_bundles(st.one_of(S.closed_manifolds(3, max_moves=1), S.simplicial_complexes(max_dim=3),
                                          S.closed_surfaces(orientable=False))))
def test_line_bundles_are_integral_everywhere(L):
    periods = L.check_integrality()  # raises IntegralityError otherwise
    assert periods.dtype == np.int64
    hol = L.holonomy_angles()
    assert np.allclose(np.exp(1j * hol), np.exp(1j * L.curvature), atol=1e-8)


@MANY
@given(S.hermitian_line_bundles(st.one_of(S.closed_surfaces(), S.closed_manifolds(3, max_moves=1),
                                          S.simplicial_complexes(max_dim=3)), curvature="flat"))
def test_flat_bundles_have_trivial_triangle_holonomy(L):
    assert not L.curvature.any()
    E = L.X.simplices(1)
    if L.X.dim >= 2:
        T = L.X.simplices(2)
        lookup = {tuple(e): i for i, e in enumerate(E.tolist())}
        w = np.angle(L.connection)
        for a, b, c in T.tolist():  # r_ab r_bc r_ca = 1: ω_ab + ω_bc − ω_ac ≡ 0 mod 2π
            h = w[lookup[(a, b)]] + w[lookup[(b, c)]] - w[lookup[(a, c)]]
            assert abs(np.angle(np.exp(1j * h))) < 1e-8


def test_flat_bundles_reach_the_torsion_class():
    X = projective_plane()
    found = set()

    @settings(max_examples=40, deadline=None)
    @given(S.hermitian_line_bundles(X, curvature="flat"))
    def run(L):
        found.add(L.is_isomorphic(type(L).trivial(X)))

    run()
    assert found == {True, False}


@SOME
@given(S.hermitian_line_bundles(degree=None).flatmap(lambda L: st.tuples(st.just(L), S.sections(L, "generic"))))
def test_poincare_hopf_on_drawn_sections(case):
    L, z = case
    assert np.all(z != 0)
    if legacy_is_closed_orientable_surface(L.X):
        assert index_sum(L, z) == L.degree()


def legacy_is_closed_orientable_surface(X):
    rep = manifold_report(X)
    return X.dim == 2 and rep.is_manifold and not rep.has_boundary and is_orientable(X)


def test_line_bundle_errors():
    with pytest.raises(InvalidParameterError, match="curvature"):
        S.hermitian_line_bundles(curvature="exact")
    with pytest.raises(InvalidParameterError, match="flat bundle has degree 0"):
        S.hermitian_line_bundles(curvature="flat", degree=1)
    with pytest.raises(InvalidParameterError, match="closed orientable surface"):
        S.hermitian_line_bundles(projective_plane(), degree=1)
    with pytest.raises(InvalidParameterError, match="Known record"):
        S.connections(X=[(0, 1, 2)])
    with pytest.raises(InvalidParameterError, match="kind"):
        S.sections(torus(), kind="zero")


# ----------------------------------------------------------------------------- cochains, vector bundles
@pytest.mark.parametrize("group", ["Z", "R", "C", "S1", "C*"])
def test_exact_cochains_are_closed(group):
    @settings(max_examples=40, deadline=None)
    @given(S.cochains(k=1, coefficients=group, exact=True))
    def run(w):
        assert w.group == group and w.k == 1 and len(w) == w.complex.n_simplices(1)
        assert w.is_closed()

    run()


@pytest.mark.parametrize("field, metric", [("R", False), ("R", True), ("C", False), ("C", True), ("Z/5", False)])
def test_vector_bundles(field, metric):
    @settings(max_examples=30, deadline=None)
    @given(S.vector_bundles(rank=2, field=field, metric=metric))
    def run(E):
        assert E.rank == 2 and E.metric == metric
        assert E.field == (("GF", 5) if field == "Z/5" else field)
        if metric:
            T = E.transports
            assert np.allclose(np.einsum("eji,ejk->eik", T.conj(), T), np.eye(2), atol=1e-9)

    run()


def test_vector_bundle_errors():
    with pytest.raises(InvalidParameterError, match="prime"):
        S.vector_bundles(field="Z/6")
    with pytest.raises(InvalidParameterError, match="metric"):
        S.vector_bundles(field="Z/5", metric=True)
    with pytest.raises(InvalidParameterError, match="rank"):
        S.vector_bundles(rank=0)


# ----------------------------------------------------------------------------- meshes
@MANY
@given(S.surface_meshes(max_faces=300))
def test_surface_meshes_are_valid(mesh):
    V, F, g = mesh
    M = validate_surface(V, F)  # raises on degenerate, non-manifold or inconsistently oriented input
    assert M.is_closed and M.euler_characteristic == 2 - 2 * g
    assert not np.any(M.flipped)
    vol = np.einsum("ij,ij->i", V[F[:, 0]], np.cross(V[F[:, 1]], V[F[:, 2]])).sum() / 6
    assert vol > 0  # outward orientation
    assert 1 <= len(F) <= 300


@pytest.mark.parametrize("genus, lo, hi", [(0, 50, 80), (1, 100, 200), (2, 0, 300), (3, 0, 500)])
def test_surface_meshes_respect_genus_and_bounds(genus, lo, hi):
    @settings(max_examples=15, deadline=None)
    @given(S.surface_meshes(genus=genus, min_faces=lo, max_faces=hi))
    def run(mesh):
        V, F, g = mesh
        assert g == genus and lo <= len(F) <= hi
        assert validate_surface(V, F).euler_characteristic == 2 - 2 * genus

    run()


def test_surface_mesh_errors():
    with pytest.raises(InvalidParameterError, match="raise max_faces"):
        S.surface_meshes(genus=2, max_faces=99)
    with pytest.raises(InvalidParameterError, match="genus"):
        S.surface_meshes(genus=-1)


# ----------------------------------------------------------------------------- package plumbing
def test_every_public_strategy_has_an_example():
    for name in S.__all__:
        doc = inspect.getdoc(getattr(S, name)) or ""
        assert "Examples" in doc and ">>>" in doc, name


def test_import_without_hypothesis_names_the_extra():
    code = ("import sys; sys.modules['hypothesis'] = None\n"
            "try:\n    import dhlb.strategies\nexcept ImportError as e:\n    print(e)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, cwd=ROOT)
    assert 'pip install ".[strategies]"' in out.stdout and "pip install hypothesis" in out.stdout


def test_legacy_adapters_keep_their_shapes():
    @settings(max_examples=10, deadline=None)
    @given(legacy.closed_surfaces(), legacy.closed_manifolds(3), legacy.balls(2))
    def run(surface, manifold, ball):
        tris, chi, orientable = surface
        assert isinstance(tris, list) and isinstance(chi, int) and isinstance(orientable, bool)
        assert manifold[1] in ("sphere", "torus") and all(len(s) == 4 for s in manifold[0])
        assert all(len(s) == 3 for s in ball)

    run()


# ----------------------------------------------------------------------------- the notebook's counterexample
def test_notebook_counterexample_cell_finds_one():
    nb = json.loads((ROOT / "notebooks" / "11_property_based_verification.ipynb").read_text())
    cells = ["".join(c["source"]) for c in nb["cells"] if c["cell_type"] == "code"]
    target = [c for c in cells if "counterexample" in c and "@given" in c]
    assert target, "the notebook has no counterexample cell"
    ns: dict = {}
    for src in cells:  # the cells are short and run in order; plotting is not used
        exec(compile(src, "notebook", "exec"), ns)
    k = ns["counterexample"]
    assert isinstance(k, S.Known) and k.name in ("RP^2", "T^2", "Klein bottle")
    L = ns["nontrivial"]
    assert L is not None and not L.is_isomorphic(type(L).trivial(k.complex))
    assert ns["k_rp2"].name == "RP^2" and not ns["is_trivial"](ns["L_rp2"])  # the torsion counterexample
