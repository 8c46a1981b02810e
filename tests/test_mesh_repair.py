"""dhlb.mesh.repair: the meshes people have — non-manifold, doubled, degenerate — repaired, named, mapped back.

A gallery of small defective meshes built here (bowtie vertex, fin edge, doubled fin, two-sided sheet,
zero-area slivers, duplicate face, mixed orientation, Möbius band, duplicate vertices): each repaired,
the field computed, Poincaré–Hopf on the repaired surface and the map back checked. Then soups drawn by
hypothesis (a sphere or a torus with random defects injected): a result or one typed error, never
anything else; mollification never moves a vertex and changes every length by exactly δ. Then the classic
public test models of ``tests/data`` (Suzanne, the beetle, the cow, the teapot; patches of the beast and
the ogre around their defects): the CLI computes fields and stripes with the default options, names the
repairs, and ``--repair none`` keeps the strict messages.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from dhlb.errors import (
    DegenerateSimplexError,
    DhlbError,
    EmptyComplexError,
    InconsistentOrientationError,
    InvalidParameterError,
    InvalidSimplexError,
    MeshRepairWarning,
    NonManifoldError,
    NonOrientableError,
)
from dhlb.fields import FieldOptions, direction_field, prescribed_field
from dhlb.io import read_surface
from dhlb.mesh import RepairOptions, repair_surface, tangent_bundle, validate_surface
from dhlb.stripes import StripeOptions, stripe_pattern
from tests.surface_meshes import icosphere, torus

DATA = os.path.join(os.path.dirname(__file__), "data")

OCTA_V = np.array([[1.0, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]])
OCTA_F = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])


def quiet(fn, *args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fn(*args, **kwargs)


def repaired(V, F, repair="safe", **kw):
    """``repair_surface`` with its warnings, as ``(mesh, {kind: the messages of that kind, joined})``."""
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        mesh = repair_surface(V, F, repair, **kw)
    out: dict[str, str] = {}
    for w in seen:
        if isinstance(w.message, MeshRepairWarning):
            out[w.message.kind] = (out.get(w.message.kind, "") + " | " + str(w.message)).strip(" |")
    return mesh, out


def check_poincare_hopf(res):
    """Σ index = nχ on a closed surface, = (ΣΩ + boundary rotation)/2π with boundary (exactly)."""
    assert res.index_sum == res.poincare_hopf
    if res.mesh.is_closed:
        assert res.index_sum == res.n * res.euler_characteristic


def check_maps(mesh, V, F):
    """Every mesh vertex sits at its input row; every mesh face is its input row's triangle (or its flip)."""
    V = np.asarray(V, float)
    F = np.asarray(F)
    assert np.array_equal(mesh.points, V[mesh.vertex_rows])
    back = mesh.vertex_rows[mesh.faces]
    orig = F[mesh.face_rows]
    orig = np.where(mesh.flipped[:, None], orig[:, [0, 2, 1]], orig)
    if mesh.repair is not None and "merge-vertices" in mesh.repair.kinds:
        return
    assert np.array_equal(back, orig)
    if mesh.repair is not None:
        voi = mesh.repair.vertex_of_input
        used = voi >= 0
        assert np.array_equal(mesh.vertex_rows[voi[used]], np.flatnonzero(used))
        foi = mesh.repair.face_of_input
        kept = foi >= 0
        assert np.array_equal(np.sort(mesh.vertex_rows[mesh.faces[foi[kept]]], axis=1), np.sort(F[kept], axis=1))


# ----------------------------------------------------------------------------- the gallery
def test_clean_meshes_are_untouched_bit_for_bit():
    V, F = icosphere(2)
    with warnings.catch_warnings():
        warnings.simplefilter("error")            # no warning at all
        mesh = repair_surface(V, F)
        strict = validate_surface(V, F)
        a = direction_field(V, F, n=4)
    b = direction_field(V, F, n=4, options=FieldOptions(repair="none"))
    assert mesh.repair is None and mesh.edge_lengths is None
    assert np.array_equal(mesh.faces, strict.faces) and np.array_equal(mesh.points, strict.points)
    assert np.array_equal(a.u, b.u) and a.eigenvalue == b.eigenvalue and a.to_json()["repairs"] == []


