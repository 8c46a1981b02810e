"""Filaments of a partitioned mesh: pieces traced on each rank's patch and stitched equal the serial filaments.

Ranks are simulated in one process: each part builds its local patch exactly as a rank would (its
tetrahedra and a halo of one layer of tetrahedra around its vertices, the local complex, the local
bundle from the velocity, ψ at its vertices), traces the pieces through its own tetrahedra, and
the pieces of all parts are stitched.
"""

from __future__ import annotations

import numpy as np
import pytest

from dhlb import SimplicialComplex
from dhlb.errors import InvalidParameterError
from dhlb.mesh import box_tet_mesh
from dhlb.mesh.tet import tet_signs
from dhlb.vortex import (
    FilamentField,
    extract_filaments,
    filament_pieces,
    hopf_link,
    stitch_pieces,
    uniform_flow,
    velocity_bundle,
    vortex_filaments,
    vortex_ring,
)
from dhlb.vortex.pipeline import filament_linking_numbers

HBAR = 1.0
SHIFT = np.array([0.013, 0.007, 0.011]) * 1.5  # as `dhlb vortex`: off the centre of the symmetric box


def linked_rings():
    """The field of `dhlb vortex --velocity linked-rings` on the box [-1.5, 1.5]^3."""
    R = 0.55 * 1.5
    return FilamentField([C + SHIFT - [0.5 * R, 0.0, 0.0] for C in hopf_link(R, n=96)], 2 * np.pi, core_radius=0.12)


def one_ring():
    return FilamentField([vortex_ring(0.9, center=SHIFT, n=96)], 2 * np.pi, core_radius=0.12)


def owners(points, n_parts, split):
    """A deterministic split of the vertices into parts: slabs in x, or blocks (many cuts)."""
    if split == "slabs":
        x = points[:, 0]
        return np.minimum(((x - x.min()) / np.ptp(x) * n_parts).astype(np.int64), n_parts - 1)
    if split == "zslabs":
        return owners(points[:, [2, 1, 0]], n_parts, "slabs")
    cells = np.floor((points - points.min(axis=0)) / np.ptp(points, axis=0) * 2.999).astype(np.int64)
    return (cells.sum(axis=1) + cells[:, 0]) % n_parts


def rank_pieces(G, points, psi, owner, rank, velocity, stats):
    """What rank ``rank`` does: build its patch from the global arrays and trace its own tetrahedra."""
    T = G.simplices(3)  # global vertex ids = compact indices of G (box_tet_mesh: labels 0 .. N-1)
    local_T = T[np.any(owner[T] == rank, axis=1)]  # the tets touching an owned vertex
    ids = np.unique(local_T)  # local vertices in increasing global order
    # a patch need not be a manifold (check_tet_mesh would refuse one of the "blocks" patches); extraction
    # needs only triangles in at most two tets, which it checks
    X = SimplicialComplex(np.searchsorted(ids, local_T))
    vid = ids[X.vertex_labels]
    assert np.array_equal(vid, ids)
    P_local = points[vid]
    rows = G.index(3, vid[X.simplices(3)])  # the same tets, sorted alike locally and globally
    assert np.array_equal(tet_signs(X, P_local), tet_signs(G, points)[rows])
    own = owner[vid[X.simplices(3)[:, 0]]] == rank  # a tet belongs to the owner of its smallest vertex
    tri_count = np.bincount(G.faces(3).ravel(), minlength=G.n_simplices(2))
    boundary = tri_count[G.index(2, vid[X.simplices(2)])] == 1  # the boundary of the whole mesh
    L = velocity_bundle(X, P_local, velocity, HBAR)
    pieces = filament_pieces(L, psi[vid], P_local, own, vertex_ids=vid, boundary=boundary)
    stats["cut ends"] = stats.get("cut ends", 0) + sum(p.ends.count("cut") for p in pieces if p.ends)
    local_count = np.bincount(X.faces(3).ravel(), minlength=X.n_simplices(2))
    gaps = np.zeros(X.n_simplices(2), bool)
    gaps[X.faces(3)[own].ravel()] = True
    gaps &= (local_count == 1) & ~boundary  # triangles of own tets whose outer tet the halo lacks
    stats["halo gaps"] = stats.get("halo gaps", 0) + int(gaps.sum())
    return pieces


