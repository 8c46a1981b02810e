"""Every public function and class (in ``__all__`` of the packages below) has a complete numpydoc docstring.

Checked with numpydoc's own validation (:func:`numpydoc.validate.validate`), failing on

* GL08 -- no docstring,
* PR01 -- a parameter of the signature is not documented (for a class: the parameters of its constructor,
  documented in the class docstring),
* PR02 -- a documented parameter is not in the signature,
* RT01 -- a function that returns something has no ``Returns`` section,

and on our own check

* RA01 -- the body of the function (for a class: of its ``__init__``, ``__new__`` or ``__post_init__``) contains a
  ``raise`` statement, but the docstring has no ``Raises`` section.

A name re-exported by several packages is checked once. To put a package under the gate, add it to PACKAGES.
"""

from __future__ import annotations

import ast
import importlib
import inspect
import textwrap

import pytest
from numpydoc.validate import get_doc_object, validate

PACKAGES = [
    "dhlb.errors",
    "dhlb.geometry",
    "dhlb.linalg",
    "dhlb.fem",
    "dhlb.io",
    "dhlb.examples",
    "dhlb.strategies",
    "dhlb.topology",
    "dhlb.forms",
    "dhlb.bundles",
    "dhlb.mesh",
    "dhlb.fields",
    "dhlb.vortex",
    "dhlb.stripes",
    "dhlb.conformal",
    "dhlb.conformal.quaternion",
    "dhlb.stripes.revolution",
    "dhlb.render",
    "dhlb.cli",
]

# names not (yet) under the gate, with the reason (none now)
EXCLUDED: set[str] = set()
# modules whose names are not (yet) under the gate (none now)
EXCLUDED_MODULES: set[str] = set()

CODES = ("GL08", "PR01", "PR02", "RT01")
# for a class, the methods whose ``raise`` statements the class docstring documents
CONSTRUCTORS = ("__new__", "__init__", "__post_init__")


def _raises_in(func) -> bool:
    """Whether the body of ``func`` itself (not of functions or classes nested in it) has a ``raise`` statement."""
    try:
        source = textwrap.dedent(inspect.getsource(inspect.unwrap(func)))
    except (OSError, TypeError):  # builtins, functions made at run time
        return False
    tree = ast.parse(source)
    if not tree.body or not isinstance(tree.body[0], (ast.FunctionDef, ast.AsyncFunctionDef)):
        return False

    def walk(node):
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.Raise):
                return True
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef, ast.Lambda)):
                continue
            if walk(child):
                return True
        return False

    return walk(tree.body[0])


def _has_raises_section(obj) -> bool:
    doc = inspect.getdoc(obj) or ""
    if not doc:
        return False
    parsed = get_doc_object(obj)
    return bool(parsed["Raises"])


def check(obj, name: str | None = None) -> list[tuple[str, str]]:
    """The failures ``(code, message)`` of the gate for one function or class."""
    name = name or f"{obj.__module__}.{obj.__qualname__}"
    try:
        result = validate(name)
    except (ImportError, AttributeError):  # not reachable by its import path: validate the object itself
        result = validate(get_doc_object(obj))
    errors = [(code, msg) for code, msg in result["errors"] if code in CODES]
    if inspect.isclass(obj):
        raising = any(_raises_in(vars(obj)[m]) for m in CONSTRUCTORS
                      if m in vars(obj) and inspect.isfunction(vars(obj)[m]))
    else:
        raising = _raises_in(obj)
    if raising and not _has_raises_section(obj):
        errors.append(("RA01", "The function raises, but the docstring has no Raises section"))
    return errors


def _qualified_name(obj, attr: str) -> str:
    """The import path of ``obj`` in its defining module (wrapped functions: the name they are bound to there)."""
    if "<locals>" in obj.__qualname__:  # e.g. a hypothesis strategy, a wrapper made by a decorator
        return f"{obj.__module__}.{attr}"
    return f"{obj.__module__}.{obj.__qualname__}"


