"""Every import path of dhlb 0.1 (commit 0d1c46c) still works, with a DeprecationWarning naming the new path."""

from __future__ import annotations

import importlib
import warnings

import numpy as np
import pytest

import dhlb
from dhlb._deprecation import MOVED

OLD_MODULES = {  # old module -> (a name it exported, the module that now holds it)
    "dhlb.surface.mesh": ("SurfaceMesh", "dhlb.mesh.surface"),
    "dhlb.surface._mesh_checks": ("check_faces", "dhlb.mesh._surface_checks"),
    "dhlb.surface._fans": ("vertex_fans", "dhlb.mesh.halfedge"),
    "dhlb.surface.tangent": ("tangent_bundle", "dhlb.mesh.tangent"),
    "dhlb.surface.energy": ("energy_matrices", "dhlb.fields.energy"),
    "dhlb.surface.field": ("direction_field", "dhlb.fields.field"),
    "dhlb.surface.guidance": ("curvature_guidance", "dhlb.fields.guidance"),
    "dhlb.surface.directions": ("field_indices", "dhlb.fields.directions"),
    "dhlb.surface.prescribed": ("prescribed_field", "dhlb.fields.prescribed"),
    "dhlb.surface.result": ("DirectionField", "dhlb.fields.result"),
    "dhlb.volume.meshes": ("box_tet_mesh", "dhlb.mesh.tet"),
    "dhlb.volume.tetgen": ("tetrahedralize", "dhlb.mesh.tetgen"),
    "dhlb.volume.curves": ("vortex_ring", "dhlb.vortex.curves"),
    "dhlb.volume.fields": ("FilamentField", "dhlb.vortex.flows"),
    "dhlb.volume.velocity": ("velocity_bundle", "dhlb.vortex.velocity"),
    "dhlb.volume.filaments": ("extract_filaments", "dhlb.vortex.filaments"),
    "dhlb.volume._face_zeros": ("face_zeros", "dhlb.vortex._face_zeros"),
    "dhlb.volume.linking": ("linking_number", "dhlb.vortex.linking"),
    "dhlb.volume.vortex": ("vortex_filaments", "dhlb.vortex.pipeline"),
    "dhlb.examples.meshes": ("MeshComplex", "dhlb.mesh.arrays"),
    "dhlb.io.compact": ("compact_mesh", "dhlb.mesh.compact"),
    "dhlb.commands": ("iter_commands", "dhlb.cli.commands"),
    **{f"dhlb.commands.{m}": ("register", f"dhlb.cli.{m}")
       for m in ("conformal", "demo", "field", "info", "stripes", "view", "vortex")},
    "dhlb.commands._common": ("run_command", "dhlb.cli._common"),
    "dhlb.commands._demo_steps": ("write_field_npz", "dhlb.cli._demo_steps"),
}

# every name the two old application packages exported
OLD_SURFACE = ["SurfaceMesh", "validate_surface", "TangentBundle", "tangent_bundle", "Guidance", "boundary_guidance",
               "curvature_guidance", "dihedral_angles", "hopf_differential", "user_guidance", "FieldIndices",
               "Singularities", "direction_vectors", "field_indices", "section_values", "energy_matrices",
               "boundary_form", "DirectionField", "direction_field", "guidance_for", "stripe_pattern",
               "PrescribedField", "prescribed_field", "locate_faces"]
OLD_VOLUME = ["TetMesh", "ball_tet_mesh", "box_tet_mesh", "check_tet_mesh", "signed_volumes", "edge_circulation",
              "gauss_legendre", "velocity_bundle", "FilamentField", "segment_velocity", "superpose", "uniform_flow",
              "hopf_link", "torus_knot", "trefoil", "vortex_ring", "Filament", "FilamentSet", "extract_filaments",
              "face_zeros", "gauss_linking_integral", "hausdorff_distance", "linking_matrix", "linking_number",
              "polyline_distance", "VortexResult", "filament_linking_numbers", "vortex_filaments"]


def _get(module: str, name: str):
    with pytest.warns(DeprecationWarning, match=r"deprecated.*use dhlb\.") as record:
        value = getattr(importlib.import_module(module), name)
    return value, str(record[0].message)


@pytest.mark.parametrize("old", sorted(OLD_MODULES))
def test_old_module_forwards_with_a_warning(old):
    name, new = OLD_MODULES[old]
    value, message = _get(old, name)
    assert value is getattr(importlib.import_module(new), name)
    assert new in message and old in message
    assert MOVED[old] == new


@pytest.mark.parametrize(("package", "names"), [("dhlb.surface", OLD_SURFACE), ("dhlb.volume", OLD_VOLUME)])
def test_old_packages_export_every_old_name(package, names):
    for name in names:
        value, message = _get(package, name)
        assert callable(value), name
        assert f"{package}.{name}" in message
    assert sorted(dir(importlib.import_module(package))) == sorted(names)


def test_unknown_names_still_raise_attribute_error():
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        dhlb.surface.nothing  # noqa: B018
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(AttributeError):
            importlib.import_module("dhlb.surface.mesh").nothing  # noqa: B018


def test_old_examples_mesh_functions_keep_their_argument_order():
    V = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]
    F = [[0, 1, 2], [0, 3, 2]]
    with pytest.warns(DeprecationWarning, match=r"mesh_complex\(V, F\)"):
        old = dhlb.examples.surface(F, V)
    new = dhlb.mesh.mesh_complex(V, F)
    assert old.complex == new.complex and np.array_equal(old.orientation, new.orientation)
    with pytest.warns(DeprecationWarning, match=r"mesh_complex\(V, T\)"):
        tets = dhlb.examples.tet_mesh([[0, 1, 2, 3]])
    assert tets.complex.counts == (4, 6, 4, 1)
    with pytest.warns(DeprecationWarning):
        assert dhlb.examples.MeshComplex is dhlb.mesh.MeshComplex
    with pytest.warns(DeprecationWarning), pytest.raises(dhlb.errors.InvalidSimplexError):
        dhlb.examples.surface([[0, 1, 2, 3]])   # the old function still insists on triangles


def test_new_homes_import_without_warnings():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for module in ("dhlb.mesh", "dhlb.fields", "dhlb.vortex", "dhlb.stripes", "dhlb.conformal"):
            importlib.import_module(module)


def test_old_mpi_main_forwards():
    value, message = _get("dhlb.linalg.backends_petsc", "mpi_main")
    assert value is importlib.import_module("dhlb.cli.mpi").mpi_main and "dhlb.cli.mpi.mpi_main" in message


def test_old_mpi_entry_point_runs_the_new_one():
    import subprocess
    import sys

    proc = subprocess.run([sys.executable, "-W", "always::DeprecationWarning", "-m", "dhlb.linalg.backends_petsc",
                           "--version"], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.startswith("dhlb ")
    assert "use python -m dhlb.cli.mpi" in proc.stderr
