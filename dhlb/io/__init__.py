"""Mesh input and output: surfaces (OBJ, OFF, PLY), simplicial meshes (Medit, Gmsh, VTK), simplex lists.

All readers return numpy arrays with 0-based indices and validate what they read: unparsable
text raises :class:`~dhlb.errors.MeshParseError` naming the file and line, NaN/inf coordinates
raise :class:`~dhlb.errors.NonFiniteError` naming the vertex. Unreferenced vertices are kept;
:func:`compact_mesh` drops them.

:func:`read_result` reads back what the commands and the results' ``save`` wrote (see
:mod:`dhlb.io.results`; imported on first use, since it brings the applications' result types).

Examples
--------
>>> from dhlb.io import load, example_path
>>> mesh = load(example_path("torus.obj"))
>>> mesh.to_complex().euler_characteristic
0
"""

from dhlb.io.atomic import atomic_write, refuse_overwrite
from dhlb.io.examples import EXAMPLES, example_path
from dhlb.io.formats import FORMATS, format_of
from dhlb.io.gmsh import read_gmsh, write_gmsh
from dhlb.io.load import MeshData, load
from dhlb.io.medit import read_medit, write_medit
from dhlb.io.ply import read_ply, write_ply
from dhlb.io.simplices import parse_simplices_text, read_simplices, write_simplices
from dhlb.io.surface import read_obj, read_off, read_surface, write_obj, write_off, write_surface
from dhlb.io.volume import read_cells, read_volume, write_cells, write_volume
from dhlb.io.vtk import read_vtk, write_vtk
from dhlb.mesh.compact import compact_mesh

__all__ = [
    "load",
    "MeshData",
    "read_surface",
    "write_surface",
    "read_volume",
    "write_volume",
    "read_cells",
    "write_cells",
    "read_obj",
    "write_obj",
    "read_off",
    "write_off",
    "read_ply",
    "write_ply",
    "read_medit",
    "write_medit",
    "read_gmsh",
    "write_gmsh",
    "read_vtk",
    "write_vtk",
    "read_simplices",
    "write_simplices",
    "parse_simplices_text",
    "compact_mesh",
    "example_path",
    "EXAMPLES",
    "atomic_write",
    "refuse_overwrite",
    "format_of",
    "FORMATS",
    "read_result",
]


def __getattr__(name: str):
    if name == "read_result":  # lazily: dhlb.io.results imports the result types of every application
        from dhlb.io.results import read_result

        return read_result
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
