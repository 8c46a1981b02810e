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

__all__ = ["MOVED", "moved_module", "moved_package", "warn_moved"]

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
