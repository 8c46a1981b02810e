"""Deprecated import paths, resolved by name on first access (SciPy's ``_sub_module_deprecation`` pattern).

When a module moves, its old path stays importable as a *shim*: a file whose whole body is ::

    from dhlb._deprecation import moved_module
    __getattr__, __dir__ = moved_module(__name__, "dhlb.mesh.surface")

Reading any attribute of the shim imports the new module (by name, with :func:`importlib.import_module`,
so a shim adds no static import edge: the layering of the package is that of the new homes) and emits
a :class:`DeprecationWarning` naming the new path. :data:`MOVED` records every shim, old → new; the
test suite imports each and checks that it warns and forwards.

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

import importlib
import warnings
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from collections.abc import Callable

__all__ = ["MOVED", "fold_deprecated_kwargs", "moved_module", "moved_package", "warn_moved"]

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
        An old keyword together with the options object that replaces it.

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
    import dataclasses

    from dhlb.errors import InvalidParameterError

    known = {}
    for i, (_, _, _, names) in enumerate(groups):
        for old, path in (names.items() if isinstance(names, dict) else ((n, n) for n in names)):
            known[old] = (i, path)
    for old in kwargs:
        if old not in known:
            raise TypeError(f"{func}() got an unexpected keyword argument {old!r}")
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