def test_bowtie_vertex_is_split_into_one_vertex_per_fan():
    small = OCTA_V * 0.5 + [1.5, 0, 0]            # its vertex 1 lands on (1, 0, 0) = vertex 0 of the big one
    V = np.vstack([OCTA_V, small])
    F2 = OCTA_F + 6
    F2[F2 == 7] = 0                               # two octahedra touching at one point
    F = np.vstack([OCTA_F, F2])
    mesh, w = repaired(V, F)
    assert set(w) == {"split"} and "vertex 0" in str(w["split"]) and mesh.n_vertices == 12
    assert mesh.components[0] == 2 and mesh.euler_characteristic == 4 and mesh.is_closed
    check_maps(mesh, np.vstack([V]), F)
    # the input row 0 speaks with the copy on the big octahedron (the larger fan area)
    v0 = mesh.repair.vertex_of_input[0]
    assert mesh.n_faces == 16 and np.all(np.linalg.norm(mesh.points[mesh.faces[np.any(mesh.faces == v0, 1)]]
                                                        .mean(axis=1), axis=1) < 1.0)
    res = quiet(direction_field, V, F, n=1)
    check_poincare_hopf(res)
    assert res.index_sum == 4
    D = res.input_directions()
    assert np.allclose(D[0], res.directions[v0])


def test_fin_on_an_edge_is_detached():
    V = np.vstack([OCTA_V, [[1.0, 1.0, 1.0]]])
    F = np.vstack([OCTA_F, [[0, 2, 6]]])            # a third face on the edge (0, 2)
    with pytest.raises(NonManifoldError, match="non-manifold edge \\(0, 2\\)"):
        validate_surface(V, F)
    mesh, w = repaired(V, F)
    assert "split" in w and "non-manifold edge" in str(w["split"])
    assert mesh.components[0] == 2 and mesh.n_faces == 9
    check_maps(mesh, V, F)
    res = quiet(direction_field, V, F, n=4)
    check_poincare_hopf(res)


def test_doubled_fin_is_removed_and_the_rest_is_the_clean_mesh():
    V = np.vstack([OCTA_V, [[1.0, 1.0, 1.0]]])
    F = np.vstack([OCTA_F[:1], [[0, 6, 2], [0, 2, 6]], OCTA_F[1:]])   # a triangle and its mirror image on (0, 2)
    mesh, w = repaired(V, F)
    assert set(w) == {"doubled"} and "faces 1, 2" in str(w["doubled"])
    assert np.array_equal(mesh.face_rows, [0, 3, 4, 5, 6, 7, 8, 9]) and mesh.n_vertices == 6
    assert mesh.repair.face_of_input.tolist() == [0, -1, -1, 1, 2, 3, 4, 5, 6, 7]
    a = quiet(direction_field, V, F, n=2)
    b = direction_field(OCTA_V, OCTA_F, n=2)
    assert a.index_sum == b.index_sum == 4 and a.eigenvalue == pytest.approx(b.eigenvalue, rel=1e-12)
    assert np.array_equal(a.input_face_index()[[1, 2]], [0, 0])


def test_a_two_sided_sheet_keeps_one_side():
    V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]])
    F = np.array([[0, 1, 2], [1, 3, 2], [0, 2, 1], [1, 2, 3]])   # both sides of a square
    mesh, w = repaired(V, F)
    assert set(w) == {"doubled"} and "one side" in str(w["doubled"])
    assert mesh.n_faces == 2 and mesh.euler_characteristic == 1
    res = quiet(direction_field, V, F, n=1)
    check_poincare_hopf(res)


