r"""Intrinsic mollification of zero-area faces (``dhlb.mesh.repair``; Sharp & Crane 2020, §4.5).

Definitions: a triangle with edge lengths ``l_1, l_2, l_3`` is a Euclidean triangle of positive area
iff the three *gaps* ``g_k = l_i + l_j − l_k`` (``{i, j, k} = {1, 2, 3}``) are positive. Mollification
adds one number ``δ ≥ 0`` to every edge length of the mesh, with
``δ = max(0, max_t (ε − min_k g_k(t)))``.

Derived and asserted:

1. (symbolic) Adding ``δ`` to the three lengths raises each gap by exactly ``δ``:
   ``g_k(l + δ) = g_k(l) + δ``; hence after mollification every gap of every triangle is ``≥ ε > 0``
   (every triangle is valid), and every length changed by exactly ``δ`` (no more).
2. (symbolic) ``δ`` is the smallest such number: for ``δ' < δ`` the triangle attaining the maximum
   keeps a gap ``< ε``.
3. (symbolic) Heron: ``16 A² = g_1 g_2 g_3 (l_1 + l_2 + l_3)``, so the area is positive exactly when the
   gaps are; the corner angle from the lengths, ``tan α_k = 4A / (l_i² + l_j² − l_k²)`` (law of cosines
   and ``A = ½ l_i l_j sin α_k``), and ``α_1 + α_2 + α_3 = π`` (checked at random rational triangles).
4. (numeric) On a mesh with a collinear face and a face with two coincident vertices,
   ``dhlb.mesh.repair.repair_surface`` mollifies: no vertex moves, every edge length grows by the same
   ``δ`` (to rounding), every triangle gap is ``≥ ε`` (to rounding), the code's corner angles are those of
   the intrinsic triangles (law of cosines) and sum to π per face, and the discrete Gauss–Bonnet sum of
   the mollified tangent bundle ``Σ σ_t + Σ_∂ κ = 2πχ`` holds.
"""

from __future__ import annotations

import sys
import time
import warnings

import numpy as np
import sympy as sp
from _derive_util import summary


def symbolic() -> list[str]:
    l1, l2, l3, d, eps = sp.symbols("l1 l2 l3 delta epsilon", positive=True)
    L = [l1, l2, l3]
    gaps = [L[(k + 1) % 3] + L[(k + 2) % 3] - L[k] for k in range(3)]
    moll = [(L[(k + 1) % 3] + d) + (L[(k + 2) % 3] + d) - (L[k] + d) for k in range(3)]
    for g, gm in zip(gaps, moll):
        assert sp.simplify(gm - (g + d)) == 0
    # minimality: if min gap = ε − δ exactly, any smaller δ' leaves that gap below ε
    dp = sp.symbols("deltaprime", nonnegative=True)
    g_min = eps - d
    assert sp.simplify((g_min + dp) - eps - (dp - d)) == 0   # gap after δ' is ε + (δ' − δ) < ε iff δ' < δ
    # Heron in the gaps, and the angle formula
    s_ = (l1 + l2 + l3) / 2
    heron16 = 16 * s_ * (s_ - l1) * (s_ - l2) * (s_ - l3)
    assert sp.expand(heron16 - gaps[0] * gaps[1] * gaps[2] * (l1 + l2 + l3)) == 0
    A = sp.sqrt(heron16) / 4
    cos3 = (l1**2 + l2**2 - l3**2) / (2 * l1 * l2)   # law of cosines at the corner opposite l3
    sin3 = 2 * A / (l1 * l2)
    assert sp.simplify(cos3**2 + sin3**2 - 1) == 0
    assert sp.simplify(sin3 / cos3 - 4 * A / (l1**2 + l2**2 - l3**2)) == 0
    rng = np.random.default_rng(3)
    for _ in range(20):
        a, b = (sp.Rational(int(x), 7) for x in rng.integers(3, 30, 2))
        c = sp.Rational(int(rng.integers(1, 29)), 7)
        if not (a + b > c and a + c > b and b + c > a):
            continue
        ang = [sp.atan2(4 * A.subs({l1: x, l2: y, l3: z}), x**2 + y**2 - z**2)
               for x, y, z in ((a, b, c), (b, c, a), (c, a, b))]
        assert abs(sp.N(sum(ang) - sp.pi, 40)) < sp.Float("1e-35")
    return ["gaps +δ", "δ minimal", "Heron = product of gaps", "tan α = 4A/(b²+c²−a²)", "Σα = π"]


def numeric() -> list[str]:
    from dhlb.mesh import tangent_bundle
    from dhlb.mesh.repair import repair_surface

    # an octahedron whose face (3, 1, 5) is split at a vertex 7 placed on vertex 3: two zero-area faces
    V = np.array([[1.0, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]])
    V2 = np.vstack([V, [[0.0, 0, 0], [0.0, -1.0, 0.0]]])     # 6 unused; 7 at the position of vertex 3
    F2 = [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 7, 5], [7, 1, 5], [0, 3, 5],
          [3, 1, 7]]   # (3, 1, 7) and (3, 7, 5) have two coincident vertices: zero area
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        mesh = repair_surface(V2, F2)
    assert mesh.repair.kinds == ("mollify",), mesh.repair.kinds
    assert np.array_equal(mesh.points, V2[mesh.vertex_rows])          # no vertex moved
    E = mesh.complex.simplices(1)
    L0 = np.linalg.norm(mesh.points[E[:, 1]] - mesh.points[E[:, 0]], axis=1)
    delta = mesh.repair.delta
    assert delta > 0 and np.allclose(mesh.edge_lengths - L0, delta, rtol=0, atol=1e-15)
    eps = mesh.repair.options.mollify_tol * L0.mean()
    tri = mesh.edge_lengths[mesh.halfedge_edge].reshape(-1, 3)
    gaps = tri.sum(axis=1)[:, None] - 2 * tri
    assert gaps.min() >= eps * (1 - 1e-9), (gaps.min(), eps)
    # corner angles: those of the intrinsic triangles (law of cosines), Σ = π
    a = tri[:, [1, 2, 0]]   # the edge opposite corner p is half-edge p + 1
    b, c = tri, tri[:, [2, 0, 1]]
    alpha = np.arccos(np.clip((b**2 + c**2 - a**2) / (2 * b * c), -1, 1))
    assert np.allclose(mesh.corner_angles, alpha, atol=1e-7), np.abs(mesh.corner_angles - alpha).max()
    assert np.allclose(mesh.corner_angles.sum(axis=1), np.pi, atol=1e-12)
    tb = tangent_bundle(mesh, n=1)
    total = tb.face_curvature.sum() + tb.boundary_turning.sum()
    assert abs(total - 2 * np.pi * mesh.euler_characteristic) < 1e-9
    return [f"δ = {delta:.3g}, gaps ≥ ε = {eps:.3g}", "no vertex moved", "angles of the intrinsic triangles",
            "Gauss–Bonnet on the mollified mesh"]


def main() -> int:
    t0 = time.perf_counter()
    done = symbolic() + numeric()
    summary("derive_mollification", done + [f"{time.perf_counter() - t0:.1f} s"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