def public_objects(packages) -> dict[str, list[tuple[str, object]]]:
    """The functions and classes in ``__all__`` of each package, each object under the first package naming it."""
    seen: set[int] = set()
    out: dict[str, list[tuple[str, object]]] = {}
    for package in packages:
        mod = importlib.import_module(package)
        out[package] = []
        for attr in getattr(mod, "__all__", []):
            obj = getattr(mod, attr)
            if not (inspect.isfunction(obj) or inspect.isclass(obj)) or id(obj) in seen:
                continue
            seen.add(id(obj))
            qualified = _qualified_name(obj, attr)
            if qualified in EXCLUDED or obj.__module__ in EXCLUDED_MODULES:
                continue
            out[package].append((qualified, obj))
    return out


def failures(objects) -> list[str]:
    """One line ``name: code message`` per failure."""
    return [f"{name}: {code} {msg}" for name, obj in objects for code, msg in check(obj, name)]


OBJECTS = public_objects(PACKAGES)


def test_there_are_objects_under_the_gate():
    assert sum(len(v) for v in OBJECTS.values()) > 100
    assert all(OBJECTS.values()), [p for p, v in OBJECTS.items() if not v]


def test_reexported_names_are_checked_once():
    names = [name for objects in OBJECTS.values() for name, _ in objects]
    assert len(names) == len(set(names))


@pytest.mark.parametrize("package", PACKAGES)
def test_public_callables_have_numpydoc_sections(package):
    bad = failures(OBJECTS[package])
    assert not bad, f"{len(bad)} numpydoc failures in {package}:\n" + "\n".join(bad)


# --- the checker itself ------------------------------------------------------------------------------------


def undocumented(V, F):
    if len(V) == 0:
        raise ValueError("empty")
    return V[F]


def documented(V, F):
    """Take the corners of the triangles.

    Parameters
    ----------
    V : (n, 3) float array
        Vertex positions.
    F : (m, 3) int array
        Triangles.

    Returns
    -------
    (m, 3, 3) float array
        The corners.

    Raises
    ------
    ValueError
        When ``V`` is empty.
    """
    if len(V) == 0:
        raise ValueError("empty")
    return V[F]


def wrong_parameters(V, F):
    """Take the corners of the triangles.

    Parameters
    ----------
    V : (n, 3) float array
        Vertex positions.
    G : (m, 3) int array
        Not a parameter.

    Returns
    -------
    (m, 3, 3) float array
        The corners.
    """
    return V[F]


def no_returns_section(V, F):
    """Take the corners of the triangles.

    Parameters
    ----------
    V : (n, 3) float array
        Vertex positions.
    F : (m, 3) int array
        Triangles.
    """
    return V[F]


def raises_only_in_a_nested_function(V):
    """Make a checker.

    Parameters
    ----------
    V : (n, 3) float array
        Vertex positions.

    Returns
    -------
    callable
        The checker.
    """
    def inner():
        raise ValueError("not raised by the outer function")

    return inner


class _RaisingConstructor:
    """A class whose constructor raises.

    Parameters
    ----------
    x : int
        A value.
    """

    def __init__(self, x):
        if x < 0:
            raise ValueError("negative")
        self.x = x


def _codes(func):
    return sorted(code for code, _ in check(func, f"{__name__}.{func.__qualname__}"))


def test_checker_fails_an_undocumented_function():
    assert _codes(undocumented) == ["GL08", "RA01"]
    assert failures([("tests.test_numpydoc.undocumented", undocumented)])


def test_checker_passes_a_documented_function():
    assert _codes(documented) == []


def test_checker_finds_missing_and_unknown_parameters():
    assert _codes(wrong_parameters) == ["PR01", "PR02"]


def test_checker_finds_a_missing_returns_section():
    assert _codes(no_returns_section) == ["RT01"]


def test_checker_ignores_raises_of_nested_functions():
    assert _codes(raises_only_in_a_nested_function) == []


def test_checker_checks_raises_of_a_class_constructor():
    assert _codes(_RaisingConstructor) == ["RA01"]
