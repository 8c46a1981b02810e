"""Option groups: every keyword of dhlb 0.1 still works (with a DeprecationWarning naming the new spelling)
and gives exactly the result of the new spelling; no public function has more than eight parameters."""

from __future__ import annotations

import ast
import pathlib
import textwrap

import numpy as np
import pytest
import scipy.sparse as sp

from dhlb.errors import InvalidParameterError
from dhlb.fields import FieldOptions, direction_field, prescribed_field
from dhlb.linalg import SolverOptions, smallest_eigenpairs, solver_options
from dhlb.mesh import box_tet_mesh
from dhlb.stripes import SectionOptions, StripeOptions, stripe_pattern
from dhlb.stripes.section import unit_section
from dhlb.vortex import FilamentField, VortexOptions, vortex_filaments, vortex_ring

ROOT = pathlib.Path(__file__).resolve().parents[1]
MAX_PARAMETERS = 8

OCTA_V = np.array([[0, 0, 1], [0, 0, -1], [1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0]], float)
OCTA_F = np.array([[0, 2, 4], [0, 4, 3], [0, 3, 5], [0, 5, 2], [1, 4, 2], [1, 3, 4], [1, 5, 3], [1, 2, 5]])


def _grid():
    x, y = np.meshgrid(np.arange(5.0), np.arange(4.0), indexing="ij")
    V = np.stack([x.ravel(), y.ravel(), 0.1 * np.sin(x.ravel() + y.ravel())], 1)
    a = (np.arange(4)[:, None] * 4 + np.arange(3)).ravel()
    F = np.concatenate([np.stack([a, a + 4, a + 5], 1), np.stack([a, a + 5, a + 1], 1)])
    return V, F


def _old(call, keyword, value, spelled):
    """``call(**{keyword: value})`` warns once, naming ``spelled``; returns its result."""
    with pytest.warns(DeprecationWarning) as rec:
        out = call(**{keyword: value})
    messages = [str(w.message) for w in rec if issubclass(w.category, DeprecationWarning)]
    assert any(f"({keyword}=...)" in m and spelled in m for m in messages), messages
    return out


# ----------------------------------------------------------------------------- solver

def _pencil(n=60):
    A = sp.diags([-np.ones(n - 1), np.r_[1, 2 * np.ones(n - 2), 1], -np.ones(n - 1)], [-1, 0, 1]).tocsr()
    return A, sp.identity(n, format="csr")


SOLVER_OLD = {"tol": 1e-12, "maxiter": 500, "backend": "superlu", "block_size": 20, "factor_shift": "floor",
              "seed": 3}


@pytest.mark.parametrize("keyword", sorted(SOLVER_OLD))
def test_smallest_eigenpairs_old_keywords(keyword):
    A, M = _pencil()
    value = SOLVER_OLD[keyword]
    old = _old(lambda **kw: smallest_eigenpairs(A, M, 2, **kw), keyword, value, f"solver=SolverOptions({keyword}=")
    new = smallest_eigenpairs(A, M, 2, solver=SolverOptions(**{keyword: value}))
    assert np.array_equal(old.eigenvalues, new.eigenvalues)
    assert np.array_equal(old.eigenvectors, new.eigenvectors)


def test_solver_shorthand_and_validation():
    A, M = _pencil()
    a = smallest_eigenpairs(A, M, 2, solver="superlu")
    b = smallest_eigenpairs(A, M, 2, solver=SolverOptions(backend="superlu"))
    assert a.backend == b.backend and np.array_equal(a.eigenvectors, b.eigenvectors)
    assert solver_options(None) == SolverOptions()
    with pytest.raises(InvalidParameterError, match="solver must be"):
        smallest_eigenpairs(A, M, 2, solver=3)
    for bad, message in (({"tol": -1.0}, "tol must be a positive number"), ({"maxiter": 0}, "maxiter must be"),
                         ({"seed": -1}, "seed must be"), ({"factor_shift": "x"}, "factor_shift must be"),
                         ({"block_size": 0}, "block_size must be")):
        with pytest.raises(InvalidParameterError, match=message):
            SolverOptions(**bad)
    with pytest.raises(InvalidParameterError, match="block_size must be an integer >= k"):
        smallest_eigenpairs(A, M, 3, solver=SolverOptions(block_size=2))
    assert SolverOptions().replace(tol=1e-9).tol == 1e-9


def test_old_keyword_with_options_object_is_an_error():
    A, M = _pencil()
    with pytest.raises(InvalidParameterError, match="not both"):
        smallest_eigenpairs(A, M, 1, solver=SolverOptions(), tol=1e-9)
    with pytest.raises(InvalidParameterError, match="not both"):
        direction_field(OCTA_V, OCTA_F, options=FieldOptions(), lumped=True)


