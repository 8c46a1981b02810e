"""The fingerprint of the seed's part 2, Fig. 5: stripes along a line field with a prescribed core and delta.

:func:`dhlb.examples.fingerprint_pad` gives a finger pad and the prescription (+1/2 core, −1/2 delta);
the stripe pattern along :func:`dhlb.fields.prescribed_field` must branch exactly at the two
prescribed faces, and follow them when they move.
"""

from __future__ import annotations

import numpy as np
import pytest

from dhlb.errors import InvalidParameterError, ShapeError
from dhlb.examples import fingerprint_pad
from dhlb.fields import prescribed_field
from dhlb.mesh import validate_surface
from dhlb.stripes import stripe_pattern


def _fingerprint(**kw):
    V, F, sing = fingerprint_pad(**kw)
    field = prescribed_field(V, F, 2, sing)
    return sing, field, stripe_pattern(field, spacing=4.0)


def _branch_rows(pattern) -> set[int]:
    return set(pattern.mesh.face_rows[pattern.branch_faces].tolist())


def test_the_pad_is_an_upward_disk_of_nearly_equilateral_triangles():
    V, F, sing = fingerprint_pad(rings=12, aspect=1.0, height=0.0)
    mesh = validate_surface(V, F)
    assert (mesh.n_vertices, mesh.n_faces) == (1 + 3 * 12 * 13, 6 * 12**2)
    assert mesh.euler_characteristic == 1 and not mesh.is_closed
    assert int(mesh.is_boundary_vertex.sum()) == 6 * 12          # one boundary ring, the outermost
    assert np.allclose(np.linalg.norm(V[mesh.is_boundary_vertex, :2], axis=1), 1.0)
    e1, e2 = V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]
    assert np.all(np.cross(e1, e2)[:, 2] > 0)                    # counter-clockwise seen from above
    lengths = np.linalg.norm(V[np.roll(F, -1, axis=1)] - V[F], axis=2)
    assert lengths.max() / lengths.min() < 2.0                   # no slivers
    assert sorted(sing.values()) == [-1, 1]


def test_branch_faces_are_exactly_the_prescribed_core_and_delta():
    sing, field, pattern = _fingerprint()
    assert _branch_rows(pattern) == set(sing)
    expected = np.zeros(field.mesh.n_faces, np.int64)
    expected[np.searchsorted(field.mesh.face_rows, list(sing))] = list(sing.values())
    assert np.array_equal(field.face_index, expected)            # +1/2 core, −1/2 delta, nothing else
    assert field.index_sum == 0
    assert pattern.eigenvalue >= 0 and pattern.zero_faces.size < 30


def test_moving_the_core_moves_the_branch_face():
    sing, _, pattern = _fingerprint()
    moved, _, moved_pattern = _fingerprint(core=(-0.3, 0.4))
    core = next(f for f, k in sing.items() if k == 1)
    new_core = next(f for f, k in moved.items() if k == 1)
    assert new_core != core
    assert _branch_rows(moved_pattern) == set(moved)
    assert core not in _branch_rows(moved_pattern) and new_core not in _branch_rows(pattern)


def test_without_a_prescription_there_is_no_branch_face():
    V, F, _ = fingerprint_pad(rings=12)
    field = prescribed_field(V, F, 2, {})
    assert _branch_rows(stripe_pattern(field, spacing=4.0)) == set()


@pytest.mark.parametrize("kw, error, match", [
    ({"core": (0.8, 0.8)}, InvalidParameterError, "inside the unit disk"),
    ({"delta": (1.0, 0.0)}, InvalidParameterError, "inside the unit disk"),
    ({"core": (0.2, 0.2), "delta": (0.2, 0.2)}, InvalidParameterError, "same face"),
    ({"core": (0.1, 0.2, 0.3)}, ShapeError, "point"),
    ({"rings": 1}, InvalidParameterError, "rings"),
    ({"aspect": 0.0}, InvalidParameterError, "aspect"),
    ({"height": -1.0}, InvalidParameterError, "height"),
])
def test_bad_arguments_are_named(kw, error, match):
    with pytest.raises(error, match=match):
        fingerprint_pad(**kw)
