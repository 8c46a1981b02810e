"""Ragged cell lists (issue 28 B): every (V, F) / (V, T) entry point names the first row of the wrong length."""

from __future__ import annotations

import numpy as np
import pytest

from dhlb.conformal import conformal_deformation
from dhlb.errors import RaggedInputError
from dhlb.fields import direction_field, prescribed_field
from dhlb.mesh import as_surface, as_tet_mesh, check_tet_mesh, mesh_complex, validate_surface
from dhlb.mesh.arrays import check_row_lengths
from dhlb.stripes import stripe_pattern
from dhlb.vortex import vortex_filaments

V = np.random.default_rng(0).random((6, 3))
F = [[0, 1, 2], [0, 2, 3, 4]]                   # face 1 is a quad
T = [[0, 1, 2, 3], [1, 2, 3, 4, 5]]             # tetrahedron 1 has five vertices
FACE = r"F: face 1 has 4 vertex indices \(0, 2, 3, 4\), a face needs 3"
TET = r"T: tetrahedron 1 has 5 vertex indices \(1, 2, 3, 4, 5\), a tetrahedron needs 4"


@pytest.mark.parametrize("call", [
    pytest.param(lambda: direction_field(V, F), id="direction_field"),
    pytest.param(lambda: prescribed_field(V, F, 1, {}), id="prescribed_field"),
    pytest.param(lambda: stripe_pattern(V, F, np.ones((6, 3))), id="stripe_pattern"),
    pytest.param(lambda: validate_surface(V, F), id="validate_surface"),
    pytest.param(lambda: as_surface(V, F), id="as_surface"),
])
def test_ragged_faces_name_the_face(call):
    with pytest.raises(RaggedInputError, match=FACE):
        call()


@pytest.mark.parametrize("call", [
    pytest.param(lambda: conformal_deformation(V, T, lambda x: x[:, 0]), id="conformal_deformation"),
    pytest.param(lambda: vortex_filaments(V, T, lambda x: x, 0.1), id="vortex_filaments"),
    pytest.param(lambda: check_tet_mesh(V, T), id="check_tet_mesh"),
    pytest.param(lambda: as_tet_mesh(V, T), id="as_tet_mesh"),
])
def test_ragged_tetrahedra_name_the_tetrahedron(call):
    with pytest.raises(RaggedInputError, match=TET):
        call()


@pytest.mark.parametrize("cells, match", [
    ([[0, 1, 2, 3], [0, 2, 3]], r"face 0 has 4 vertex indices \(0, 1, 2, 3\), a face needs 3"),  # no row fits
    ([[0, 1, 2], [0, 2]], r"face 1 has 2 vertex indices \(0, 2\), a face needs 3"),
    ([[0, 1, 2], 5], r"face 1 has 1 vertex index \(5,\), a face needs 3"),
    ([[0, 1, 2], [1, 2, 3], np.array([0, 3, 4, 5])], r"face 2 has 4 vertex indices \(0, 3, 4, 5\)"),
])
def test_validate_surface_names_the_first_odd_row(cells, match):
    with pytest.raises(RaggedInputError, match="F: " + match):
        validate_surface(V, cells)


def test_mesh_complex_reads_the_dimension_from_the_first_row():
    with pytest.raises(RaggedInputError, match=r"^tetrahedron 1 has 5 vertex indices \(1, 2, 3, 4, 5\), a tetrahedron"):
        mesh_complex(V, T)
    with pytest.raises(RaggedInputError, match=r"^triangle 1 has 4 vertex indices"):
        mesh_complex(None, F)


def test_rectangular_cells_pass_the_row_check():
    check_row_lengths(np.zeros((4, 3), int), 3, "face")      # arrays are never ragged
    check_row_lengths([[0, 1, 2, 3]] * 2, 3, "face")         # one wrong width: a shape error for the caller
    assert validate_surface(V[:4], [[0, 1, 2], [0, 2, 3]]).n_faces == 2