@pytest.mark.parametrize("call", [
    lambda: smallest_eigenpairs(*_pencil(), 1, bogus=1),
    lambda: direction_field(OCTA_V, OCTA_F, bogus=1),
    lambda: stripe_pattern(*_grid(), np.tile([1.0, 0, 0], (20, 1)), frequency=0.25, bogus=1),
])
def test_unknown_keyword_is_a_type_error(call):
    with pytest.raises(TypeError, match=r"\(\) got an unexpected keyword argument 'bogus'"):
        call()


# ----------------------------------------------------------------------------- fields

FIELD_OLD = {"lumped": ("options", FieldOptions, True), "reorient": ("options", FieldOptions, True),
             "components": ("options", FieldOptions, "largest"), "progress": ("options", FieldOptions, True),
             "backend": ("solver", SolverOptions, "superlu"), "tol": ("solver", SolverOptions, 1e-12)}


@pytest.mark.parametrize("keyword", sorted(FIELD_OLD))
def test_direction_field_old_keywords(keyword):
    group, cls, value = FIELD_OLD[keyword]
    old = _old(lambda **kw: direction_field(OCTA_V, OCTA_F, n=2, **kw), keyword, value,
               f"{group}={cls.__name__}({keyword}=")
    new = direction_field(OCTA_V, OCTA_F, n=2, **{group: cls(**{keyword: value})})
    assert np.array_equal(old.u, new.u) and old.index_sum == new.index_sum == 4


PRESCRIBED_OLD = {k: FIELD_OLD[k] for k in ("reorient", "components", "backend")}


@pytest.mark.parametrize("keyword", sorted(PRESCRIBED_OLD))
def test_prescribed_field_old_keywords(keyword):
    group, cls, value = PRESCRIBED_OLD[keyword]
    sing = {0: 1, 6: 1}
    old = _old(lambda **kw: prescribed_field(OCTA_V, OCTA_F, 1, sing, **kw), keyword, value,
               f"{group}={cls.__name__}({keyword}=")
    new = prescribed_field(OCTA_V, OCTA_F, 1, sing, **{group: cls(**{keyword: value})})
    assert np.array_equal(old.u, new.u) and np.array_equal(old.delta, new.delta)


# ----------------------------------------------------------------------------- stripes

STRIPE_OLD = {  # keyword: (group, value, new options object)
    "energy": ("options", "fem", StripeOptions(energy="fem")),
    "orthogonal": ("options", True, StripeOptions(orthogonal=True)),
    "method": ("options", "extrinsic", StripeOptions(method="extrinsic")),
    "lumped": ("options", True, StripeOptions(lumped=True)),
    "branch_weight": ("options", 0.5, StripeOptions(branch_weight=0.5)),
    "reorient": ("options", True, StripeOptions(reorient=True)),
    "components": ("options", "largest", StripeOptions(components="largest")),
    "warn_aliasing": ("options", False, StripeOptions(warn_aliasing=False)),
    "progress": ("options", True, StripeOptions(progress=True)),
    "section": ("options", "eigenvector", StripeOptions(section=SectionOptions(kind="eigenvector"))),
    "iterations": ("options", 3, StripeOptions(section=SectionOptions(iterations=3))),
    "seed": ("options", 7, StripeOptions(section=SectionOptions(seed=7))),
    "unit_tol": ("options", 0.1, StripeOptions(section=SectionOptions(unit_tol=0.1))),
    "backend": ("solver", "superlu", SolverOptions(backend="superlu")),
    "tol": ("solver", 1e-12, SolverOptions(tol=1e-12)),
    "block_size": ("solver", 5, SolverOptions(block_size=5)),
}
SPELLED = {"section": "section=SectionOptions(kind=", "iterations": "section=SectionOptions(iterations=",
           "seed": "section=SectionOptions(seed=", "unit_tol": "section=SectionOptions(unit_tol="}


@pytest.mark.parametrize("keyword", sorted(STRIPE_OLD))
def test_stripe_pattern_old_keywords(keyword):
    group, value, new_obj = STRIPE_OLD[keyword]
    V, F = _grid()
    X = np.tile([1.0, 0.3, 0.0], (len(V), 1))
    cls = type(new_obj).__name__
    spelled = f"{group}={cls}(" + SPELLED.get(keyword, f"{keyword}=")
    old = _old(lambda **kw: stripe_pattern(V, F, X, frequency=0.3, **kw), keyword, value, spelled)
    new = stripe_pattern(V, F, X, frequency=0.3, **{group: new_obj})
    assert np.array_equal(old.psi, new.psi) and old.section == new.section and old.energy == new.energy
    assert (old.orthogonal is None) == (new.orthogonal is None)


