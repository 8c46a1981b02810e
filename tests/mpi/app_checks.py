"""Distributed applications under MPI; run ``mpirun -n P python tests/mpi/app_checks.py OUT.json``.

Every rank runs every check; rank 0 writes the results (eigenvalues, singularities, filaments, local
sizes) to OUT.json so that the pytest driver (tests/test_mpi_apps.py) can compare the runs for
P = 1, 2, 3 with each other and with the default backend. The script exits 1 if a check failed on
any rank.
"""

import json
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from mpi4py import MPI  # noqa: E402

from dhlb.fields import direction_field, energy_matrices  # noqa: E402
from dhlb.fields.distributed import distributed_direction_field  # noqa: E402
from dhlb.io import read_surface  # noqa: E402
from dhlb.linalg import SolverOptions  # noqa: E402
from dhlb.linalg.distributed import RowBlock  # noqa: E402
from dhlb.mesh import box_tet_mesh, tangent_bundle  # noqa: E402
from dhlb.mesh.distribute import distribute_surface, distribute_tets  # noqa: E402
from dhlb.mesh.partition import owned_rows  # noqa: E402
from dhlb.vortex import vortex_filaments  # noqa: E402
from dhlb.vortex.distributed import distributed_vortex_filaments  # noqa: E402

COMM = MPI.COMM_WORLD
RANK, SIZE = COMM.rank, COMM.size
BUNNY = ROOT / "tests" / "data" / "bunny-7k.obj"


def _gathered_rows(B: RowBlock):
    """All ranks' owned rows on rank 0 as one scipy CSR (test only: the comparison needs the whole matrix)."""
    import scipy.sparse as sp

    got = COMM.gather((B.indptr, B.indices, B.data, B.start, B.stop), root=0)
    if RANK != 0:
        return None
    rows = [sp.csr_matrix((d, i, p), shape=(b - a, B.n)) for p, i, d, a, b in got]
    return sp.vstack(rows, format="csr")


