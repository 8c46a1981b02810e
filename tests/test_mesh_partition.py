"""dhlb.mesh.partition: METIS parts, the part-by-part numbering, local meshes whose owned rows are the serial ones.

The core check: every "rank" (a loop over parts, no MPI) assembles on its local mesh, and its owned
rows are bitwise equal (``array_equal``, not ``allclose``) to the owned rows of the serial assembly
on the renumbered mesh.
"""

from __future__ import annotations

import pathlib
import warnings

import numpy as np
import pytest
import scipy.sparse as sp

from dhlb.errors import InvalidParameterError, NonManifoldError, ShapeError, UnreferencedVertexError
from dhlb.fem import bundle_matrices
from dhlb.fields import energy_matrices
from dhlb.fields.directions import field_indices
from dhlb.geometry.euclidean import EuclideanComplex
from dhlb.io import example_path, read_surface, read_volume
from dhlb.mesh import (
    MeshPart,
    TetMesh,
    box_tet_mesh,
    check_tet_mesh,
    owned_rows,
    partition_vertices,
    surface_part,
    tangent_bundle,
    tet_part,
    validate_surface,
    vertex_layout,
)
from dhlb.vortex import FilamentField, velocity_bundle, vortex_ring
from tests.surface_meshes import grid, torus

DATA = pathlib.Path(__file__).resolve().parent / "data"


def _surface(name):
    if name == "bunny":
        V, F = read_surface(DATA / "bunny-7k.obj")
    elif name == "saddle":
        V, F = read_surface(example_path("saddle.obj"))
    else:
        V, F = torus(24, 12)
    mesh = validate_surface(V, F)
    return mesh.points, mesh.faces


def _tets(name):
    if name == "box":
        mesh = box_tet_mesh(8, lower=-1.5, upper=1.5)
    else:
        mesh = check_tet_mesh(*read_volume(example_path("solid-torus.mesh")))
    return mesh.points, mesh.tets


def _layout(V, C, P):
    layout = vertex_layout(partition_vertices(len(V), C, P), P)
    return layout, V[layout.order], layout.inverse[C]


def _serial_rows(S, lo, hi):
    R = sp.csr_matrix(S)[lo:hi]
    R.sort_indices()
    return R.indptr.astype(np.int64), R.indices.astype(np.int64), R.data


def _assert_bitwise(local, serial, what):
    for a, b, name in zip(local, serial, ("indptr", "indices", "data")):
        assert a.dtype == b.dtype, (what, name)
        where = np.count_nonzero(a != b) if a.shape == b.shape else a.shape
        assert np.array_equal(a, b), f"{what}: {name} differs ({where})"


# ---------------------------------------------------------------------------------------------- partition, layout


def test_partition_covers_every_vertex_deterministically():
    V, F = _surface("bunny")
    part = partition_vertices(len(V), F, 3)
    assert part.dtype == np.int64 and part.shape == (len(V),)
    assert set(np.unique(part).tolist()) == {0, 1, 2}
    assert np.array_equal(part, partition_vertices(len(V), F, 3))
    sizes = np.bincount(part)
    assert sizes.max() <= 1.05 * len(V) / 3  # METIS's default imbalance 1.03
    assert np.array_equal(partition_vertices(len(V), F, 1), np.zeros(len(V), np.int64))


@pytest.mark.parametrize("parts", [0, -1, 9, True, 2.0])
def test_partition_refuses_bad_part_counts(parts):
    with pytest.raises(InvalidParameterError, match=str(parts)):
        partition_vertices(8, [[0, 1, 2, 3], [4, 5, 6, 7]], parts)


def test_partition_refuses_bad_cells():
    with pytest.raises(ShapeError):
        partition_vertices(4, [[0, 1], [1, 2]], 2)
    with pytest.raises(ValueError, match="outside"):
        partition_vertices(3, [[0, 1, 3]], 2)


def test_layout_is_a_permutation_part_by_part():
    rng = np.random.default_rng(1)
    part = rng.integers(0, 4, 50)
    part[part == 2] = 3  # an empty part
    layout = vertex_layout(part, 4)
    assert np.array_equal(np.sort(layout.order), np.arange(50))
    assert np.array_equal(layout.inverse[layout.order], np.arange(50))
    assert np.array_equal(layout.offsets, np.r_[0, np.cumsum(np.bincount(part, minlength=4))])
    for r in range(4):
        block = layout.order[layout.offsets[r]:layout.offsets[r + 1]]
        assert np.all(part[block] == r) and np.all(np.diff(block) > 0)  # original order inside each part
    assert np.array_equal(layout.owner(np.arange(50)), part[layout.order])
    with pytest.raises(InvalidParameterError):
        vertex_layout([0, 4], 4)


# ---------------------------------------------------------------------------------------------- parts


