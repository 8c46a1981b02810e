"""Options are values that check themselves (issue 39, point 2).

Every option class (``FieldOptions``, ``StripeOptions``, ``SectionOptions``, ``SolverOptions``,
``VortexOptions``) refuses a bad field at construction, and again in ``replace``, with a :mod:`dhlb.errors`
message that names the class and the field; every public entry point refuses an options object of the
wrong kind, or a plain dict, with a message that spells the right call
(:func:`dhlb._deprecation.check_option_group`, run by ``fold_deprecated_kwargs``).
"""

from __future__ import annotations

import dataclasses
import math
import re

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb.errors import DhlbError, InvalidParameterError, InvalidTypeError
from dhlb.fields import FieldOptions, direction_field, prescribed_field
from dhlb.linalg import SolverOptions, available_backends, smallest_eigenpairs, solver_options
from dhlb.stripes import SectionOptions, StripeOptions, stripe_pattern
from dhlb.stripes.section import unit_section
from dhlb.vortex import VortexOptions, vortex_filaments
from tests.surface_meshes import icosphere

CLASSES = (FieldOptions, StripeOptions, SectionOptions, SolverOptions, VortexOptions)

# (class, base keywords, field, bad value, error, words of the message)
BAD = [
    # FieldOptions: flags are real bools, components a known name, repair a known repair
    (FieldOptions, {}, "lumped", "no", InvalidParameterError, ["FieldOptions.lumped must be True or False", "'no'"]),
    (FieldOptions, {}, "lumped", 1, InvalidParameterError, ["FieldOptions.lumped", "True or False"]),
    (FieldOptions, {}, "lumped", None, InvalidParameterError, ["FieldOptions.lumped", "True or False"]),
    (FieldOptions, {}, "reorient", "yes", InvalidParameterError, ["FieldOptions.reorient", "True or False"]),
    (FieldOptions, {}, "progress", 0, InvalidParameterError, ["FieldOptions.progress", "True or False"]),
    (FieldOptions, {}, "components", "larget", InvalidParameterError,
     ["FieldOptions.components", "'all', 'largest'", "did you mean 'largest'"]),
    (FieldOptions, {}, "components", 3, InvalidParameterError, ["FieldOptions.components", "'all', 'largest'"]),
    (FieldOptions, {}, "repair", "sfae", InvalidParameterError, ["unknown repair 'sfae'"]),
    # StripeOptions
    (StripeOptions, {}, "energy", "dirichlet", InvalidParameterError, ["StripeOptions.energy must be one of", "'fem'"]),
    (StripeOptions, {}, "energy", None, InvalidParameterError, ["StripeOptions.energy", "'cotan'"]),
    (StripeOptions, {}, "method", "intrinisic", InvalidParameterError,
     ["StripeOptions.method", "'extrinsic'", "did you mean 'intrinsic'"]),
    (StripeOptions, {}, "orthogonal", "no", InvalidParameterError, ["StripeOptions.orthogonal", "True or False"]),
    (StripeOptions, {}, "lumped", "yes", InvalidParameterError, ["StripeOptions.lumped", "True, False or None"]),
    (StripeOptions, {}, "reorient", 1, InvalidParameterError, ["StripeOptions.reorient", "True or False"]),
    (StripeOptions, {}, "warn_aliasing", "false", InvalidParameterError, ["StripeOptions.warn_aliasing"]),
    (StripeOptions, {}, "progress", None, InvalidParameterError, ["StripeOptions.progress"]),
    (StripeOptions, {}, "components", "Largest", InvalidParameterError,
     ["StripeOptions.components", "did you mean 'largest'"]),
    (StripeOptions, {}, "branch_weight", -0.5, InvalidParameterError, ["StripeOptions.branch_weight", ">= 0"]),
    (StripeOptions, {}, "branch_weight", math.inf, InvalidParameterError, ["StripeOptions.branch_weight", "finite"]),
    (StripeOptions, {}, "branch_weight", math.nan, InvalidParameterError, ["StripeOptions.branch_weight"]),
    (StripeOptions, {}, "branch_weight", "0.5", InvalidParameterError, ["StripeOptions.branch_weight"]),
    (StripeOptions, {}, "branch_weight", True, InvalidParameterError, ["StripeOptions.branch_weight"]),
    (StripeOptions, {}, "section", "power", InvalidParameterError,
     ["StripeOptions.section must be a SectionOptions", "SectionOptions(kind='power')"]),
    (StripeOptions, {}, "section", {"kind": "power"}, InvalidParameterError, ["StripeOptions.section"]),
    (StripeOptions, {}, "repair", "everything", InvalidParameterError, ["unknown repair"]),
    # SectionOptions
    (SectionOptions, {}, "kind", "powr", InvalidParameterError,
     ["SectionOptions.kind", "section must be one of", "did you mean 'power'"]),
    (SectionOptions, {}, "kind", 2, InvalidParameterError, ["SectionOptions.kind", "'unit'"]),
    (SectionOptions, {}, "iterations", 2.5, InvalidParameterError, ["SectionOptions.iterations", "integer"]),
    (SectionOptions, {}, "iterations", True, InvalidParameterError, ["SectionOptions.iterations", "integer"]),
    (SectionOptions, {}, "iterations", -1, InvalidParameterError, ["SectionOptions.iterations"]),
    (SectionOptions, {}, "iterations", 100_001, InvalidParameterError,
     ["SectionOptions.iterations must be between 0 and 100000"]),
    (SectionOptions, {"kind": "power"}, "iterations", 0, InvalidParameterError,
     ["SectionOptions.iterations must be between 1 and 100000", "kind='power'"]),
    (SectionOptions, {}, "seed", -1, InvalidParameterError, ["SectionOptions.seed must be >= 0"]),
    (SectionOptions, {}, "seed", 1.5, InvalidParameterError, ["SectionOptions.seed", "integer or a numpy Generator"]),
    (SectionOptions, {}, "seed", True, InvalidParameterError, ["SectionOptions.seed", "integer or a numpy Generator"]),
    (SectionOptions, {}, "unit_tol", 0.0, InvalidParameterError, ["SectionOptions.unit_tol must be a positive number"]),
    (SectionOptions, {}, "unit_tol", math.inf, InvalidParameterError, ["SectionOptions.unit_tol", "finite"]),
    (SectionOptions, {}, "energy_tol", -1e-3, InvalidParameterError, ["SectionOptions.energy_tol", ">= 0"]),
    (SectionOptions, {}, "energy_tol", math.nan, InvalidParameterError, ["SectionOptions.energy_tol", "finite"]),
    (SectionOptions, {}, "unit_tol", True, InvalidParameterError, ["SectionOptions.unit_tol"]),
    (SectionOptions, {}, "unit_tol", "1e-3", InvalidParameterError, ["SectionOptions.unit_tol"]),
    # SolverOptions
    (SolverOptions, {}, "backend", 42, InvalidTypeError,
     ["SolverOptions.backend must be a backend name", "'superlu'", "'auto'", "factorize", "got 42 (int)"]),
    (SolverOptions, {}, "backend", ["superlu"], InvalidTypeError, ["SolverOptions.backend", "'superlu'"]),
    (SolverOptions, {}, "backend", "superLU", InvalidParameterError,
     ["SolverOptions.backend", "unknown backend 'superLU'", "did you mean 'superlu'"]),
    (SolverOptions, {}, "tol", 0.0, InvalidParameterError, ["SolverOptions.tol must be a positive number"]),
    (SolverOptions, {}, "tol", -1e-9, InvalidParameterError, ["SolverOptions.tol"]),
    (SolverOptions, {}, "tol", 1.0, InvalidParameterError, ["SolverOptions.tol", "below 1"]),
    (SolverOptions, {}, "tol", math.nan, InvalidParameterError, ["SolverOptions.tol"]),
    (SolverOptions, {}, "tol", True, InvalidParameterError, ["SolverOptions.tol"]),
    (SolverOptions, {}, "tol", "1e-9", InvalidParameterError, ["SolverOptions.tol"]),
    (SolverOptions, {}, "maxiter", 0, InvalidParameterError, ["SolverOptions.maxiter must be an integer >= 1"]),
    (SolverOptions, {}, "maxiter", 10.0, InvalidParameterError, ["SolverOptions.maxiter"]),
    (SolverOptions, {}, "maxiter", True, InvalidParameterError, ["SolverOptions.maxiter"]),
    (SolverOptions, {}, "block_size", 0, InvalidParameterError, ["SolverOptions.block_size must be an integer >= 1"]),
    (SolverOptions, {}, "block_size", 24.0, InvalidParameterError, ["SolverOptions.block_size"]),
    (SolverOptions, {}, "factor_shift", "flor", InvalidParameterError,
     ["SolverOptions.factor_shift", "'auto', 'floor'", "did you mean 'floor'"]),
    (SolverOptions, {}, "factor_shift", None, InvalidParameterError, ["SolverOptions.factor_shift"]),
    (SolverOptions, {}, "seed", -1, InvalidParameterError, ["SolverOptions.seed must be an integer >= 0"]),
    (SolverOptions, {}, "seed", np.bool_(True), InvalidParameterError, ["SolverOptions.seed"]),
    # VortexOptions
    (VortexOptions, {}, "order", 0, InvalidParameterError, ["VortexOptions.order must be an integer between 1 and 64"]),
    (VortexOptions, {}, "order", 65, InvalidParameterError, ["VortexOptions.order", "between 1 and 64"]),
    (VortexOptions, {}, "order", 4.0, InvalidParameterError, ["VortexOptions.order"]),
    (VortexOptions, {}, "order", True, InvalidParameterError, ["VortexOptions.order"]),
    (VortexOptions, {}, "placement", "middle", InvalidParameterError,
     ["VortexOptions.placement must be one of 'balanced', 'vertex'"]),
    (VortexOptions, {}, "orientation", "fixed", InvalidParameterError,
     ["VortexOptions.orientation", "did you mean 'fix'"]),
]