def test_section_options_validate_like_the_function_did():
    with pytest.raises(InvalidParameterError, match="section must be one of"):
        SectionOptions(kind="other")
    with pytest.raises(InvalidParameterError, match="iterations must be between 1 and 100000"):
        SectionOptions(kind="power", iterations=0)
    with pytest.raises(InvalidParameterError, match="unit_tol must be a positive number"):
        SectionOptions(unit_tol=0.0)
    with pytest.raises(InvalidParameterError, match="seed must be an integer or a numpy Generator"):
        SectionOptions(seed=1.5)
    with pytest.raises(InvalidParameterError, match="energy must be one of"):
        StripeOptions(energy="dirichlet")


UNIT_OLD = {"maxiter": ("iterations", 2), "rtol": ("unit_tol", 0.5), "seed": ("seed", 4)}


@pytest.mark.parametrize("keyword", sorted(UNIT_OLD))
def test_unit_section_old_keywords(keyword):
    field, value = UNIT_OLD[keyword]
    A = sp.csr_matrix([[2.0, -1.0, -1.0], [-1.0, 2.0, -1.0], [-1.0, -1.0, 2.0]], dtype=complex)
    M = sp.identity(3, dtype=complex, format="csr")
    solve = sp.linalg.splu((A + 1e-9 * M).tocsc()).solve
    x0 = np.array([1, 1j, -1])
    old = _old(lambda **kw: unit_section(A, M, solve, x0, **kw), keyword, value,
               f"options=SectionOptions({field}=")
    new = unit_section(A, M, solve, x0, options=SectionOptions(**{field: value}))
    assert np.array_equal(old.x, new.x) and old.energies == new.energies


# ----------------------------------------------------------------------------- vortex

VORTEX_OLD = {"order": ("options", VortexOptions, 2), "placement": ("options", VortexOptions, "vertex"),
              "orientation": ("options", VortexOptions, "require"),
              "backend": ("solver", SolverOptions, "superlu"), "tol": ("solver", SolverOptions, 1e-10)}


@pytest.mark.parametrize("keyword", sorted(VORTEX_OLD))
def test_vortex_filaments_old_keywords(keyword):
    group, cls, value = VORTEX_OLD[keyword]
    mesh = box_tet_mesh(4, lower=-1.5, upper=1.5)
    v = FilamentField([vortex_ring(0.8, center=(0.01, 0.02, 0.03), n=24)], 2 * np.pi, core_radius=0.3)
    old = _old(lambda **kw: vortex_filaments(mesh.points, mesh.tets, v, 1.0, **kw), keyword, value,
               f"{group}={cls.__name__}({keyword}=")
    new = vortex_filaments(mesh.points, mesh.tets, v, 1.0, **{group: cls(**{keyword: value})})
    assert np.array_equal(old.psi, new.psi) and len(old.filaments) == len(new.filaments)


def test_vortex_options_validate():
    with pytest.raises(InvalidParameterError, match="placement must be one of"):
        VortexOptions(placement="middle")
    with pytest.raises(InvalidParameterError, match="orientation must be one of"):
        VortexOptions(orientation="flip")
    with pytest.raises(InvalidParameterError):
        VortexOptions(order=0)


# ----------------------------------------------------------------------------- renderers

def _png(path):
    mpimg = pytest.importorskip("matplotlib.image")
    return mpimg.imread(path)


CAMERA_OLD = {"view": (0.2, -1.0, 0.8), "up": (0.0, 1.0, 0.0), "size": (90, 70), "dpi": 50}
FIELD_STYLE_OLD = {"glyph_length": 0.3, "glyph_width": 1.5, "glyph_color": "red", "face_color": (0.5, 0.6, 0.7),
                   "ambient": 0.6, "max_glyphs": 2, "dot_radius": 0.1, "background": "black"}
STRIPE_STYLE_OLD = {"dark": (0.5, 0.0, 0.0), "light": (0.0, 0.5, 0.0), "fn": np.sin, "ambient": 0.6,
                    "max_triangles": 500, "mark_singularities": True, "background": "black"}
FILAMENT_STYLE_OLD = {"line_width": 4.0, "fill": (0.5, 0.5, 0.5), "outline_color": "red", "background": "black"}


