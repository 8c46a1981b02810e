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

    dhlb's own strict readers handle OBJ, OFF, PLY, Medit, Gmsh and legacy VTK (their errors name the
    file line); any other extension that meshio reads (``.vtu``, ``.stl``, ``.xdmf``, ...) is
    ``"meshio"`` when meshio is installed (``dhlb[meshio]``).

    Parameters
    ----------
    path : str or path-like
        The file; only its extension (case-insensitive) is used, and its name in messages.
    fmt : str, optional
        A format name or extension (``"off"``, ``".txt"``, ``"meshio"``) that overrides the extension.
    hint : str, optional
        Appended to the message for an unknown extension (what the caller can do instead).

    Returns
    -------
    str
        One of ``"obj"``, ``"off"``, ``"ply"``, ``"mesh"``, ``"msh"``, ``"vtk"``, ``"simplices"``, ``"meshio"``.

    Raises
    ------
    MeshParseError
        Unknown ``fmt`` or extension (the message lists the known ones).

    Examples
    --------
    >>> format_of("bunny.OFF"), format_of("a.dat", "simplices")
    ('off', 'simplices')
    >>> format_of("a.xyz")
    Traceback (most recent call last):
    ...
    dhlb.errors.MeshParseError: a.xyz: unknown file extension '.xyz'; known: .obj .off .ply .mesh .msh ...
    """
    known = sorted(set(FORMATS.values())) + ["meshio"]
    if fmt is not None:
        name = FORMATS.get(fmt.lower().lstrip("."), fmt.lower())
        if name not in known:
            raise MeshParseError(f"unknown format {fmt!r}; known formats: {', '.join(known)}", os.fspath(path))
        return name
    ext = os.path.splitext(os.fspath(path))[1].lower().lstrip(".")
    if ext not in FORMATS and ext and _meshio_reads(ext):
        return "meshio"
    if ext not in FORMATS:
        shown = f"'.{ext}'" if ext else "(none)"
        raise MeshParseError(
            f"unknown file extension {shown}; known: {' '.join('.' + e for e in FORMATS)} {hint}",
            os.fspath(path),
        )
    return FORMATS[ext]


def _meshio_reads(ext: str) -> bool:
    """Whether meshio is installed and reads files with extension ``ext`` (no dot)."""
    import importlib.util

    if importlib.util.find_spec("meshio") is None:
        return False
    import meshio

    return f".{ext}" in getattr(meshio, "extension_to_filetypes", {})