def _bad_id(case):
    cls, base, name, value, *_ = case
    return f"{cls.__name__}-{name}={value!r}" + ("-" + ",".join(map(str, base.values())) if base else "")


@pytest.mark.parametrize("case", BAD, ids=[_bad_id(c) for c in BAD])
def test_bad_field_is_refused_at_construction_and_by_replace(case):
    cls, base, name, value, error, words = case
    with pytest.raises(error) as info:
        cls(**base, **{name: value})
    assert isinstance(info.value, DhlbError) and isinstance(info.value, ValueError)
    for word in words:
        assert word in str(info.value), (word, str(info.value))
    with pytest.raises(error) as again:                  # dataclasses.replace runs __post_init__ again
        cls(**base).replace(**{name: value})
    assert str(again.value) == str(info.value)


def test_every_field_has_a_bad_value_in_the_table():
    covered = {(cls, name) for cls, _, name, *_ in BAD}
    fields = {(cls, f.name) for cls in CLASSES for f in dataclasses.fields(cls)}
    assert fields == covered, sorted((c.__name__, n) for c, n in fields - covered)


# ------------------------------------------------------------------------------ the failures of the issue

def test_a_truthy_string_is_not_a_flag():
    """``FieldOptions(lumped="no")`` meant lumped (a non-empty string is true)."""
    with pytest.raises(InvalidParameterError, match=r"^FieldOptions\.lumped must be True or False, got 'no'$"):
        FieldOptions(lumped="no")


