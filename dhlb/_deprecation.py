"""Deprecated import paths, resolved by name on first access (SciPy's ``_sub_module_deprecation`` pattern).

When a module moves, its old path stays importable as a *shim*: a file whose whole body is ::

    from dhlb._deprecation import moved_module
    __getattr__, __dir__ = moved_module(__name__, "dhlb.mesh.surface")

Reading any attribute of the shim imports the new module (by name, with :func:`importlib.import_module`,
so a shim adds no static import edge: the layering of the package is that of the new homes) and emits
a :class:`DeprecationWarning` naming the new path. :data:`MOVED` records every shim, old → new; the
test suite imports each and checks that it warns and forwards.

Option groups (``FieldOptions``, ``SolverOptions``, ...) reach every public entry point through
:func:`fold_deprecated_kwargs`, which also refuses an options object of the wrong kind, or a plain dict,
with a message that spells the right call (:func:`check_option_group`). The option classes check their
own fields with the small helpers :func:`check_flag`, :func:`check_choice`, :func:`check_integer` and
:func:`check_number`, whose messages name the field (``"FieldOptions.lumped must be True or False, got 'no'"``).

Examples
--------
>>> import warnings
>>> with warnings.catch_warnings(record=True) as caught:
...     warnings.simplefilter("always")
...     from dhlb.surface.mesh import SurfaceMesh
>>> SurfaceMesh.__module__, caught[0].category.__name__
('dhlb.mesh.surface', 'DeprecationWarning')
"""

from __future__ import annotations

import dataclasses
import importlib
import numbers
import sys
import warnings
from typing import TYPE_CHECKING, Any

from dhlb.errors import InvalidParameterError

if TYPE_CHECKING:
    from collections.abc import Callable, Iterable

__all__ = ["MOVED", "check_choice", "check_flag", "check_integer", "check_number", "check_option_group", "did_you_mean",
           "fold_deprecated_kwargs", "moved_module", "moved_package", "warn_moved"]

MOVED: dict[str, str] = {}
"""Every deprecated module path → the path that replaces it (filled as the shims are imported)."""

REMOVAL = "0.3"
"""The version in which the deprecated paths disappear."""


def warn_moved(old: str, new: str, stacklevel: int = 3) -> None:
    """Emit the one deprecation message of the package: ``old`` is deprecated, use ``new``.

    Parameters
    ----------
    old, new : str
        Dotted paths (or call forms) of the deprecated name and of its replacement.
    stacklevel : int
        Passed to :func:`warnings.warn` (3: the caller of the function that warns).

    Returns
    -------
    None

    Warns
    -----
    DeprecationWarning
        Always.
    """
    warnings.warn(f"{old} is deprecated and will be removed in dhlb {REMOVAL}; use {new}",
                  DeprecationWarning, stacklevel=stacklevel)


def moved_module(old: str, new: str, renames: dict[str, str] | None = None
                 ) -> tuple[Callable[[str], object], Callable[[], list[str]]]:
    """Module ``__getattr__`` and ``__dir__`` for a shim at ``old`` whose content now lives at ``new``.

    Parameters
    ----------
    old : str
        The shim's ``__name__``.
    new : str
        Dotted path of the module that replaces it.
    renames : dict, optional
        Old attribute name → new attribute name, for names that changed as they moved.

    Returns
    -------
    getattr, dir : callables
        To be assigned to the shim's ``__getattr__`` and ``__dir__``.
    """
    MOVED[old] = new
    renames = renames or {}

    def __getattr__(name: str):
        if name.startswith("__"):
            raise AttributeError(name)
        target = importlib.import_module(new)
        new_name = renames.get(name, name)
        try:
            value = getattr(target, new_name)
        except AttributeError:
            raise AttributeError(f"module {old!r} has no attribute {name!r}") from None
        warn_moved(f"{old}.{name}", f"{new}.{new_name}")
        return value

    def __dir__() -> list[str]:
        return sorted(set(dir(importlib.import_module(new))) | set(renames))

    return __getattr__, __dir__


