"""Benchmark of the FEM assembly (issue 16) against a plain numpy P1 assembly timed in the same run.

Prints one table, every figure measured in this run (best of three, the machine is shared):

| case | ratio | target |
|---|---|---|
| triangles (stanford-bunny): ``EuclideanComplex`` + bundle mass + Dirichlet ÷ plain P1 | ≤ 1.2× |
| tetrahedra (1M-tet Kuhn box): the same ÷ plain P1 | ≤ 3× |
| ``mass_matrix`` alone ÷ ``bundle_matrices`` (bunny, box) | ≤ 0.5× |
| tetrahedra from intrinsic edge lengths (200k-tet flat 3-torus) ÷ from points, per tet | ≤ 1.5× |

"Plain P1" is the textbook vectorised numpy assembly from the points: edge vectors, barycentric
gradients (cross products), volumes, the local stiffness ``vol ∇λ_i·∇λ_j`` and mass
``vol (1 + δ_ij) / ((n+1)(n+2))``, both scattered by ``scipy.sparse.coo_matrix(...).tocsr()``.
Both sides start from the points (resp. edge lengths) of a complex whose topology is built; the
line bundle (connection and curvature of a uniform magnetic field) is input, not timed.

Run:  OPENBLAS_NUM_THREADS=1 python benchmarks/bench_fem.py   (needs /work/shared/meshes for the bunny)
"""
from __future__ import annotations

import os
import sys
import time
from pathlib import Path

import numpy as np
import scipy.sparse as sp

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))

from dhlb import EuclideanComplex, HermitianLineBundle, SimplicialComplex
from dhlb.examples import torus_nd
from dhlb.fem import bundle_matrices, mass_matrix
from dhlb.mesh import box_tet_mesh

BUNNY = Path(os.environ.get("DHLB_MESHES", "/work/shared/meshes")) / "stanford-bunny.obj"


def best(fn, reps: int = 3) -> float:
    t = float("inf")
    for _ in range(reps):
        t0 = time.perf_counter()
        fn()
        t = min(t, time.perf_counter() - t0)
    return t


def plain_p1(P: np.ndarray, T: np.ndarray) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """Textbook numpy P1 stiffness and mass of triangles or tetrahedra in R³ (the reference cost)."""
    m, k = T.shape
    n = k - 1
    E = P[T[:, 1:]] - P[T[:, :1]]                        # (m, n, 3)
    grads = np.empty((m, k, 3))
    if n == 3:
        c = np.cross(E[:, [1, 2, 0]], E[:, [2, 0, 1]])   # e_b × e_c: ∇λ_a · det
        det = np.einsum("mi,mi->m", E[:, 0], c[:, 0])
        grads[:, 1:] = c / det[:, None, None]
        vol = np.abs(det) / 6.0
    else:
        nrm = np.cross(E[:, 0], E[:, 1])
        a2 = np.einsum("mi,mi->m", nrm, nrm)
        grads[:, 1] = np.cross(E[:, 1], nrm) / a2[:, None]
        grads[:, 2] = np.cross(nrm, E[:, 0]) / a2[:, None]
        vol = 0.5 * np.sqrt(a2)
    grads[:, 0] = -grads[:, 1:].sum(axis=1)
    K = vol[:, None, None] * np.einsum("mai,mbi->mab", grads, grads)
    Mref = (np.ones((k, k)) + np.eye(k)) / ((n + 1) * (n + 2))
    M = vol[:, None, None] * Mref
    rows = np.repeat(T, k, axis=1).ravel()
    cols = np.tile(T, (1, k)).ravel()
    N = P.shape[0]
    return (sp.coo_matrix((K.ravel(), (rows, cols)), shape=(N, N)).tocsr(),
            sp.coo_matrix((M.ravel(), (rows, cols)), shape=(N, N)).tocsr())


def field_bundle(X: SimplicialComplex, P: np.ndarray, B: float) -> HermitianLineBundle:
    """Uniform field ``B dx∧dy``: potential ``(B/2)(-y, x, 0)`` integrated exactly along the edges."""
    E = X.simplices(1)
    ang = 0.5 * B * (P[E[:, 0], 0] * P[E[:, 1], 1] - P[E[:, 0], 1] * P[E[:, 1], 0])
    T = X.simplices(2)
    e1, e2 = P[T[:, 1]] - P[T[:, 0]], P[T[:, 2]] - P[T[:, 0]]
    return HermitianLineBundle.from_angles(X, ang, 0.5 * B * (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]))