def test_a_non_string_backend_is_a_dhlb_error_naming_the_field_and_the_backends():
    """``SolverOptions(backend=42)`` was a plain TypeError at the solve (still a TypeError: InvalidTypeError)."""
    with pytest.raises(InvalidTypeError) as info:
        SolverOptions(backend=42)
    assert isinstance(info.value, TypeError)
    for name in available_backends():
        assert repr(name) in str(info.value)


def test_a_stripe_options_passed_to_direction_field_is_refused():
    V, F = icosphere(0)
    with pytest.raises(InvalidParameterError) as info:
        direction_field(V, F, options=StripeOptions())
    message = str(info.value)
    assert message.startswith("direction_field: options must be a FieldOptions, e.g. options=FieldOptions(")
    assert message.endswith("got StripeOptions(...)")


# ------------------------------------------------------------------------------ hypothesis: bad values

NOT_A_BOOL = st.one_of(st.none(), st.integers(), st.floats(), st.text(max_size=5), st.lists(st.booleans(), max_size=2))
FLAGS = [(FieldOptions, n) for n in ("lumped", "reorient", "progress")] + \
        [(StripeOptions, n) for n in ("orthogonal", "reorient", "warn_aliasing", "progress")]


@pytest.mark.parametrize(("cls", "name"), FLAGS, ids=[f"{c.__name__}.{n}" for c, n in FLAGS])
@settings(max_examples=15)
@given(value=NOT_A_BOOL)
def test_a_flag_is_a_bool(cls, name, value):
    with pytest.raises(InvalidParameterError, match=rf"^{cls.__name__}\.{name} must be True or False"):
        cls(**{name: value})


NAMES = [(FieldOptions, "components", ("all", "largest")), (StripeOptions, "components", ("all", "largest")),
         (StripeOptions, "energy", ("cotan", "fem")), (StripeOptions, "method", ("intrinsic", "extrinsic")),
         (SectionOptions, "kind", ("unit", "eigenvector", "power")), (SolverOptions, "factor_shift", ("auto", "floor")),
         (VortexOptions, "placement", ("balanced", "vertex")), (VortexOptions, "orientation", ("fix", "require"))]