@pytest.mark.parametrize("kind,name", [("surface", "bunny"), ("surface", "saddle"), ("tet", "box"), ("tet", "torus")])
@pytest.mark.parametrize("P", [2, 3])
def test_every_cell_owned_once_and_parts_consistent(kind, name, P):
    V, C = _surface(name) if kind == "surface" else _tets(name)
    layout, _, Cn = _layout(V, C, P)
    build = surface_part if kind == "surface" else tet_part
    owned = []
    for r in range(P):
        p = build(Cn, layout, r)
        assert isinstance(p, MeshPart) and (p.rank, p.parts) == (r, P)
        assert p.owned_range == tuple(int(x) for x in layout.offsets[r:r + 2])
        assert np.array_equal(p.vertices[p.owned], np.arange(*p.owned_range))
        nd = p.vertices.size - p.n_copies
        assert np.all(np.diff(p.vertices[:nd]) > 0) and np.all(np.diff(p.cells) > 0)
        assert np.array_equal(p.vertices[p.local_cells], Cn[p.cells])  # local cells are the global ones
        assert p.vertices.size == p.n_owned + p.halo.size
        positions = np.sort(np.r_[np.arange(p.owned.start, p.owned.stop), p.halo])
        assert np.array_equal(positions, np.arange(p.vertices.size))
        # every cell at an owned vertex is local (the owned rows see all their cells); tets: exactly these
        at_owned = np.flatnonzero(np.any(layout.owner(Cn) == r, axis=1))
        assert np.array_equal(p.cells, at_owned) if kind == "tet" else np.all(np.isin(at_owned, p.cells))
        owned.append(p.cells[p.owned_cells])
    assert np.array_equal(np.sort(np.concatenate(owned)), np.arange(len(Cn)))


def test_surface_part_splits_bowtie_fringe_vertices():
    V, F = grid(8, 8)  # vertex (i, j) is 9 i + j
    part = np.ones(len(V), np.int64)
    part[[0, 4]] = 0  # rank 0 owns (0, 0) and (0, 4): their two-ring patches meet at (0, 2) only
    layout = vertex_layout(part, 2)
    p = surface_part(layout.inverse[F], layout, 0)
    assert p.n_copies == 1 and layout.order[p.vertices[-1]] == 2
    Vl = V[layout.order][p.vertices]
    mesh = validate_surface(Vl, p.local_cells)  # accepted: one fan per vertex
    assert mesh.n_vertices == p.vertices.size
    merged = p.vertices[p.local_cells]
    merged = np.searchsorted(p.vertices[:-1], merged)  # the copy put back onto its vertex
    with pytest.raises(NonManifoldError):
        validate_surface(Vl[:-1], merged)


def test_split_parts_of_the_bunny_are_valid_surfaces():
    V, F = _surface("bunny")
    layout, Vn, Fn = _layout(V, F, 3)
    parts = [surface_part(Fn, layout, r) for r in range(3)]
    assert sum(p.n_copies for p in parts) > 0  # the bunny in three parts has bowtie fringe vertices
    for p in parts:
        assert validate_surface(Vn[p.vertices], p.local_cells).n_faces == p.cells.size


def test_parts_refuse_bad_arguments():
    V, F = grid(3, 3)
    layout = vertex_layout(np.arange(len(V)) % 2, 2)
    with pytest.raises(InvalidParameterError):
        surface_part(F, layout, 2)
    with pytest.raises(ShapeError):
        tet_part(F, layout, 0)
    with pytest.raises(UnreferencedVertexError):
        surface_part(F[:2], layout, 1)
    p = surface_part(layout.inverse[F], layout, 0)
    with pytest.raises(ShapeError):
        owned_rows(sp.identity(p.vertices.size + 1, format="csr"), p)


def test_owned_rows_refuse_a_split_copy_column():
    V, F = grid(8, 8)
    part = np.ones(len(V), np.int64)
    part[[0, 4]] = 0
    layout = vertex_layout(part, 2)
    p = surface_part(layout.inverse[F], layout, 0)
    S = sp.lil_matrix((p.vertices.size, p.vertices.size))
    S[p.owned.start, p.vertices.size - 1] = 1.0  # an owned row touching the copy
    with pytest.raises(ShapeError, match="copy"):
        owned_rows(S.tocsr(), p)


# ---------------------------------------------------------------------------------------------- bitwise equality


@pytest.mark.parametrize("name", ["bunny", "saddle", "torus"])
@pytest.mark.parametrize("P", [2, 3])
@pytest.mark.parametrize("n,s", [(4, 0.0), (1, 1.0)])
def test_surface_owned_rows_are_bitwise_serial(name, P, n, s):
    V, F = _surface(name)
    layout, Vn, Fn = _layout(V, F, P)
    A, M = energy_matrices(Vn, Fn, n=n, s=s, lumped=False)
    for r in range(P):
        p = surface_part(Fn, layout, r)
        Al, Ml = energy_matrices(Vn[p.vertices], p.local_cells, n=n, s=s, lumped=False)
        _assert_bitwise(owned_rows(Al, p), _serial_rows(A, *p.owned_range), f"A rank {r}")
        _assert_bitwise(owned_rows(Ml, p), _serial_rows(M, *p.owned_range), f"M rank {r}")


