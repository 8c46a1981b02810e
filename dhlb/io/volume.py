"""Tetrahedral (and general simplicial) meshes: dispatch over Medit, Gmsh and VTK files."""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

import numpy as np

from dhlb.errors import InvalidSimplexError, MeshParseError
from dhlb.io.formats import format_of
from dhlb.io.gmsh import read_gmsh, write_gmsh
from dhlb.io.medit import read_medit, write_medit
from dhlb.io.vtk import read_vtk, write_vtk

if TYPE_CHECKING:
    from collections.abc import Mapping
    from typing import Any

    from numpy.typing import ArrayLike

__all__ = ["read_volume", "write_volume", "read_cells", "write_cells"]


def read_cells(path: str | os.PathLike[str], fmt: str | None = None) -> tuple[np.ndarray, dict[int, np.ndarray]]:
    """Read points and simplices by dimension from a ``.mesh``, ``.msh`` or ``.vtk`` file.

    Parameters
    ----------
    path : str or path-like
        The file to read.
    fmt : str, optional
        ``"mesh"``, ``"msh"`` or ``"vtk"`` (or the extension) instead of the extension of ``path``.

    Returns
    -------
    V : (n, 3) float64
    cells : dict {k: (m_k, k+1) int64}, 0-based, only the dimensions present in the file.

    Raises
    ------
    MeshParseError
        Unknown format or one that is not a volume format, or the errors of the reader
        (:func:`~dhlb.io.read_medit`, :func:`~dhlb.io.read_gmsh`, :func:`~dhlb.io.read_vtk`), which name the line.
    NonFiniteError
        A vertex has a NaN or infinite coordinate.

    Examples
    --------
    >>> from dhlb.io import read_cells, example_path
    >>> V, cells = read_cells(example_path("solid-torus.mesh"))
    >>> {k: T.shape for k, T in cells.items()}
    {2: (256, 3), 3: (384, 4)}
    """
    fmt = format_of(path, fmt)
    if fmt == "mesh":
        return read_medit(path)
    if fmt == "msh":
        return read_gmsh(path)
    if fmt == "vtk":
        return read_vtk(path)
    raise MeshParseError(f"{fmt!r} is not a volume format (use mesh, msh, vtk)", os.fspath(path))


def read_volume(path: str | os.PathLike[str], fmt: str | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Read a tetrahedral mesh from a ``.mesh`` (Medit), ``.msh`` (Gmsh) or ``.vtk`` (legacy) file.

    Parameters
    ----------
    path : str or path-like
        The file to read.
    fmt : str, optional
        ``"mesh"``, ``"msh"`` or ``"vtk"`` (or the extension) instead of the extension of ``path``.

    Returns
    -------
    V : (n, 3) float64
    T : (m, 4) int64, 0-based, in file order. Unreferenced vertices are kept
        (see :func:`dhlb.io.compact_mesh`); lower-dimensional cells in the file are ignored.

    Raises
    ------
    MeshParseError
        Unparsable file, unknown or non-volume format, or a file without tetrahedra.
    NonFiniteError
        A vertex has a NaN or infinite coordinate.

    Examples
    --------
    >>> from dhlb.io import read_volume, example_path
    >>> V, T = read_volume(example_path("solid-torus.mesh"))
    >>> V.shape, T.shape
    ((144, 3), (384, 4))
    """
    V, cells = read_cells(path, fmt)
    if 3 not in cells or len(cells[3]) == 0:
        have = ", ".join(f"{len(c)} {k}-simplices" for k, c in sorted(cells.items())) or "no cells"
        raise MeshParseError(
            f"the file contains no tetrahedra ({have}); use read_surface for surfaces", os.fspath(path)
        )
    return V, cells[3]


def write_cells(
    path: str | os.PathLike[str],
    V: ArrayLike,
    cells: ArrayLike | Mapping[int, ArrayLike],
    fmt: str | None = None,
    **kwargs: Any,
) -> None:
    """Write points and simplices to ``.mesh``, ``.msh`` or ``.vtk`` (format from the extension or ``fmt``).

    Parameters
    ----------
    path : str or path-like
        The output file, written atomically (:func:`~dhlb.io.atomic_write`); its folder must exist.
    V : (n, 3) float array
        Vertex positions.
    cells : (m, k+1) int array or dict {k: (m_k, k+1) int array}
        0-based k-simplices (k = 1..3 for Medit, 0..3 for Gmsh and VTK).
    fmt : str, optional
        ``"mesh"``, ``"msh"`` or ``"vtk"``; default: from the extension of ``path``.
    **kwargs
        Passed to the writer (e.g. ``version="4.1"`` for :func:`~dhlb.io.write_gmsh`).

    Returns
    -------
    None
        The writers return nothing.

    Raises
    ------
    MeshParseError
        Unknown format, or one that is not a volume format.
    InvalidSimplexError
        A wrong shape, a dimension the format does not store, a non-integer cell array, or a cell index out of range.
    NonFiniteError
        A vertex has a NaN or infinite coordinate.
    OutputError
        The file cannot be written; nothing is left at ``path``.

    Examples
    --------
    >>> import os, tempfile, numpy as np
    >>> from dhlb.io import read_cells, write_cells
    >>> V = np.eye(3); cells = {1: np.array([[0, 1]]), 2: np.array([[0, 1, 2]])}
    >>> with tempfile.TemporaryDirectory() as d:
    ...     write_cells(os.path.join(d, "t.msh"), V, cells)
    ...     print(sorted(read_cells(os.path.join(d, "t.msh"))[1]))
    [1, 2]
    """
    fmt = format_of(path, fmt)
    if fmt == "mesh":
        return write_medit(path, V, cells, **kwargs)
    if fmt == "msh":
        return write_gmsh(path, V, cells, **kwargs)
    if fmt == "vtk":
        return write_vtk(path, V, cells, **kwargs)
    raise MeshParseError(f"cannot write cells as {fmt!r} (use mesh, msh, vtk)", os.fspath(path))


def write_volume(
    path: str | os.PathLike[str], V: ArrayLike, T: ArrayLike, fmt: str | None = None, **kwargs: Any
) -> None:
    """Write a tetrahedral mesh ``(V, T)`` to ``.mesh``, ``.msh`` or ``.vtk``.

    Parameters
    ----------
    path : str or path-like
        The output file, written atomically (:func:`~dhlb.io.atomic_write`); its folder must exist.
    V : (n, 3) float array
        Vertex positions.
    T : (m, 4) int array
        0-based tetrahedra.
    fmt : str, optional
        ``"mesh"``, ``"msh"`` or ``"vtk"``; default: from the extension of ``path``.
    **kwargs
        Passed to the writer, as in :func:`write_cells`.

    Raises
    ------
    InvalidSimplexError
        ``T`` is not an ``(m, 4)`` array, or as :func:`write_cells`.
    MeshParseError, NonFiniteError, OutputError
        As :func:`write_cells`.

    Examples
    --------
    >>> import os, tempfile, numpy as np
    >>> from dhlb.io import read_volume, write_volume
    >>> V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]); T = np.array([[0, 1, 2, 3]])
    >>> with tempfile.TemporaryDirectory() as d:
    ...     write_volume(os.path.join(d, "t.vtk"), V, T)
    ...     print(read_volume(os.path.join(d, "t.vtk"))[1])
    [[0 1 2 3]]
    """
    T = np.asarray(T)
    if T.ndim != 2 or T.shape[1] != 4:
        raise InvalidSimplexError(f"tetrahedra need an (m, 4) array, got shape {T.shape}")
    write_cells(path, V, {3: T}, fmt, **kwargs)