@pytest.mark.parametrize(("cls", "name", "known"), NAMES, ids=[f"{c.__name__}.{n}" for c, n, _ in NAMES])
@settings(max_examples=15)
@given(value=st.one_of(st.text(max_size=12), st.integers(), st.none()))
def test_a_name_is_one_of_the_known_names(cls, name, known, value):
    if value in known:
        assert getattr(cls(**{name: value}), name) == value
        return
    with pytest.raises(InvalidParameterError) as info:
        cls(**{name: value})
    assert f"{cls.__name__}.{name}" in str(info.value) and all(repr(k) in str(info.value) for k in known)


# (class, field, valid predicate on a finite float, integer-only)
NUMBERS = [(SolverOptions, "tol", lambda x: 0 < x < 1, False),
           (SectionOptions, "unit_tol", lambda x: x > 0, False),
           (SectionOptions, "energy_tol", lambda x: x >= 0, False),
           (StripeOptions, "branch_weight", lambda x: x >= 0, False),
           (SolverOptions, "maxiter", lambda x: x >= 1, True),
           (SolverOptions, "block_size", lambda x: x >= 1, True),
           (SolverOptions, "seed", lambda x: x >= 0, True),
           (VortexOptions, "order", lambda x: 1 <= x <= 64, True),
           (SectionOptions, "iterations", lambda x: 0 <= x <= 100_000, True)]


@pytest.mark.parametrize(("cls", "name", "valid", "integer"), NUMBERS,
                         ids=[f"{c.__name__}.{n}" for c, n, *_ in NUMBERS])
@settings(max_examples=20)
@given(value=st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-10**6, 10**6),
                       st.booleans(), st.text(max_size=4)))
def test_a_number_is_finite_and_in_range(cls, name, valid, integer, value):
    is_int = isinstance(value, int) and not isinstance(value, bool)
    is_real = isinstance(value, (int, float)) and not isinstance(value, bool)
    ok = (is_int if integer else is_real) and math.isfinite(value) and valid(float(value))
    if ok:
        assert getattr(cls(**{name: value}), name) == value
    else:
        with pytest.raises(InvalidParameterError, match=rf"^{cls.__name__}\.{name}"):
            cls(**{name: value})


# ------------------------------------------------------------------------------ valid values stay valid

class _Backend:
    name = "mine"

    def factorize(self, K, positive_definite=False):
        return sp.linalg.splu(sp.csc_matrix(K))


@pytest.mark.parametrize("make", [
    lambda: FieldOptions(lumped=np.True_, reorient=np.False_, progress=True, components="largest", repair="none"),
    lambda: StripeOptions(lumped=None, branch_weight=np.float64(0.5), energy="fem", method="extrinsic"),
    lambda: StripeOptions(lumped=np.bool_(True), branch_weight=2, section=SectionOptions(kind="power")),
    lambda: SectionOptions(kind="unit", iterations=np.int64(0), seed=np.random.default_rng(1),
                           unit_tol=np.float32(0.5), energy_tol=0),
    lambda: SectionOptions(kind="power", iterations=1, seed=2**70),
    lambda: SolverOptions(backend="auto", tol=0.5, maxiter=np.int32(1), block_size=1, factor_shift="floor",
                          seed=np.uint8(3)),
    lambda: SolverOptions(backend="cholmod"),          # registered; whether it is installed: checked by the solve
    lambda: SolverOptions(backend=_Backend(), tol=np.float64(1e-12)),
    lambda: VortexOptions(order=np.int16(64), placement="vertex", orientation="require"),
], ids=["field", "stripe", "stripe-numpy", "section-unit", "section-power", "solver", "solver-cholmod",
        "solver-object", "vortex"])
def test_valid_values_construct_and_replace(make):
    opts = make()
    assert opts.replace() == opts


def test_defaults_are_unchanged():
    assert repr(FieldOptions()) == ("FieldOptions(lumped=False, reorient=False, components='all', progress=False, "
                                    "repair='safe')")
    assert repr(SolverOptions()) == ("SolverOptions(backend=None, tol=None, maxiter=1000, block_size=None, "
                                     "factor_shift='auto', seed=0)")
    assert repr(VortexOptions()) == "VortexOptions(order=4, placement='balanced', orientation='fix')"
    assert repr(SectionOptions()) == ("SectionOptions(kind='unit', iterations=None, seed=None, unit_tol=0.001, "
                                        "energy_tol=0.001)")
    assert StripeOptions().section == SectionOptions() and StripeOptions().lumped is None