def test_duplicate_face_is_merged_and_mapped_back():
    V, F = icosphere(1)
    F2 = np.vstack([F, F[7:8]])
    mesh, w = repaired(V, F2)
    assert set(w) == {"duplicates"} and mesh.n_faces == len(F)
    assert mesh.repair.face_of_input[len(F)] == mesh.repair.face_of_input[7]
    res = quiet(direction_field, V, F2, n=1)
    check_poincare_hopf(res)
    idx = res.input_face_index()
    assert idx.shape == (len(F2),) and idx[len(F)] == idx[7]


def test_mixed_orientation_is_reoriented_per_component():
    V, F = icosphere(1)
    F = F.copy()
    F[[3, 10, 11]] = F[[3, 10, 11], ::-1]
    mesh, w = repaired(V, F)
    assert set(w) == {"reorient"} and mesh.flipped.sum() == 3
    res = quiet(direction_field, V, F, n=4)
    check_poincare_hopf(res)
    assert res.index_sum == 8
    with pytest.raises(InconsistentOrientationError):
        direction_field(V, F, options=FieldOptions(repair="none"))
    with pytest.raises(InconsistentOrientationError, match="reorient"):
        repair_surface(V, F, "split,duplicates")


def test_zero_area_slivers_are_mollified_without_moving_a_vertex():
    # an octahedron whose face (3, 1, 5) is split at a vertex placed on vertex 3, and a collinear sliver
    V = np.vstack([OCTA_V, [[0.0, -1.0, 0.0]]])
    F = np.vstack([OCTA_F[:6], [[3, 6, 5], [6, 1, 5], [3, 1, 6]], OCTA_F[7:]])
    mesh, w = repaired(V, F)
    assert set(w) == {"mollify"} and mesh.is_intrinsic and "no vertex moved" in str(w["mollify"])
    assert np.array_equal(mesh.points, V[mesh.vertex_rows])
    E = mesh.complex.simplices(1)
    L0 = np.linalg.norm(mesh.points[E[:, 1]] - mesh.points[E[:, 0]], axis=1)
    delta = mesh.repair.delta
    assert 0 < delta and np.all(np.abs(mesh.edge_lengths - L0 - delta) <= 1e-15)
    assert np.all(np.isfinite(mesh.geometry.cotan_weights))
    for n in (1, 2, 4):
        res = quiet(direction_field, V, F, n=n)
        check_poincare_hopf(res)
        assert res.index_sum == 2 * n
    tb = tangent_bundle(mesh, n=4)
    assert tb.bundle.degree() == 8
    with pytest.raises(DegenerateSimplexError, match="zero area"):
        direction_field(V, F, options=FieldOptions(repair="none"))


def test_faces_repeating_a_vertex_are_dropped():
    V, F = icosphere(1)
    F2 = np.vstack([F, [[0, 0, 1]]])
    mesh, w = repaired(V, F2)
    assert set(w) == {"degenerate"} and mesh.n_faces == len(F) and mesh.repair.face_of_input[-1] == -1
    with pytest.raises(EmptyComplexError):
        repair_surface(V, [[0, 0, 1], [2, 2, 2]])


def test_moebius_band_is_refused_or_dropped_when_asked():
    V, F = read_surface(os.path.join(DATA, "moebius-160-10.ply"))
    with pytest.raises(NonOrientableError, match="not orientable"):
        direction_field(V, F, n=2)
    with pytest.raises(EmptyComplexError):
        quiet(repair_surface, V, F, "safe,drop-nonorientable")
    W, G = icosphere(1)
    V2 = np.vstack([V, W + [5.0, 0, 0]])
    F2 = np.vstack([F, G + len(V)])
    mesh, w = repaired(V2, F2, "safe,drop-nonorientable")
    assert "drop-nonorientable" in w and mesh.n_faces == len(G)
    res = quiet(direction_field, V2, F2, n=2, options=FieldOptions(repair="safe,drop-nonorientable"))
    check_poincare_hopf(res)
    assert res.index_sum == 4