@pytest.mark.parametrize("name", ["bunny", "saddle"])
def test_face_indices_of_owned_faces_are_serial(name):
    V, F = _surface(name)
    layout, Vn, Fn = _layout(V, F, 3)
    u = np.exp(0.37j * np.arange(len(V))) * (1.5 + np.cos(np.arange(len(V))))  # nowhere zero, any section
    serial = field_indices(tangent_bundle(Vn, Fn, n=4), u).face_index
    assert np.any(serial != 0)
    for r in range(3):
        p = surface_part(Fn, layout, r)
        local = field_indices(tangent_bundle(Vn[p.vertices], p.local_cells, n=4), u[p.vertices]).face_index
        assert np.array_equal(local[p.owned_cells], serial[p.cells[p.owned_cells]])


_RING = FilamentField([vortex_ring(0.8, center=(0.01, 0.02, 0.03), n=48)], 2 * np.pi, core_radius=0.15)


def _vortex(P, T):
    mesh = TetMesh.from_validated(P, T)
    L = velocity_bundle(mesh.complex, mesh.points, _RING, 1.0)
    return L, EuclideanComplex(mesh.complex, points=mesh.points)


def test_tet_patches_need_the_unchecked_constructor():
    V, T = read_volume(pathlib.Path(__file__).parent / "data" / "octopus-low-tet.mesh")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        mesh = check_tet_mesh(V, T)
    layout, Vn, Tn = _layout(mesh.points, mesh.tets, 4)
    refused = 0
    for r in range(4):
        p = tet_part(Tn, layout, r)
        try:
            check_tet_mesh(Vn[p.vertices], p.local_cells)
        except NonManifoldError:
            refused += 1  # a fringe edge or vertex whose star in the patch is disconnected
        local = TetMesh.from_validated(Vn[p.vertices], p.local_cells)
        assert np.array_equal(local.tets, p.local_cells) and np.all(local.volumes > 0)
    assert refused > 0


@pytest.mark.parametrize("name", ["box", "torus"])
@pytest.mark.parametrize("P", [2, 3])
def test_tet_element_data_of_owned_rows_are_serial(name, P):
    """Connection, curvature, volumes and Gram matrices of every local tetrahedron equal the serial ones."""
    V, T = _tets(name)
    layout, Vn, Tn = _layout(V, T, P)
    Lg, Gg = _vortex(Vn, Tn)
    Xg = Lg.X
    for r in range(P):
        p = tet_part(Tn, layout, r)
        Ll, Gl = _vortex(Vn[p.vertices], p.local_cells)
        Xl = Ll.X
        for k, values in ((1, (Lg.connection, Ll.connection)), (2, (Lg.curvature, Ll.curvature)),
                          (3, (Gg.volumes(3), Gl.volumes(3)))):
            rows = Xg.index(k, p.vertices[Xl.simplices(k)])
            assert np.array_equal(values[0][rows], values[1]), (k, r)
        rows = Xg.index(3, p.vertices[Xl.simplices(3)])
        assert np.array_equal(Gg.barycentric_gradient_gram[rows], Gl.barycentric_gradient_gram)


# The tet kernel (dhlb.fem._fast_moments) gives each element the series degree of its own curvature and
# pads its BLAS products to a fixed column multiple, so an element's entries do not depend on its batch.
@pytest.mark.parametrize("name,P", [("box", 3), ("box", 2), ("torus", 2), ("torus", 3)])
def test_tet_owned_rows_are_bitwise_serial(name, P):
    V, T = _tets(name)
    layout, Vn, Tn = _layout(V, T, P)
    A, M = bundle_matrices(*_vortex(Vn, Tn))
    for r in range(P):
        p = tet_part(Tn, layout, r)
        Al, Ml = bundle_matrices(*_vortex(Vn[p.vertices], p.local_cells))
        _assert_bitwise(owned_rows(Ml, p), _serial_rows(M, *p.owned_range), f"M rank {r}")
        _assert_bitwise(owned_rows(Al, p), _serial_rows(A, *p.owned_range), f"A rank {r}")


def test_field_indices_of_the_parts_of_a_face_partition_add_up_to_the_whole():
    from dhlb.fields import direction_field

    V, F = read_surface(DATA / "bunny-7k.obj")
    res = direction_field(V, F, n=4)
    tb, whole = res.tangent, res.indices
    part = np.arange(tb.mesh.n_faces) % 3
    pieces = [field_indices(tb, res.u, faces=part == k) for k in range(3)]
    assert np.array_equal(sum(p.face_index for p in pieces), whole.face_index)
    assert sum(p.total for p in pieces) == whole.total
    assert abs(sum(p.total_curvature for p in pieces) - whole.total_curvature) < 1e-9
    got = np.sort(np.concatenate([p.singularities.faces for p in pieces]))
    assert np.array_equal(got, whole.singularities.faces)
    with pytest.raises(ShapeError, match="bool mask"):
        field_indices(tb, res.u, faces=np.ones(3, bool))