def test_a_solve_with_a_backend_object_still_works():
    A = sp.diags([2.0, 3.0, 5.0], format="csr")
    res = smallest_eigenpairs(A, sp.identity(3, format="csr"), 1, solver=SolverOptions(backend=_Backend()))
    assert np.isclose(res.eigenvalues[0], 2.0)


# ------------------------------------------------------------------------------ entry points

@pytest.fixture(scope="module")
def sphere():
    return icosphere(0)


def _refused(call, *words):
    with pytest.raises(InvalidParameterError) as info:
        call()
    for word in words:
        assert word in str(info.value), (word, str(info.value))
    return str(info.value)


def test_direction_field_refuses_other_options_and_dicts(sphere):
    V, F = sphere
    _refused(lambda: direction_field(V, F, options=StripeOptions(lumped=True)),
             "direction_field: options must be a FieldOptions", "e.g. options=FieldOptions(lumped=True)",
             "got StripeOptions(...)")
    _refused(lambda: direction_field(V, F, options={"lumped": True}),
             "direction_field: options must be a FieldOptions, not a dict", "write options=FieldOptions(lumped=True)")
    _refused(lambda: direction_field(V, F, options={"lumped": "no"}),
             "write options=FieldOptions(lumped='no')", "refused too: FieldOptions.lumped must be True or False")
    _refused(lambda: direction_field(V, F, solver=FieldOptions()),
             "direction_field: solver must be a SolverOptions or a backend name", "e.g. solver=SolverOptions(",
             "got FieldOptions(...)")
    _refused(lambda: direction_field(V, F, options="lumped"), "got 'lumped' (str)")


def test_direction_field_deprecated_keyword_is_validated(sphere):
    V, F = sphere
    with pytest.warns(DeprecationWarning), pytest.raises(InvalidParameterError, match=r"FieldOptions\.lumped"):
        direction_field(V, F, lumped="no")


def test_prescribed_field_refuses_other_options(sphere):
    V, F = sphere
    _refused(lambda: prescribed_field(V, F, 1, {0: 1, 5: 1}, options=VortexOptions()),
             "prescribed_field: options must be a FieldOptions", "got VortexOptions(...)")


def test_stripe_pattern_refuses_other_options_and_dicts(sphere):
    V, F = sphere
    X = np.tile([1.0, 0.0, 0.0], (len(V), 1))
    _refused(lambda: stripe_pattern(V, F, X, frequency=1.0, options=FieldOptions()),
             "stripe_pattern: options must be a StripeOptions", "e.g. options=StripeOptions(energy='fem')",
             "got FieldOptions(...)")
    _refused(lambda: stripe_pattern(V, F, X, frequency=1.0, options={"energy": "fem", "section": {"kind": "power"}}),
             "not a dict", "write options=StripeOptions(energy='fem', section=SectionOptions(kind='power'))")
    _refused(lambda: stripe_pattern(V, F, X, frequency=1.0, solver={"tol": 1e-9}),
             "stripe_pattern: solver must be a SolverOptions", "write solver=SolverOptions(tol=1e-09)")
    with pytest.warns(DeprecationWarning), pytest.raises(InvalidParameterError, match=r"SectionOptions\.kind"):
        stripe_pattern(V, F, X, frequency=1.0, section="powr")


def test_smallest_eigenpairs_refuses_dicts_and_keeps_the_shorthand():
    A, M = sp.diags([2.0, 3.0, 5.0], format="csr"), sp.identity(3, format="csr")
    _refused(lambda: smallest_eigenpairs(A, M, 1, solver={"tol": 1}),
             "smallest_eigenpairs: solver must be a SolverOptions", "write solver=SolverOptions(tol=1)",
             "refused too: SolverOptions.tol")
    _refused(lambda: smallest_eigenpairs(A, M, 1, solver=3), "solver must be", "got 3 (int)")
    _refused(lambda: smallest_eigenpairs(A, M, 1, solver="superLU"), "did you mean 'superlu'")
    assert smallest_eigenpairs(A, M, 1, solver="superlu").eigenvalues[0] == pytest.approx(2.0)
    _refused(lambda: solver_options({"tol": 1e-9}), "write solver=SolverOptions(**{'tol': 1e-09})")