def check_field_rows_bitwise():
    """Owned rows of A and M equal, bit for bit, the serial assembly of the renumbered mesh."""
    V, F = read_surface(BUNNY) if RANK == 0 else (None, None)
    loc = distribute_surface(V, F)
    tb = tangent_bundle(loc.mesh, n=4)
    A, M = energy_matrices(tb, s=0.0)
    blocks = [RowBlock(*owned_rows(S, loc.part), loc.start, loc.stop, loc.n_vertices) for S in (A, M)]
    sizes = COMM.gather((loc.n_owned, blocks[0].indptr.size - 1, loc.part.vertices.size), root=0)
    whole = [_gathered_rows(B) for B in blocks]
    if RANK != 0:
        return {}
    gm, lay = loc.global_mesh, loc.layout
    ref = energy_matrices(tangent_bundle(gm.points[lay.order], lay.inverse[gm.faces], n=4), s=0.0)
    for name, got, want in zip("AM", whole, ref):
        want = want.tocsr()
        want.sort_indices()
        assert got.shape == want.shape and np.array_equal(got.indptr, want.indptr), f"{name}: patterns differ"
        assert np.array_equal(got.indices, want.indices), f"{name}: column indices differ"
        bad = np.count_nonzero(got.data != want.data)
        assert bad == 0, f"{name}: {bad} entries differ from the serial assembly"
    N = gm.n_vertices
    for r, (owned, rows, _) in enumerate(sizes):
        assert rows == owned, f"rank {r} handed {rows} rows to PETSc, owns {owned}"
        assert owned <= -(-N // SIZE) * 1.1 + 1, f"rank {r} owns {owned} of {N} vertices"
    return {"bitwise_rows": True, "owned": [s[0] for s in sizes], "local": [s[2] for s in sizes]}


def check_tet_rows_bitwise():
    """The vortex matrices' owned rows equal, bit for bit, the serial assembly of the renumbered tet mesh."""
    from dhlb.cli.vortex import demo_velocity
    from dhlb.fem import bundle_matrices
    from dhlb.geometry import EuclideanComplex
    from dhlb.mesh import TetMesh
    from dhlb.vortex import velocity_bundle

    mesh = box_tet_mesh(10, lower=-1.0, upper=1.0)
    field, _ = demo_velocity("linked-rings", mesh.points)

    def matrices(m):
        L = velocity_bundle(m.complex, m.points, field, 1.0)
        return bundle_matrices(L, EuclideanComplex(m.complex, points=m.points))

    loc = distribute_tets(mesh if RANK == 0 else None, None)
    blocks = [RowBlock(*owned_rows(S, loc.part), loc.start, loc.stop, loc.n_vertices) for S in matrices(loc.mesh)]
    whole = [_gathered_rows(B) for B in blocks]
    if RANK != 0:
        return {}
    lay = loc.layout
    ref = matrices(TetMesh.from_validated(mesh.points[lay.order], lay.inverse[mesh.tets]))
    for name, got, want in zip("AM", whole, ref):
        want = want.tocsr()
        want.sort_indices()
        assert np.array_equal(got.indptr, want.indptr) and np.array_equal(got.indices, want.indices), \
            f"{name}: patterns differ"
        bad = np.count_nonzero(got.data != want.data)
        assert bad == 0, f"{name}: {bad} entries differ from the serial assembly"
    return {"bitwise_rows": True}


def check_field():
    V, F = read_surface(BUNNY) if RANK == 0 else (None, None)
    res = distributed_direction_field(V, F, n=4)
    if RANK != 0:
        assert res is None
        return {}
    ref = direction_field(V, F, n=4)
    rel = abs(res.eigenvalue / ref.eigenvalue - 1)
    assert rel <= 1e-12, f"eigenvalue {res.eigenvalue!r} vs {ref.eigenvalue!r}: relative {rel:.2e}"
    a, b = ref.singularities, res.singularities
    assert np.array_equal(a.faces, b.faces) and np.array_equal(a.index, b.index), "singularities differ"
    assert res.index_sum == ref.index_sum and abs(res.poincare_hopf - ref.poincare_hopf) < 1e-9
    # the phase of one process (issue 42): the same u and directions, not turned by a global angle
    du = float(np.abs(res.u - ref.u).max())
    assert du <= 1e-6, f"u differs from the serial one by {du:.2e} (a global phase?)"
    away = np.abs(ref.u) > 1e-3 * np.abs(ref.u).max()      # near a zero of u a direction is ill-conditioned
    dd = float(np.abs(res.directions - ref.directions)[away].max())
    assert dd <= 1e-4, f"directions differ from the serial ones by {dd:.2e}"
    par = res.solver["parallel"]
    assert par["petsc_rows"] == par["owned_vertices"] and sum(par["owned_vertices"]) == res.mesh.n_vertices
    return {"eigenvalue": res.eigenvalue, "eigenvalue_rel": rel, "u_diff": du, "directions_diff": dd,
            "sing_faces": b.faces.tolist(),
            "sing_index": b.index.tolist(), "parallel": {k: par[k] for k in ("owned_vertices", "local_vertices")}}


def check_field_with_boundary():
    """A mesh with boundary: the boundary rotation of the Poincaré–Hopf terms is summed over the ranks."""
    from dhlb.io import example_path

    V, F = read_surface(example_path("saddle.obj")) if RANK == 0 else (None, None)
    res = distributed_direction_field(V, F, n=4)
    if RANK != 0:
        return {}
    ref = direction_field(V, F, n=4)
    assert np.array_equal(res.singularities.faces, ref.singularities.faces), "singularities differ"
    assert res.index_sum == ref.index_sum
    rot = abs(res.indices.boundary_rotation - ref.indices.boundary_rotation)
    assert rot < 1e-9 and abs(res.poincare_hopf - ref.poincare_hopf) < 1e-9, f"boundary rotation differs by {rot:.2e}"
    return {"boundary_rotation": res.indices.boundary_rotation}


def check_vortex():
    from dhlb.cli.vortex import demo_velocity

    mesh = box_tet_mesh(16, lower=-1.0, upper=1.0)
    field, _ = demo_velocity("linked-rings", mesh.points)
    # filament points move with ψ: compare solves converged to a backward error of 1e-12 (default 1e-9)
    res = distributed_vortex_filaments(mesh if RANK == 0 else None, None, field, 1.0, solver=SolverOptions(tol=1e-12))
    loc = distribute_tets(mesh if RANK == 0 else None, None)
    sizes = COMM.gather((loc.n_owned, loc.part.vertices.size), root=0)
    if RANK != 0:
        assert res is None
        return {}
    ref = vortex_filaments(mesh, None, field, 1.0, solver=SolverOptions(tol=1e-12))
    assert len(res.filaments) == len(ref.filaments) == 2, f"{len(res.filaments)} filaments, serial {len(ref.filaments)}"
    assert all(f.closed for f in res.filaments)
    assert res.linking_numbers.tolist() == [[0, 1], [1, 0]], res.linking_numbers
    worst = 0.0
    for f in res.filaments:  # each filament equals a serial one, point by point up to the start and direction
        best = np.inf
        for g in ref.filaments:
            if len(g.points) != len(f.points):
                continue
            k = int(np.argmin(np.linalg.norm(g.points - f.points[0], axis=1)))
            h = np.roll(g.points, -k, axis=0)
            best = min(best, np.abs(h - f.points).max())
        worst = max(worst, best)
    assert worst <= 1e-10, f"filament points differ from the serial ones by {worst:.2e}"
    rel = abs(res.eigenvalue / ref.eigenvalue - 1)
    assert rel <= 1e-12, f"eigenvalue relative difference {rel:.2e}"
    return {"filament_points_diff": worst, "eigenvalue": res.eigenvalue, "eigenvalue_rel": rel,
            "n_filaments": len(res.filaments), "points": [f.points.tolist() for f in res.filaments],
            "owned": [s[0] for s in sizes], "local": [s[1] for s in sizes]}


def check_open_filament():
    """A ring that leaves the box: one open filament from boundary to boundary, cut between the ranks."""
    from dhlb.vortex import FilamentField, vortex_ring

    mesh = box_tet_mesh(14, lower=-1.0, upper=1.0)
    field = FilamentField([vortex_ring(1.0, center=(1.013, 0.007, 0.011), n=96)], 2 * np.pi, core_radius=0.15)
    res = distributed_vortex_filaments(mesh if RANK == 0 else None, None, field, 1.0, solver=SolverOptions(tol=1e-12))
    if RANK != 0:
        return {}
    ref = vortex_filaments(mesh, None, field, 1.0, solver=SolverOptions(tol=1e-12))
    assert [f.closed for f in res.filaments] == [f.closed for f in ref.filaments] == [False]
    a, b = res.filaments[0].points, ref.filaments[0].points
    assert a.shape == b.shape and np.abs(a - b).max() <= 1e-10, "the open filament differs from the serial one"
    for key in ("n_crossed_faces", "tets_by_crossed_faces", "n_triangles", "n_edges", "n_tets"):
        assert res.statistics[key] == ref.statistics[key], (key, res.statistics[key], ref.statistics[key])
    return {"open_points_diff": float(np.abs(a - b).max())}


def main():
    out = sys.argv[1]
    failed, results = 0, {}
    for check in (check_field_rows_bitwise, check_tet_rows_bitwise, check_field, check_field_with_boundary,
                  check_vortex, check_open_filament):
        try:
            data, ok = check(), True
        except AssertionError as err:
            data, ok = {"error": str(err)}, False
        oks = COMM.allgather(ok)
        failed += not all(oks)
        if RANK == 0:
            results[check.__name__] = {"ok": all(oks), **data}
            print(f"[{SIZE} ranks] {check.__name__}: {'ok' if all(oks) else 'FAILED'} {data.get('error', '')}",
                  flush=True)
    if RANK == 0:
        Path(out).write_text(json.dumps(results))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