def _render_cases():
    from dhlb.render import (
        CONFORMAL_CAMERA,
        FILAMENT_CAMERA,
        Camera,
        FieldStyle,
        FilamentStyle,
        StripeStyle,
        render_conformal_png,
        render_field_png,
        render_filaments_png,
        render_stripes_png,
    )

    def field(path, **kw):
        return render_field_png(path, OCTA_V, OCTA_F, np.tile([1.0, 0, 0], (6, 1)),
                                (OCTA_V[:1] * 1.1, np.array([1])), **kw)

    def stripes(path, **kw):
        res = stripe_pattern(*_grid(), np.tile([1.0, 0.3, 0], (20, 1)), frequency=0.3)
        return render_stripes_png(path, res.texture, **kw)

    def filaments(path, **kw):
        m = box_tet_mesh(2)
        return render_filaments_png(path, [vortex_ring(0.4, center=(0.5, 0.5, 0.5), n=16)], m.points,
                                    m.boundary_faces, **kw)

    def conformal(path, **kw):
        m = box_tet_mesh(2)
        F = m.boundary_faces
        return render_conformal_png(path, m.points, 2 * m.points, F, np.linspace(1, 2, len(F)), **kw)

    cases = []
    for name, fn, cam, style_cls, styles in (("field", field, Camera(), FieldStyle, FIELD_STYLE_OLD),
                                             ("stripes", stripes, Camera(), StripeStyle, STRIPE_STYLE_OLD),
                                             ("filaments", filaments, FILAMENT_CAMERA, FilamentStyle,
                                              FILAMENT_STYLE_OLD),
                                             ("conformal", conformal, CONFORMAL_CAMERA, None, {})):
        for key, value in CAMERA_OLD.items():
            cases.append((name, fn, key, value, "camera=Camera(", {"camera": cam.replace(**{key: value})}))
        for key, value in styles.items():
            cases.append((name, fn, key, value, f"style={style_cls.__name__}(", {"style": style_cls(**{key: value})}))
    return cases


def _case_ids():
    return [f"{name}-{key}" for name, key in
            [(n, k) for n, s in (("field", FIELD_STYLE_OLD), ("stripes", STRIPE_STYLE_OLD),
                                 ("filaments", FILAMENT_STYLE_OLD), ("conformal", {}))
             for k in [*CAMERA_OLD, *s]]]


@pytest.mark.parametrize("index", range(len(_case_ids())), ids=_case_ids())
def test_renderers_old_keywords(index, tmp_path):
    pytest.importorskip("matplotlib")
    _, fn, key, value, spelled, new_kw = _render_cases()[index]
    old = _old(lambda **kw: fn(tmp_path / "old.png", **kw), key, value, spelled + f"{key}=")
    new = fn(tmp_path / "new.png", **new_kw)
    a, b = _png(old), _png(new)
    assert a.shape == b.shape and np.array_equal(a, b)
    if key == "size":
        assert a.shape[:2] == (70, 90)


def test_camera_validates_view_and_cli_import():
    from dhlb.cli.conformal import render_conformal_png as from_cli
    from dhlb.render import Camera, render_conformal_png

    assert from_cli is render_conformal_png
    with pytest.raises(InvalidParameterError, match="view must be a nonzero 3D direction"):
        Camera(view=(0, 0, 0))


# ----------------------------------------------------------------------------- parameter count

def too_many_parameters(source: str, limit: int = MAX_PARAMETERS) -> list[tuple[str, int]]:
    """Public functions and methods of ``source`` with more than ``limit`` parameters (self/cls, ``**kw`` excluded)."""
    out = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and not node.name.startswith("_"):
            a = node.args
            names = [x.arg for x in a.posonlyargs + a.args + a.kwonlyargs if x.arg not in ("self", "cls")]
            if len(names) > limit:
                out.append((node.name, len(names)))
    return out


def test_parameter_checker_catches_a_long_signature():
    snippet = textwrap.dedent("""
        def fine(a, b, c, d, e, f, g, h, **kw): ...
        def long(a, b, c, d, e, f, g, *, h, i): ...
        def _private(a, b, c, d, e, f, g, h, i): ...
        class K:
            def method(self, a, b, c, d, e, f, g, h): ...
            def wide(self, a, b, c, d, e, f, g, h, i): ...
    """)
    assert too_many_parameters(snippet) == [("long", 9), ("wide", 9)]


def test_no_public_function_has_more_than_eight_parameters():
    offenders = [(str(p.relative_to(ROOT)), name, n) for p in sorted((ROOT / "dhlb").rglob("*.py"))
                 for name, n in too_many_parameters(p.read_text(encoding="utf-8"))]
    assert offenders == []