def partitioned(G, points, psi, velocity, n_parts, split):
    owner = owners(points, n_parts, split)
    stats = {}
    parts = [rank_pieces(G, points, psi, owner, r, velocity, stats) for r in range(n_parts)]
    assert sum(len(p) for p in parts) >= (0 if n_parts == 1 else 1)
    return parts, stats


def assert_same_as_serial(whole, fs, G):
    """The stitched filaments are the serial ones, crossing by crossing; returns the largest point difference."""
    assert len(whole) == len(fs) > 0
    assert [f.closed for f in whole] == [f.closed for f in fs]
    diff = 0.0
    for a, b in zip(whole, fs, strict=True):
        assert np.array_equal(a.faces, G.simplices(2)[b.faces])  # the same triangles in the same order
        assert np.array_equal(a.slots, np.zeros(len(b), np.int64))
        assert a.ends == (None if b.closed else ("boundary", "boundary"))
        diff = max(diff, float(np.abs(a.points - b.points).max()))
    assert diff <= 1e-12
    assert np.array_equal(whole.tie_edges, G.simplices(1)[fs.tie_edges])
    assert np.array_equal(whole.ambiguous_tets, G.simplices(3)[fs.ambiguous_tets])
    assert np.array_equal(whole.clamped_faces, np.sort(G.simplices(2)[fs.clamped_faces], axis=0))
    assert np.array_equal(whole.degenerate_faces, np.sort(G.simplices(2)[fs.degenerate_faces], axis=0))
    return diff


@pytest.fixture(scope="module", params=["linked-rings", "ring"])
def serial(request):
    velocity = linked_rings() if request.param == "linked-rings" else one_ring()
    res = vortex_filaments(box_tet_mesh(14, lower=-1.5, upper=1.5), None, velocity, hbar=HBAR)
    assert len(res.filaments) == (2 if request.param == "linked-rings" else 1)
    return res, velocity


@pytest.mark.parametrize("split", ["slabs", "blocks"])
def test_stitched_filaments_equal_the_serial_ones(serial, split):
    res, velocity = serial
    G, points = res.mesh.complex, res.mesh.points
    stitched = []
    for n_parts in (1, 2, 3):
        parts, stats = partitioned(G, points, res.psi, velocity, n_parts, split)
        whole = stitch_pieces(parts)
        diff = assert_same_as_serial(whole, res.filament_set, G)
        print(f"{split}, P = {n_parts}: {sum(len(p) for p in parts)} pieces, {stats}, max |Δx| = {diff:.3g}")
        assert (stats["cut ends"] > 0) == (n_parts > 1)
        Lk, idx, _ = filament_linking_numbers(whole.pieces)
        assert np.array_equal(Lk, res.linking_numbers) and np.array_equal(idx, res.linking_index)
        stitched.append(whole)
    if len(res.filaments) == 2:
        assert Lk.tolist() == [[0, 1], [1, 0]]
    for other in stitched[1:]:  # the same for any number of parts
        assert all(np.array_equal(a.points, b.points) for a, b in zip(stitched[0], other, strict=True))