def test_a_fin_and_a_moebius_band_dropped_together_report_input_rows():
    V, F = read_surface(os.path.join(DATA, "moebius-160-10.ply"))
    W = np.vstack([OCTA_V, [[1.0, 1.0, 1.0]]]) + [5.0, 0, 0]
    G = np.vstack([OCTA_F, [[0, 2, 6]]]) + len(V)           # an octahedron with a fin on the edge (0, 2)
    V2, F2 = np.vstack([V, W]), np.vstack([F, G])
    mesh, w = repaired(V2, F2, "safe,drop-nonorientable")
    assert {"split", "drop-nonorientable"} <= set(w) and mesh.n_faces == 9
    assert str(len(F) + 8) in w["split"]                    # the fin's input row, after the band was dropped
    check_maps(mesh, V2, F2)


def test_duplicate_vertices_are_merged_only_when_asked():
    V, F = icosphere(1)
    V2 = np.vstack([V, V[:1]])                    # row 42 = row 0
    F2 = F.copy()
    F2[np.flatnonzero((F == 0).any(axis=1))[:2]] = np.where(F[(F == 0).any(axis=1)][:2] == 0, len(V),
                                                             F[(F == 0).any(axis=1)][:2])
    cut = direction_field(V2, F2, n=1)            # a valid surface with a slit: no repair needed
    assert cut.mesh.repair is None and not cut.mesh.is_closed
    check_poincare_hopf(cut)
    mesh, w = repaired(V2, F2, "safe,merge-vertices", force=True)
    assert "merge-vertices" in w and "42 → 0" in str(w["merge-vertices"]) and mesh.is_closed
    merged = quiet(direction_field, V2, F2, n=1, options=FieldOptions(repair="safe,merge-vertices"))
    check_poincare_hopf(merged)
    assert merged.index_sum == 2
    assert np.array_equal(merged.input_directions()[len(V)], merged.input_directions()[0])


def test_repair_options_are_checked():
    assert RepairOptions.parse("safe").enabled == ("degenerate", "duplicates", "split", "reorient", "mollify")
    assert RepairOptions.parse("all").merge_vertices and not RepairOptions.parse("none").any
    for bad in ("splt", "safe,none", 3):
        with pytest.raises(InvalidParameterError):
            RepairOptions.parse(bad)
    with pytest.raises(InvalidParameterError, match="did you mean 'mollify'"):
        FieldOptions(repair="molify")
    with pytest.raises(InvalidParameterError):
        StripeOptions(repair="bogus")
    with pytest.raises(InvalidParameterError):
        RepairOptions(split="yes")


def test_curvature_alignment_on_a_repaired_mesh_with_flat_pieces():
    # the beetle's repair cuts off single flat triangles: no principal directions, and λ_t = 0 is their
    # smallest eigenvalue; they get their smoothest field (one warning), the rest is aligned
    V, F = read_surface(os.path.join(DATA, "beetle.obj"))
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        res = direction_field(V, F, n=4, align="curvature")
    lines = [str(w.message) for w in seen if "no alignment on" in str(w.message)]
    assert len(lines) == 1 and "of 19 components" in lines[0]
    check_poincare_hopf(res)
    assert res.guidance is not None and 0 < res.t < 1


def test_stripes_on_a_repaired_mesh_share_the_fields_mesh():
    V, F = read_surface(os.path.join(DATA, "cow.obj"))
    fld = quiet(direction_field, V, F, n=2)
    assert fld.mesh.repair.kinds == ("split",)
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        res = stripe_pattern(V, F, fld, spacing=8.0, n=2)
    assert res.form.mesh is fld.mesh and not [w for w in seen if isinstance(w.message, MeshRepairWarning)]
    assert res.to_json()["repairs"][0]["kind"] == "split"


def test_prescribed_field_on_a_repaired_mesh():
    V = np.vstack([OCTA_V, [[1.0, 1.0, 1.0]]])
    F = np.vstack([OCTA_F[:1], [[0, 6, 2], [0, 2, 6]], OCTA_F[1:]])
    res = quiet(prescribed_field, V, F, n=1, singularities={0: 1, 9: 1})
    assert sorted(res.singularities.input_faces.tolist()) == [0, 9] and res.index_sum == 2


