"""File formats known to :mod:`dhlb.io`, chosen from the file extension."""

from __future__ import annotations

import os

from dhlb.errors import MeshParseError

__all__ = ["FORMATS", "SURFACE_FORMATS", "VOLUME_FORMATS", "format_of"]

#: extension (lower case, no dot) -> format name
FORMATS = {
    "obj": "obj",
    "off": "off",
    "ply": "ply",
    "mesh": "mesh",
    "msh": "msh",
    "vtk": "vtk",
    "txt": "simplices",
    "simplices": "simplices",
}
SURFACE_FORMATS = ("obj", "off", "ply")
VOLUME_FORMATS = ("mesh", "msh", "vtk")


def format_of(path: str | os.PathLike[str], fmt: str | None = None, hint: str = "(or pass fmt= explicitly)") -> str:
    """The format name of ``path``: ``fmt`` if given, else from the extension.

    Raises
    ------
    MeshParseError
        Unknown ``fmt`` or extension (the message lists the known ones).

    Examples
    --------
    >>> format_of("bunny.OFF"), format_of("a.dat", "simplices")
    ('off', 'simplices')
    >>> format_of("a.stl")
    Traceback (most recent call last):
    ...
    dhlb.errors.MeshParseError: a.stl: unknown file extension '.stl'; known: .obj .off .ply .mesh .msh ...
    """
    known = sorted(set(FORMATS.values()))
    if fmt is not None:
        name = FORMATS.get(fmt.lower().lstrip("."), fmt.lower())
        if name not in known:
            raise MeshParseError(f"unknown format {fmt!r}; known formats: {', '.join(known)}", os.fspath(path))
        return name
    ext = os.path.splitext(os.fspath(path))[1].lower().lstrip(".")
    if ext not in FORMATS:
        shown = f"'.{ext}'" if ext else "(none)"
        raise MeshParseError(
            f"unknown file extension {shown}; known: {' '.join('.' + e for e in FORMATS)} {hint}",
            os.fspath(path),
        )
    return FORMATS[ext]