def test_without_boundary_the_gaps_of_a_one_layer_halo_are_still_joined(serial):
    # without `boundary`, an end at a triangle whose outer tet is missing from the patch (a one-layer halo
    # around the owned vertices lacks some) is taken for a boundary end; the stitch joins it all the same
    res, velocity = serial
    G, points = res.mesh.complex, res.mesh.points
    owner = owners(points, 3, "blocks")
    parts = []
    for r in range(3):
        T = G.simplices(3)
        ids = np.unique(T[np.any(owner[T] == r, axis=1)])
        X = SimplicialComplex(T[np.any(owner[T] == r, axis=1)])  # built from global ids: vertex_labels = ids
        assert np.array_equal(X.vertex_labels, ids)
        own = owner[X.vertex_labels[X.simplices(3)[:, 0]]] == r
        L = velocity_bundle(X, points[ids], velocity, HBAR)
        parts.append(filament_pieces(L, res.psi[ids], points[ids], np.nonzero(own)[0]))
    assert any(p.ends == ("boundary", "boundary") for part in parts for p in part)  # mistaken, but joined
    assert_same_as_serial(stitch_pieces(parts), res.filament_set, G)


@pytest.mark.parametrize("n_parts", [2, 3])
def test_open_filament_split_across_parts(n_parts):
    mesh = box_tet_mesh(12, lower=-1.5, upper=1.5)
    G, points = mesh.complex, mesh.points
    x, y, _ = points.T
    psi = (x - 0.1) + 1j * (y - 0.2)  # zero set: the vertical line (0.1, 0.2, t), from boundary to boundary
    still = uniform_flow([0.0, 0.0, 0.0])
    fs = extract_filaments(velocity_bundle(G, points, still, HBAR), psi, points)
    assert len(fs) == 1 and not fs[0].closed
    parts, stats = partitioned(G, points, psi, still, n_parts, "zslabs")
    assert [len(p) for p in parts] == [1] * n_parts and stats["cut ends"] == 2 * (n_parts - 1)
    whole = stitch_pieces(parts[::-1])  # the order of the parts does not matter
    assert_same_as_serial(whole, fs, G)
    assert np.allclose(whole[0].points[:, :2], [0.1, 0.2], rtol=0, atol=1e-12)
    assert whole[0].points[[0, -1], 2].tolist() == [-1.5, 1.5]


def test_a_missing_piece_is_named(serial):
    res, velocity = serial
    G, points = res.mesh.complex, res.mesh.points
    parts, _ = partitioned(G, points, res.psi, velocity, 3, "blocks")
    r, i = next((r, i) for r, part in enumerate(parts) for i, p in enumerate(part) if p.ends == ("cut", "cut"))
    dropped = parts[r][i]
    parts[r] = type(parts[r])(parts[r].pieces[:i] + parts[r].pieces[i + 1:])
    with pytest.raises(InvalidParameterError, match="no piece continues the filament through the triangle") as err:
        stitch_pieces(parts)
    named = {str(tuple(int(v) for v in dropped.faces[j])) for j in (0, -1)}
    assert any(t in str(err.value) for t in named)


def test_overlapping_parts_are_rejected(serial):
    res, velocity = serial
    parts, _ = partitioned(res.mesh.complex, res.mesh.points, res.psi, velocity, 2, "slabs")
    with pytest.raises(InvalidParameterError, match="two pieces start at the crossing 0 of the triangle"):
        stitch_pieces(parts + parts[:1])


def test_bad_arguments():
    mesh = box_tet_mesh(2)
    L = velocity_bundle(mesh.complex, mesh.points, uniform_flow([0.0, 0.0, 0.0]), HBAR)
    psi = (mesh.points[:, 0] - 0.3) + 1j * (mesh.points[:, 1] - 0.6)
    with pytest.raises(InvalidParameterError, match="vertex_ids must increase"):
        filament_pieces(L, psi, mesh.points, vertex_ids=np.arange(27)[::-1])
    with pytest.raises(InvalidParameterError, match=r"rows 0\.\.47"):
        filament_pieces(L, psi, mesh.points, [0, 48])
    with pytest.raises(ValueError, match="one bool per tetrahedron"):
        filament_pieces(L, psi, mesh.points, np.ones(5, bool))
    assert len(filament_pieces(L, psi, mesh.points, [])) == 0