def test_a_repaired_field_reads_back(tmp_path):
    from dhlb.io import read_result
    from dhlb.io.results import write_field_npz

    V = np.vstack([OCTA_V, [[0.0, -1.0, 0.0]]])
    F = np.vstack([OCTA_F[:6], [[3, 6, 5], [6, 1, 5], [3, 1, 6]], OCTA_F[7:]])   # mollified
    small = OCTA_V * 0.5 + [1.5, 0, 0]
    V = np.vstack([V, small])
    F2 = OCTA_F + len(OCTA_V) + 1
    F2[F2 == len(OCTA_V) + 2] = 0                                            # and a bowtie at vertex 0
    F = np.vstack([F, F2])
    res = quiet(direction_field, V, F, n=4)
    assert set(res.mesh.repair.kinds) == {"split", "mollify"}
    back = read_result(write_field_npz(tmp_path / "f.npz", res))
    assert back.mesh.is_intrinsic and np.array_equal(back.mesh.edge_lengths, res.mesh.edge_lengths)
    assert np.abs(back.directions - res.directions).max() < 1e-12 and back.index_sum == res.index_sum == 16
    assert np.array_equal(back.input_face_index(), res.input_face_index())
    data = np.load(tmp_path / "f.npz")
    assert [r["kind"] for r in json.loads(str(data["repairs"]))] == ["split", "mollify"]


# ----------------------------------------------------------------------------- soups drawn by hypothesis
DEFECTS = ("duplicate", "mirror", "flip", "fin", "doubled-fin", "bowtie", "sliver", "repeat", "collapse")


@st.composite
def soups(draw):
    base = draw(st.sampled_from(["sphere", "torus"]))
    V, F = icosphere(1) if base == "sphere" else torus(8, 6)
    V, F = V.copy(), F.copy()
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    kinds = draw(st.lists(st.sampled_from(DEFECTS), min_size=1, max_size=4))
    for kind in kinds:
        f = int(rng.integers(len(F)))
        a, b, c = (int(x) for x in F[f])
        if kind == "duplicate":
            F = np.vstack([F, F[f:f + 1]])
        elif kind == "mirror":
            F = np.vstack([F, F[f:f + 1, ::-1]])
        elif kind == "flip":
            F[f] = F[f, ::-1]
        elif kind in ("fin", "doubled-fin"):
            V = np.vstack([V, V[[a, b, c]].mean(axis=0) + rng.standard_normal(3)])
            fin = [[a, b, len(V) - 1]] + ([[b, a, len(V) - 1]] if kind == "doubled-fin" else [])
            F = np.vstack([F, fin])
        elif kind == "bowtie":
            W, G = icosphere(0)
            off = len(V)
            V = np.vstack([V, V[a] + (W - W[0]) * 0.3])   # a small sphere touching at vertex a
            G = G + off
            G[G == off] = a
            F = np.vstack([F, G])
        elif kind == "sliver":
            V = np.vstack([V, (V[a] + V[b]) / 2])   # a vertex on the edge (a, b): a zero-area face (a, m, b)
            F = np.vstack([F, [[a, len(V) - 1, b]]])
        elif kind == "repeat":
            F = np.vstack([F, [[a, a, b]]])
        elif kind == "collapse":
            V[a] = V[b]                              # two vertices at one position: zero-area faces
    return V, F, kinds


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(soup=soups(), n=st.sampled_from([1, 2, 4]))
def test_random_soups_give_a_result_or_one_typed_error(soup, n):
    V, F, _ = soup
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            res = direction_field(V, F, n=n)
    except DhlbError:
        return                                           # a typed error is an answer
    check_poincare_hopf(res)
    mesh = res.mesh
    check_maps(mesh, V, F)
    assert np.all(np.isfinite(res.u)) and np.all(np.isfinite(res.directions))
    if mesh.edge_lengths is not None:                    # mollified: no vertex moved, every length + δ
        E = mesh.complex.simplices(1)
        L0 = np.linalg.norm(mesh.points[E[:, 1]] - mesh.points[E[:, 0]], axis=1)
        assert np.all(np.abs(mesh.edge_lengths - L0 - mesh.repair.delta) <= 1e-12 * (1 + L0))
    assert res.input_directions().shape == (len(V), n, 3) and res.input_face_index().shape == (len(F),)


