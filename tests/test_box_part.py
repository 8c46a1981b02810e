"""dhlb.mesh.partition.box_tet_part: one rank's slab of box_tet_mesh, built without the whole box.

Every result is compared with the whole-mesh route (box_tet_mesh, slab part ids, vertex_layout,
tet_part) field by field, the points bit for bit, and the owned rows of the vortex matrices
assembled on the part bit for bit with the serial assembly on the whole box.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from dhlb.errors import InvalidParameterError, NonFiniteError, ShapeError
from dhlb.fem import bundle_matrices
from dhlb.geometry.euclidean import EuclideanComplex
from dhlb.mesh import TetMesh, box_tet_mesh, owned_rows, tet_part, vertex_layout
from dhlb.mesh.partition import box_tet_part
from dhlb.vortex import FilamentField, velocity_bundle, vortex_ring

LOWER, UPPER = -1.0, (1.0, 2.0, 3.0)
FIELDS = ("rank", "parts", "vertices", "owned", "owned_range", "cells", "local_cells", "owned_cells")


def _axes(m):
    return (m,) * 3 if np.ndim(m) == 0 else tuple(m)


def _slab_ids(m, parts):
    """Part id of every box vertex: rank r owns the x planes r (m0+1) // P .. (r+1) (m0+1) // P - 1."""
    m0, m1, m2 = _axes(m)
    n = m0 + 1
    first = np.array([r * n // parts for r in range(parts + 1)])
    plane_rank = np.searchsorted(first, np.arange(n), side="right") - 1
    return np.repeat(plane_rank, (m1 + 1) * (m2 + 1))


def _cases():
    for m in (3, 7, (4, 5, 6), (1, 2, 3)):
        for parts in (1, 2, 3, 5):
            if parts <= _axes(m)[0] + 1:
                yield m, parts


@pytest.mark.parametrize("m,parts", list(_cases()))
def test_box_part_equals_the_part_of_the_whole_box(m, parts):
    box = box_tet_mesh(m, LOWER, UPPER)
    layout = vertex_layout(_slab_ids(m, parts), parts)
    assert np.array_equal(layout.order, np.arange(box.points.shape[0]))  # the slabs keep the box numbering
    owned = np.zeros(box.points.shape[0], np.int64)
    cells = np.zeros(box.tets.shape[0], np.int64)
    for r in range(parts):
        whole = tet_part(box.tets, layout, r)
        part, points, bf = box_tet_part(m, LOWER, UPPER, r, parts)
        for name in FIELDS:
            a, b = getattr(part, name), getattr(whole, name)
            assert type(a) is type(b), name
            if isinstance(a, np.ndarray):
                assert a.dtype == b.dtype, name
                assert not a.flags.writeable, name
            assert np.array_equal(a, b), (name, r)
        assert np.array_equal(box.tets[part.cells], part.vertices[part.local_cells])
        assert points.dtype == np.float64 and points.shape == (part.vertices.size, 3)
        assert np.array_equal(points.view(np.uint64), box.points[part.vertices].view(np.uint64))  # bitwise
        local_of = np.full(box.points.shape[0], -1, np.int64)
        local_of[part.vertices] = np.arange(part.vertices.size)
        expected = local_of[box.boundary_faces]
        expected = expected[np.all(expected >= 0, axis=1)]
        assert bf.dtype == np.int64 and bf.shape == expected.shape
        assert np.array_equal(bf, expected)  # same rows (orientation included), same order
        owned[part.owned_range[0]:part.owned_range[1]] += 1
        cells[part.cells[part.owned_cells]] += 1
    assert np.all(owned == 1) and np.all(cells == 1)


def test_a_rank_owns_whole_x_planes_in_balanced_slabs():
    sizes = []
    for r in range(4):
        part, points, _ = box_tet_part((9, 2, 3), LOWER, UPPER, r, 4)
        lo, hi = part.owned_range
        assert lo % 12 == 0 and hi % 12 == 0  # (2 + 1)(3 + 1) vertices per plane
        sizes.append((hi - lo) // 12)
        assert np.unique(points[part.owned, 0]).size == sizes[-1]  # whole planes x = const
    assert sizes == [2, 3, 2, 3]  # 10 planes over 4 ranks: r * 10 // 4 = 0, 2, 5, 7, 10


def test_the_whole_box_is_never_built(monkeypatch):
    import dhlb.examples
    import dhlb.mesh.tet

    def refuse(*args, **kwargs):
        raise AssertionError("the whole box was built")

    for mod, name in ((dhlb.mesh.tet, "check_tet_mesh"), (dhlb.mesh.tet, "box_tet_mesh"),
                      (dhlb.examples, "cube_nd"), (dhlb.mesh.tet, "cube_nd")):
        monkeypatch.setattr(mod, name, refuse)
    part, points, bf = box_tet_part(5, LOWER, UPPER, 1, 3)
    assert part.cells.size == 3 * 6 * 25 and points.shape == (4 * 36, 3) and bf.shape[0] > 0


_RING = FilamentField([vortex_ring(0.8, center=(0.01, 0.52, 1.03), n=48)], 2 * np.pi, core_radius=0.15)


def _matrices(X, P):
    return bundle_matrices(velocity_bundle(X, P, _RING, 1.0), EuclideanComplex(X, points=P))


def _assert_bitwise(local, serial, what):
    for a, b, name in zip(local, serial, ("indptr", "indices", "data")):
        assert a.dtype == b.dtype, (what, name)
        assert np.array_equal(a, b), f"{what}: {name} differs"


@pytest.mark.parametrize("m,parts", [(7, 2), (7, 3), ((4, 5, 6), 5)])
def test_owned_rows_of_the_vortex_matrices_are_bitwise_serial(m, parts):
    box = box_tet_mesh(m, LOWER, UPPER)
    A, M = _matrices(box.complex, box.points)
    for r in range(parts):
        part, points, _ = box_tet_part(m, LOWER, UPPER, r, parts)
        local = TetMesh.from_validated(points, part.local_cells)
        Al, Ml = _matrices(local.complex, local.points)
        lo, hi = part.owned_range
        for S, Sl, name in ((M, Ml, "M"), (A, Al, "A")):
            R = sp.csr_matrix(S)[lo:hi]
            R.sort_indices()
            serial = R.indptr.astype(np.int64), R.indices.astype(np.int64), R.data
            _assert_bitwise(owned_rows(Sl, part), serial, f"{name} rank {r}")


@pytest.mark.parametrize("kwargs,error", [
    ({"parts": 5}, InvalidParameterError),                  # m0 + 1 = 4 planes for 5 ranks
    ({"parts": 0}, InvalidParameterError),
    ({"parts": True}, InvalidParameterError),
    ({"parts": 2.0}, InvalidParameterError),
    ({"rank": 2}, InvalidParameterError),
    ({"rank": -1}, InvalidParameterError),
    ({"rank": 1.0}, InvalidParameterError),
    ({"m": 0}, InvalidParameterError),
    ({"m": (3, 3)}, InvalidParameterError),
    ({"m": 2.5}, InvalidParameterError),
    ({"upper": (1.0, -2.0, 3.0)}, InvalidParameterError),  # upper < lower on y
    ({"lower": 1.0}, InvalidParameterError),                # lower == upper on x
    ({"lower": (0.0, 0.0)}, ShapeError),
    ({"upper": (1.0, np.inf, 3.0)}, NonFiniteError),
])
def test_box_part_refuses_bad_arguments(kwargs, error):
    args = {"m": (3, 4, 5), "lower": LOWER, "upper": UPPER, "rank": 1, "parts": 2} | kwargs
    with pytest.raises(error):
        box_tet_part(args["m"], args["lower"], args["upper"], args["rank"], args["parts"])


def test_box_part_accepts_as_many_ranks_as_planes():
    for r in range(4):
        part, _, _ = box_tet_part((3, 4, 5), LOWER, UPPER, r, 4)
        assert part.n_owned == 30 and part.owned_range == (30 * r, 30 * r + 30)