def moved_package(old: str, homes: dict[str, str]) -> tuple[Callable[[str], object], Callable[[], list[str]]]:
    """``__getattr__`` and ``__dir__`` for a deprecated package whose names moved to several new homes.

    Parameters
    ----------
    old : str
        The package's ``__name__``.
    homes : dict
        Every name the package exported → the dotted path of the module that now holds it.

    Returns
    -------
    getattr, dir : callables
        To be assigned to the package's ``__getattr__`` and ``__dir__``.
    """
    MOVED[old] = ", ".join(sorted(set(homes.values())))

    def __getattr__(name: str):
        if name not in homes:
            raise AttributeError(f"module {old!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(homes[name]), name)
        warn_moved(f"{old}.{name}", f"{homes[name]}.{name}")
        return value

    def __dir__() -> list[str]:
        return sorted(homes)

    return __getattr__, __dir__


def fold_deprecated_kwargs(func: str, kwargs: dict, *groups: tuple) -> tuple:
    """Old keyword arguments of ``func`` → the options objects that replace them, each with a warning.

    A public function whose knobs moved into option groups keeps accepting the old keywords through
    ``**kwargs``; this folds them into its options objects (:func:`dataclasses.replace`, so the
    options class validates them) and warns once per keyword, naming the new spelling.

    Parameters
    ----------
    func : str
        The public function's name (for the messages).
    kwargs : dict
        The ``**kwargs`` the function received.
    *groups : (param, given, default, names) tuples
        One per options parameter: its name, the value the caller gave (``None`` if not given), the
        object to start from when it was not given, and ``names``: a mapping old keyword → field of the
        options class (a dotted path such as ``"section.kind"`` for a nested options object), or an
        iterable of keywords that kept their name.

    Returns
    -------
    tuple
        Per group, the options object to use: ``given`` if it is not None (then no old keyword of the
        group may be present), else ``default`` with the old keywords applied.

    Raises
    ------
    TypeError
        A keyword that no group knows, in Python's own words.
    InvalidParameterError
        An old keyword together with the options object that replaces it; a ``given`` that is not an
        instance of ``type(default)`` (nor its shorthand, :func:`check_option_group`), e.g. a
        ``StripeOptions`` passed as ``options=`` to ``direction_field``, or a dict.

    Warns
    -----
    DeprecationWarning
        Once per old keyword, e.g. ``f(tol=...) is deprecated ...; use solver=SolverOptions(tol=...)``.

    Examples
    --------
    >>> import warnings
    >>> from dataclasses import dataclass
    >>> @dataclass(frozen=True)
    ... class Knobs:
    ...     tol: float = 1e-9
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     (knobs,) = fold_deprecated_kwargs("f", {"tol": 1e-6}, ("knobs", None, Knobs(), ["tol"]))
    >>> knobs, str(caught[0].message).split("; ")[1]
    (Knobs(tol=1e-06), 'use knobs=Knobs(tol=...)')
    """
    known = {}
    for i, (_, _, _, names) in enumerate(groups):
        for old, path in (names.items() if isinstance(names, dict) else ((n, n) for n in names)):
            known[old] = (i, path)
    for old in kwargs:
        if old not in known:
            raise TypeError(f"{func}() got an unexpected keyword argument {old!r}")
    for param, given, default, _ in groups:
        if given is not None:
            check_option_group(func, param, given, default)
    out = []
    for i, (param, given, default, _) in enumerate(groups):
        changes = {old: known[old][1] for old in kwargs if known[old][0] == i}
        if changes and given is not None:
            raise InvalidParameterError(f"{func}(): pass either {param}= or the deprecated keyword(s) "
                                        f"{', '.join(changes)}, not both")
        value = default if given is None else given
        for old, path in changes.items():
            *outer, field = path.split(".")
            objs = [value]
            for name in outer:
                objs.append(getattr(objs[-1], name))
            spelled = f"{field}=..."
            for obj, name in zip(reversed(objs), reversed([None, *outer])):
                spelled = f"{type(obj).__name__}({spelled})"
                spelled = spelled if name is None else f"{name}={spelled}"
            warn_moved(f"{func}({old}=...)", f"{param}={spelled}", stacklevel=4)
            new = kwargs[old]
            for obj, name in zip(reversed(objs), reversed([*outer, field])):
                new = dataclasses.replace(obj, **{name: new})
            value = new
        out.append(value)
    return tuple(out)


# ---------------------------------------------------------------------------------------- option values
def _numpy_bool(value: Any) -> bool:
    np = sys.modules.get("numpy")   # not imported: value is no numpy bool (and numpy stays unimported)
    return np is not None and isinstance(value, np.bool_)


def did_you_mean(word: Any, choices: Iterable[str], quote: bool = True) -> str:
    """``"; did you mean 'X'?"`` for the choice closest to ``word`` (:mod:`difflib`), or ``""``.

    Parameters
    ----------
    word : object
        What was given; only a string gets a hint.
    choices : iterable of str
        The known names.
    quote : bool, default True
        Quote the name as Python does (``'X'``); the command line's messages speak shell: ``X``.

    Returns
    -------
    str
        The hint, to append to a message.

    Examples
    --------
    >>> did_you_mean("larget", ("all", "largest")), did_you_mean("zzz", ("all", "largest"))
    ("; did you mean 'largest'?", '')
    >>> did_you_mean("linked-ring", ["ring", "linked-rings"], quote=False)
    '; did you mean linked-rings?'
    """
    if not isinstance(word, str):
        return ""
    import difflib

    close = difflib.get_close_matches(word, list(choices), n=1, cutoff=0.6)
    return (f"; did you mean {close[0]!r}?" if quote else f"; did you mean {close[0]}?") if close else ""


def check_flag(value: Any, name: str, *, optional: bool = False) -> None:
    """Refuse anything but ``True`` or ``False`` (a numpy bool counts; with ``optional``, also ``None``).

    A truthy value is not a flag: ``lumped="no"`` would mean lumped.

    Parameters
    ----------
    value : object
        The value of the field.
    name : str
        The field, as the message names it (``"FieldOptions.lumped"``).
    optional : bool
        Whether ``None`` (the default of the method) is allowed.

    Returns
    -------
    None

    Raises
    ------
    InvalidParameterError
        ``value`` is not a bool.

    Examples
    --------
    >>> check_flag("no", "FieldOptions.lumped")
    Traceback (most recent call last):
    ...
    dhlb.errors.InvalidParameterError: FieldOptions.lumped must be True or False, got 'no'
    """
    if optional and value is None:
        return
    if isinstance(value, bool) or _numpy_bool(value):
        return
    allowed = "True, False or None" if optional else "True or False"
    raise InvalidParameterError(f"{name} must be {allowed}, got {value!r}")


def check_choice(value: Any, name: str, choices: Iterable[str]) -> None:
    """Refuse anything but one of the names ``choices`` (a string; with a "did you mean" hint).

    Parameters
    ----------
    value : object
        The value of the field.
    name : str
        The field, as the message names it.
    choices : iterable of str
        The known names.

    Returns
    -------
    None

    Raises
    ------
    InvalidParameterError
        ``value`` is not one of ``choices``.

    Examples
    --------
    >>> check_choice("larget", "components", ("all", "largest"))
    Traceback (most recent call last):
    ...
    dhlb.errors.InvalidParameterError: components must be one of 'all', 'largest', got 'larget'; did you mean 'largest'?
    """
    choices = tuple(choices)
    if isinstance(value, str) and value in choices:
        return
    raise InvalidParameterError(f"{name} must be one of {', '.join(map(repr, choices))}, got {value!r}"
                                f"{did_you_mean(value, choices)}")


def check_integer(value: Any, name: str, low: int, high: int | None = None, *, why: str = "") -> None:
    """Refuse anything but an integer (Python or numpy, not a bool) in ``low .. high``.

    Parameters
    ----------
    value : object
        The value of the field.
    name : str
        The field, as the message names it.
    low : int
        The smallest value allowed.
    high : int, optional
        The largest value allowed (no bound if None).
    why : str, optional
        Appended to the message, in parentheses: what the bound protects.

    Returns
    -------
    None

    Raises
    ------
    InvalidParameterError
        ``value`` is not an integer, or out of range.

    Examples
    --------
    >>> check_integer(2.5, "SolverOptions.maxiter", 1)
    Traceback (most recent call last):
    ...
    dhlb.errors.InvalidParameterError: SolverOptions.maxiter must be an integer >= 1, got 2.5
    """
    ok = isinstance(value, numbers.Integral) and not isinstance(value, bool) and not _numpy_bool(value)
    if ok and low <= int(value) and (high is None or int(value) <= high):
        return
    bound = f">= {low}" if high is None else f"between {low} and {high}"
    raise InvalidParameterError(f"{name} must be an integer {bound}{f' ({why})' if why else ''}, got {value!r}")


def check_number(value: Any, name: str, what: str, ok: Callable[[float], bool] = lambda x: True) -> None:
    """Refuse anything but a finite real number (Python or numpy, not a bool) ``x`` with ``ok(x)``.

    Parameters
    ----------
    value : object
        The value of the field.
    name : str
        The field, as the message names it.
    what : str
        What the field must be, for the message (``"a positive number"``).
    ok : callable, optional
        The range: ``ok(float(value))`` must be true.

    Returns
    -------
    None

    Raises
    ------
    InvalidParameterError
        ``value`` is not a real number, is NaN or infinite, or ``ok`` refuses it.

    Examples
    --------
    >>> check_number(float("nan"), "SolverOptions.tol", "a number in (0, 1)", lambda x: 0 < x < 1)
    Traceback (most recent call last):
    ...
    dhlb.errors.InvalidParameterError: SolverOptions.tol must be a number in (0, 1), got nan
    """
    import math

    real = isinstance(value, numbers.Real) and not isinstance(value, bool) and not _numpy_bool(value)
    if real and math.isfinite(float(value)) and ok(float(value)):
        return
    raise InvalidParameterError(f"{name} must be {what}, got {value!r}")


def _default_of(field: dataclasses.Field) -> Any:
    if field.default is not dataclasses.MISSING:
        return field.default
    if field.default_factory is not dataclasses.MISSING:
        return field.default_factory()
    return dataclasses.MISSING


def _spelled(cls: type, values: dict) -> str:
    """``Cls(a=1, b='x')``: the constructor call with ``values`` (a nested dict spelled as its own options class)."""
    fields = {f.name: f for f in dataclasses.fields(cls)} if dataclasses.is_dataclass(cls) else {}
    parts = []
    for key, value in values.items():
        inner = _default_of(fields[key]) if key in fields else None
        if isinstance(value, dict) and dataclasses.is_dataclass(inner) and not isinstance(inner, type):
            parts.append(f"{key}={_spelled(type(inner), value)}")
        else:
            parts.append(f"{key}={value!r}")
    return f"{cls.__name__}({', '.join(parts)})"


def _example(cls: type, given: Any) -> str:
    """A right call ``Cls(...)`` for a ``given`` options object of another kind.

    The fields of ``given`` that differ from the defaults of its own class and that ``cls`` has too, if ``cls``
    takes them (``options=StripeOptions(lumped=True)`` → ``FieldOptions(lumped=True)``), else ``cls._EXAMPLE``
    (the options classes' own example).
    """
    if dataclasses.is_dataclass(cls) and dataclasses.is_dataclass(given) and not isinstance(given, type):
        mine = {f.name for f in dataclasses.fields(cls)}
        shared = {f.name: getattr(given, f.name) for f in dataclasses.fields(given)
                  if f.name in mine and getattr(given, f.name) != _default_of(f)}
        try:
            if shared:
                cls(**shared)
                return _spelled(cls, shared)
        except (TypeError, ValueError):  # not a valid call of cls: the class's own example
            pass
    return f"{cls.__name__}({getattr(cls, '_EXAMPLE', '')})"


def _built(cls: type, values: dict) -> Any:
    """``cls(**values)``, a nested dict built as its own options class (as :func:`_spelled` spells it)."""
    fields = {f.name: f for f in dataclasses.fields(cls)} if dataclasses.is_dataclass(cls) else {}
    kwargs = {}
    for key, value in values.items():
        inner = _default_of(fields[key]) if key in fields else None
        nested = isinstance(value, dict) and dataclasses.is_dataclass(inner) and not isinstance(inner, type)
        kwargs[key] = _built(type(inner), value) if nested else value
    return cls(**kwargs)


def _shown(value: Any) -> str:
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return f"{type(value).__name__}(...)"
    text = repr(value)
    text = text if len(text) <= 80 else text[:77] + "..."
    return f"{text} ({type(value).__name__})"


def check_option_group(func: str, param: str, given: Any, default: Any) -> None:
    """Refuse an options object of the wrong kind, or a plain dict, with a message that spells the right call.

    ``given`` must be an instance of ``type(default)``, or of the class's shorthand types: a class may
    declare ``_SHORTHAND = (types, description)``, e.g. :class:`~dhlb.linalg.SolverOptions` takes a
    backend name (``solver="superlu"``). The example in the message is made of the fields a wrong options
    object shares with the right class (``options=StripeOptions(lumped=True)`` →
    ``options=FieldOptions(lumped=True)``), or of a dict's items, or of the class's ``_EXAMPLE``.

    Parameters
    ----------
    func : str
        The public function's name (for the message).
    param : str
        The parameter that takes the options.
    given : object
        What the caller passed.
    default : object
        The options object used when nothing is given; its class is the one expected.

    Returns
    -------
    None

    Raises
    ------
    InvalidParameterError
        ``given`` is not an instance of ``type(default)`` (nor a shorthand).

    Examples
    --------
    >>> from dataclasses import dataclass
    >>> @dataclass(frozen=True)
    ... class Knobs:
    ...     tol: float = 1e-9
    >>> check_option_group("f", "knobs", {"tol": 1e-6}, Knobs())
    Traceback (most recent call last):
    ...
    dhlb.errors.InvalidParameterError: f: knobs must be a Knobs, not a dict: write knobs=Knobs(tol=1e-06)
    """
    cls = type(default)
    shorthand, described = getattr(cls, "_SHORTHAND", ((), ""))
    if isinstance(given, cls) or (shorthand and isinstance(given, shorthand)):
        return
    kinds = f"a {cls.__name__}" + (f" or {described}" if described else "")
    if isinstance(given, dict) and all(isinstance(k, str) and k.isidentifier() for k in given):
        try:
            _built(cls, given)
            refused = ""
        except (TypeError, ValueError) as err:   # the options' own check (a DhlbError is a ValueError)
            refused = f" (which is refused too: {err})"
        raise InvalidParameterError(f"{func}: {param} must be {kinds}, not a dict: "
                                    f"write {param}={_spelled(cls, given)}{refused}")
    raise InvalidParameterError(f"{func}: {param} must be {kinds}, e.g. {param}={_example(cls, given)}; "
                                f"got {_shown(given)}")