def warm(X: SimplicialComplex) -> None:
    """Topology caches (the CSR pattern of the complex), built once per complex, not per assembly."""
    X.vertex_adjacency  # noqa: B018
    X.top_entry_positions  # noqa: B018


def ours(X, L, points=None, lengths=None, what="both"):
    geo = EuclideanComplex(X, points=points, edge_lengths=lengths)
    return mass_matrix(L, geo) if what == "mass" else bundle_matrices(L, geo)


def check(X, P, L) -> None:
    """The benchmark compares like with like: at zero field both give the same matrices."""
    A, M = bundle_matrices(HermitianLineBundle.trivial(X), EuclideanComplex(X, points=P))
    K, Mp = plain_p1(P, X.simplices(X.dim))
    assert abs(A - K).max() <= 1e-10 * abs(K).max() and abs(M - Mp).max() <= 1e-12 * abs(Mp).max()


def case(name, X, P, L):
    warm(X)
    check(X, P, L)
    T = X.simplices(X.dim)
    t_p1 = best(lambda: plain_p1(P, T))
    t_geo = best(lambda: EuclideanComplex(X, points=P).barycentric_gradient_gram)
    t_both = best(lambda: ours(X, L, points=P))
    t_mass = best(lambda: ours(X, L, points=P, what="mass"))
    geo = EuclideanComplex(X, points=P)
    geo.barycentric_gradient_gram  # noqa: B018
    t_pre = best(lambda: bundle_matrices(L, geo))
    m = T.shape[0]
    print(f"  {name}: {m:,} simplices; plain P1 {t_p1:.3f} s, ours {t_both:.3f} s "
          f"({m / t_both:,.0f}/s; geometry {t_geo:.3f} s, assembly with geometry built {t_pre:.3f} s), "
          f"mass_matrix alone {t_mass:.3f} s")
    return t_p1, t_both, t_mass, t_pre


def main() -> None:
    print(f"OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS')}; load: {os.getloadavg()}")
    from dhlb.io import read_surface

    V, F = read_surface(BUNNY)
    X = SimplicialComplex(F)
    used = X.vertex_labels
    P = np.ascontiguousarray(V[used] / np.ptp(V, axis=0).max())
    tri = case("stanford-bunny (triangles)", X, P, field_bundle(X, P, 2 * np.pi * 40))

    mesh = box_tet_mesh(55)
    X = SimplicialComplex(mesh.tets)
    P = mesh.points
    tet = case("Kuhn box 55³ (tetrahedra)", X, P, field_bundle(X, P, 2 * np.pi * 3))

    Xt, Pt = torus_nd(3, 32, return_points=True)
    Ed = Pt[Xt.simplices(1)[:, 1]] - Pt[Xt.simplices(1)[:, 0]]
    lengths = np.linalg.norm(Ed - np.round(Ed), axis=1)
    Lt = HermitianLineBundle.trivial(Xt)
    warm(Xt)
    mt = Xt.n_simplices(3)
    t_len = best(lambda: ours(Xt, Lt, lengths=lengths))
    per_len, per_pts = t_len / mt, tet[1] / X.n_simplices(3)
    print(f"  flat 3-torus 32³ from edge lengths: {mt:,} tets, {t_len:.3f} s ({mt / t_len:,.0f} tets/s)")

    rows = [
        ("triangles: EuclideanComplex + bundle mass + Dirichlet ÷ plain P1",
         f"{tri[1] / tri[0]:.2f}× ({tri[3] / tri[0]:.2f}× with the geometry built beforehand)", "≤ 1.2×"),
        ("tetrahedra: the same ÷ plain P1",
         f"{tet[1] / tet[0]:.2f}× ({tet[3] / tet[0]:.2f}× with the geometry built beforehand; "
         f"{X.n_simplices(3) / tet[1] / 1e3:,.0f}k tets/s)", "≤ 3×"),
        ("`mass_matrix` alone ÷ `bundle_matrices`",
         f"{tri[2] / tri[1]:.2f}× (bunny), {tet[2] / tet[1]:.2f}× (box)", "≤ 0.5×"),
        ("tetrahedra from intrinsic edge lengths ÷ from points (per tet)", f"{per_len / per_pts:.2f}×", "≤ 1.5×"),
    ]
    print("\n| case (from points to matrices, both sides timed in one run) | now | target |\n|---|---|---|")
    for r in rows:
        print("| " + " | ".join(r) + " |")


if __name__ == "__main__":
    main()