# ----------------------------------------------------------------------------- the public test models
MODELS = {   # file: (the repairs made, the strict message of --repair none)
    "suzanne.obj": ({"doubled"}, "faces 269 and 270 are the same triangle"),
    "beetle.obj": ({"split", "reorient"}, "non-manifold edge (56, 62)"),
    "cow.obj": ({"split"}, "non-manifold vertex 253"),
    "teapot.obj": ({"split"}, "non-manifold vertex 66"),
    "beast-fins.obj": ({"doubled"}, "the same triangle"),
    "ogre-slivers.obj": ({"mollify"}, "4 face(s) have zero area"),
}


@pytest.mark.parametrize("name", sorted(MODELS))
def test_public_models_are_repaired_and_poincare_hopf_holds(name):
    kinds, _ = MODELS[name]
    V, F = read_surface(os.path.join(DATA, name))
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        res = direction_field(V, F, n=4)
    assert {w.message.kind for w in seen if isinstance(w.message, MeshRepairWarning)} == kinds
    check_poincare_hopf(res)
    check_maps(res.mesh, V, F)
    assert {r["kind"] for r in res.to_json()["repairs"]} == kinds


def _cli(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "dhlb", *args], capture_output=True, text=True, cwd=cwd,
                          env=dict(os.environ, OPENBLAS_NUM_THREADS="1"), timeout=600)


@pytest.mark.parametrize("name", ["suzanne.obj", "beetle.obj", "ogre-slivers.obj"])
def test_cli_field_and_stripes_run_on_the_models_and_name_the_repairs(name, tmp_path):
    path = os.path.join(DATA, name)
    out = _cli("field", path, "--n", "4", "-o", str(tmp_path / "f"), "--no-png")
    assert out.returncode == 0, out.stderr
    lines = [ln for ln in out.stderr.splitlines() if "repaired the mesh" in ln]
    assert len(lines) == len(MODELS[name][0]) + (name == "beetle.obj")     # the beetle: edges and vertices
    summary = json.loads((tmp_path / "f.json").read_text())
    assert {r["kind"] for r in summary["repairs"]} == MODELS[name][0]
    assert summary["index_sum"] == summary["poincare_hopf"]
    out = _cli("stripes", path, "--spacing", "6", "-o", str(tmp_path / "s"), "--no-png")
    assert out.returncode == 0, out.stderr
    assert "repaired the mesh" in out.stderr
    side = json.loads((tmp_path / "s.json").read_text())
    assert {r["kind"] for r in side["repairs"]} == MODELS[name][0]
    from dhlb.io import read_result

    back = [read_result(str(tmp_path / b)) for b in ("f", "s")]   # both read back on the repaired mesh
    assert back[0].index_sum == summary["index_sum"] and back[1].texture.mesh.n_faces == summary["n_faces"]
    assert back[1].texture.mesh.is_intrinsic == ("mollify" in MODELS[name][0])
    strict = _cli("field", path, "--n", "4", "-o", str(tmp_path / "g"), "--repair", "none")
    assert strict.returncode == 1 and MODELS[name][1] in strict.stderr and not (tmp_path / "g.json").exists()


def test_cli_repair_option_is_checked(tmp_path):
    out = _cli("field", os.path.join(DATA, "suzanne.obj"), "-o", str(tmp_path / "f"), "--repair", "splt")
    assert out.returncode == 2 and "did you mean 'split'" in out.stderr


def test_strict_messages_are_kept_with_repair_none():
    for name, (_, message) in MODELS.items():
        V, F = read_surface(os.path.join(DATA, name))
        with pytest.raises((NonManifoldError, InvalidSimplexError, DegenerateSimplexError)) as err:
            quiet(direction_field, V, F, n=4, options=FieldOptions(repair="none"))
        assert message in str(err.value), name