def test_vortex_filaments_and_unit_section_refuse_other_options():
    _refused(lambda: vortex_filaments(None, None, None, 1.0, options=FieldOptions()),
             "vortex_filaments: options must be a VortexOptions", "e.g. options=VortexOptions(order=6)")
    _refused(lambda: vortex_filaments(None, None, None, 1.0, solver=VortexOptions(order=2)),
             "vortex_filaments: solver must be a SolverOptions")
    _refused(lambda: unit_section(None, None, None, None, options=StripeOptions()),
             "unit_section: options must be a SectionOptions", "e.g. options=SectionOptions(kind='eigenvector')")


def test_renderers_refuse_a_style_as_camera():
    from dhlb.render import Camera, FieldStyle, render_field_png

    _refused(lambda: render_field_png("x.png", None, None, camera=FieldStyle()),
             "render_field_png: camera must be a Camera", "got FieldStyle(...)")
    _refused(lambda: render_field_png("x.png", None, None, camera=Camera(), style={"glyph_color": "red"}),
             "write style=FieldStyle(glyph_color='red')")


# ------------------------------------------------------------------------------ the helpers

def test_check_option_group_accepts_instances_subclasses_and_shorthands():
    from dhlb._deprecation import check_option_group

    @dataclasses.dataclass(frozen=True)
    class Knobs:
        tol: float = 1e-9

    class Finer(Knobs):
        pass

    check_option_group("f", "knobs", Knobs(), Knobs())
    check_option_group("f", "knobs", Finer(), Knobs())
    check_option_group("f", "solver", "superlu", SolverOptions())
    with pytest.raises(InvalidParameterError, match=r"^f: knobs must be a Knobs, e\.g\. knobs=Knobs\(\); got 1\.5"):
        check_option_group("f", "knobs", 1.5, Knobs())
    with pytest.raises(InvalidParameterError, match="not a dict"):
        check_option_group("f", "knobs", {"tol": 1e-3}, Knobs())
    with pytest.raises(InvalidParameterError, match=r"e\.g\. knobs=Knobs"):      # keys that are not names
        check_option_group("f", "knobs", {1: 2}, Knobs())


def test_did_you_mean():
    from dhlb._deprecation import did_you_mean

    assert did_you_mean("superLU", ["superlu", "cholmod"]) == "; did you mean 'superlu'?"
    assert did_you_mean("zzz", ["superlu"]) == "" and did_you_mean(3, ["superlu"]) == ""


# ----------------------------------------------------------------------------- the picture styles
STYLE_CASES = [  # (class name, field, bad value, words of the message)
    ("FieldStyle", "glyph_length", -1.0, "finite number > 0"), ("FieldStyle", "glyph_width", float("nan"), "> 0"),
    ("FieldStyle", "glyph_color", "no-such-colour", "matplotlib colour"), ("FieldStyle", "ambient", 1.5, "[0, 1]"),
    ("FieldStyle", "max_glyphs", 0, ">= 1"), ("FieldStyle", "dot_radius", "big", "> 0"),
    ("FieldStyle", "background", 42, "matplotlib colour"), ("StripeStyle", "dark", (2.0, 0, 0), "colour"),
    ("StripeStyle", "fn", "cos", "function"), ("StripeStyle", "max_triangles", 2.5, "integer"),
    ("StripeStyle", "mark_singularities", "yes", "True or False"), ("FilamentStyle", "line_width", 0, "> 0"),
    ("FilamentStyle", "fill", None, "colour"), ("ConformalStyle", "colormap", "viridiss", "did you mean"),
    ("ConformalStyle", "colormap", 3, "colormap"),
]


@pytest.mark.parametrize("cls, field, bad, words", STYLE_CASES)
def test_picture_styles_check_their_fields(cls, field, bad, words):
    import dhlb.render as render

    style = getattr(render, cls)
    with pytest.raises(InvalidParameterError, match=re.escape(f"{cls}.{field}")) as err:
        style(**{field: bad})
    assert words in str(err.value)
    with pytest.raises(InvalidParameterError):
        style().replace(**{field: bad})
    assert style() == style()                              # the defaults are valid


def test_picture_styles_take_every_matplotlib_colour():
    import numpy as np

    from dhlb.render import ConformalStyle, FieldStyle, StripeStyle

    assert FieldStyle(glyph_color="#1f77b4", face_color=(0.5, 0.5, 0.5), background="white").glyph_color == "#1f77b4"
    assert StripeStyle(fn=np.sin, dark="black").fn is np.sin
    assert ConformalStyle(colormap="magma").colormap == "magma"
