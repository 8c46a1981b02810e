"""Fields with prescribed singularities (issue 21, ``dhlb.fields.prescribed_field``): the closed forms.

Derives, from the definitions in ``docs/conventions.md``:

1. If ``z`` is parallel for the connection ``r_ab e^{iδ_ab}`` and ``|δ| < π``, its rotation form is
   ``ξ = δ``; the face condition ``Σ_h s_h δ_h = 2πk − Ω`` then gives the index ``(Σ s ξ + Ω)/2π = k``.
2. One triangle: ``|Σ s δ| < 3π`` and ``|Ω| < π`` leave exactly ``k ∈ {−1, 0, 1}``.
3. The tree–cotree sweep (leaves first, ``x_f = r_f + Σ_children x_c``) solves every face equation
   of a closed surface whose right-hand sides sum to zero — re-implemented here with exact
   symbols on an octahedron.
4. Minimal norm: on a 4×4 torus (exact rationals) ``C d₀ = 0`` and ``rank C = n₁ − (N − 1)``
   (faces and the two generators), i.e. ker C = im d₀; hence ``δ = δ_p − d₀ L⁻¹ d₀ᵀ W δ_p`` with
   ``d₀ᵀ W δ = 0`` is the Lagrange (KKT) minimiser ``δ = W⁻¹ Cᵀ λ`` of ``δᵀ W δ`` subject to
   ``C δ = t``. Cross-checked numerically against the code on the torus and on spot.
"""

from __future__ import annotations

import os
import sys

import numpy as np
import sympy as sp

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))

# 1. the rotation form of a parallel section of the changed connection
rho, delta, phi_a = sp.symbols("rho delta phi_a", real=True)
z_a = sp.exp(sp.I * phi_a)
z_b = sp.exp(sp.I * (rho + delta)) * z_a                    # z_b = r e^{iδ} z_a, r = e^{iρ}
ratio = sp.simplify(z_b / (sp.exp(sp.I * rho) * z_a))          # z_b / (r z_a): its argument is ξ
assert sp.simplify(ratio - sp.exp(sp.I * delta)) == 0          # ξ = arg e^{iδ} = δ for δ ∈ (−π, π]
d1, d2, d3, Om, k = sp.symbols("d1 d2 d3 Omega k", real=True)
s = (1, -1, 1)
face = sp.Eq(s[0] * d1 + s[1] * d2 + s[2] * d3, 2 * sp.pi * k - Om)
d3_sol = sp.solve(face, d3)[0]
index = (s[0] * d1 + s[1] * d2 + s[2] * d3_sol + Om) / (2 * sp.pi)
assert sp.simplify(index - k) == 0
print("1. xi = delta for a parallel section of r e^{i delta}; face condition => index k")

# 2. the integer indices one triangle can carry
for om in (sp.Rational(-99, 100) * sp.pi, 0, sp.Rational(1, 2) * sp.pi, sp.Rational(99, 100) * sp.pi):
    ks = [kk for kk in range(-5, 6) if abs(2 * sp.pi * kk - om) < 3 * sp.pi]
    assert ks == [-1, 0, 1], (om, ks)
print("2. |2 pi k - Omega| < 3 pi with |Omega| < pi  <=>  k in {-1, 0, 1}")

# 3. tree–cotree sweep on an octahedron, exact symbols
F = [(0, 2, 4), (0, 4, 3), (0, 3, 5), (0, 5, 2), (1, 4, 2), (1, 3, 4), (1, 5, 3), (1, 2, 5)]
edges = sorted({tuple(sorted((f[i], f[(i + 1) % 3]))) for f in F for i in range(3)})
eid = {e: i for i, e in enumerate(edges)}
g = list(sp.symbols("g0:7")) + [None]
g[7] = -sum(g[:7])                                           # Σ_f g_f = 0 (Poincaré–Hopf)
tree_parent = {1: 2, 2: 0, 3: 0, 4: 0, 5: 0}                 # a spanning tree of the vertices
tree = {eid[tuple(sorted((v, p)))] for v, p in tree_parent.items()}
he = {}                                                     # edge -> [(face, sign)]
for f, t in enumerate(F):
    for i in range(3):
        a, b = t[i], t[(i + 1) % 3]
        he.setdefault(eid[tuple(sorted((a, b)))], []).append((f, 1 if a < b else -1))
dual = {e: he[e] for e in range(len(edges)) if e not in tree}
parent, via, order, seen = {0: None}, {}, [0], {0}         # BFS cotree from face 0
for f in order:
    for e, ((f1, s1), (f2, s2)) in dual.items():
        for mine, other in (((f1, s1), (f2, s2)), ((f2, s2), (f1, s1))):
            if mine[0] == f and other[0] not in seen:
                seen.add(other[0])
                parent[other[0]], via[other[0]] = f, (e, other[1])
                order.append(other[0])
assert len(order) == len(F) and len(tree) + len(via) == len(edges)   # genus 0: no generator edges
x = {f: g[f] for f in range(len(F))}                         # δ = 0 on tree edges: r_f = g_f
for f in reversed(order[1:]):
    x[parent[f]] = x[parent[f]] + x[f]
dval = {e: 0 for e in tree}
for f, (e, sgn) in via.items():
    dval[e] = sgn * x[f]
for f, t in enumerate(F):
    lhs = sum((1 if t[i] < t[(i + 1) % 3] else -1) * dval[eid[tuple(sorted((t[i], t[(i + 1) % 3])))]]
              for i in range(3))
    assert sp.expand(lhs - g[f]) == 0, f
print("3. the leaves-first subtree sums solve all 8 face equations of the octahedron exactly")

# 4. ker C = im d0 on a 4x4 torus (exact), then the code's delta is the KKT minimiser
import scipy.sparse as ssp  # noqa: E402
import scipy.sparse.linalg as ssl  # noqa: E402

from dhlb.fields import prescribed_field  # noqa: E402

m = 4
idx = np.arange(m * m).reshape(m, m)
Ft = []
for i in range(m):
    for j in range(m):
        a, b, c, d = idx[i, j], idx[(i + 1) % m, j], idx[(i + 1) % m, (j + 1) % m], idx[i, (j + 1) % m]
        Ft += [(a, b, c), (a, c, d)]
Ft = np.array(Ft)
u, v = np.meshgrid(np.arange(m) * 2 * np.pi / m, np.arange(m) * 2 * np.pi / m, indexing="ij")
Vt = np.stack([(2 + np.cos(v)) * np.cos(u), (2 + np.cos(v)) * np.sin(u), np.sin(v)], -1).reshape(-1, 3)
res = prescribed_field(Vt, Ft, 1, {0: 1, 9: -1}, weights="cotan")
X = res.mesh.complex
E = X.simplices(1)
n1, N = len(E), X.n_vertices
d0 = sp.zeros(n1, N)
for e, (a, b) in enumerate(E):
    d0[e, a], d0[e, b] = -1, 1
mf = res.mesh.faces
rows = []
for t in mf:
    row = [0] * n1
    for i in range(3):
        a, b = int(t[i]), int(t[(i + 1) % 3])
        row[int(np.searchsorted(E[:, 0] * N + E[:, 1], min(a, b) * N + max(a, b)))] += 1 if a < b else -1
    rows.append(row)
G = res.generators.toarray()
C = sp.Matrix(rows + G.tolist())
assert C * d0 == sp.zeros(C.rows, N)
assert C.rank() == n1 - (N - 1) == len(mf) - 1 + G.shape[0]
print(f"4. torus {m}x{m}: C d0 = 0 and rank C = n1 - (N - 1) = {n1 - N + 1}: ker C = im d0")

# numeric cross-check: the code's δ equals the KKT minimiser W⁻¹Cᵀλ, C δ = t
for name, VF, n, pres in [("torus 4x4", (Vt, Ft), 1, {0: 1, 9: -1}),
                         ("spot", None, 4, {0: 1, 1000: 1, 2000: 1, 3000: 1, 4000: 1, 5000: 1, 1500: 1, 2500: 1})]:
    if VF is None:
        from dhlb.io import example_path, read_surface

        VF = read_surface(example_path("spot.obj"))
    VV, FF = VF
    r = prescribed_field(VV, FF, n, pres)
    mesh = r.mesh
    a, b = mesh.faces.ravel(), np.roll(mesh.faces, -1, axis=1).ravel()

    Cf = ssp.csr_matrix((np.where(a < b, 1.0, -1.0), (np.arange(a.size) // 3, mesh.halfedge_edge)),
                        shape=(mesh.n_faces, len(r.delta)))
    # the face rows sum to zero with the orientation (closed surface): drop the last one
    Cn = ssp.vstack([Cf[:-1], r.generators.astype(float)]).tocsr()
    t = np.concatenate([2 * np.pi * r.prescribed - n * r.tangent.face_curvature, r.holonomy])
    t = np.delete(t, mesh.n_faces - 1)
    Winv = 1.0 / r.edge_weights
    lam = ssl.spsolve((Cn @ ssp.diags(Winv) @ Cn.T).tocsc(), t)
    kkt = Winv * (Cn.T @ lam)
    assert np.allclose(Cn @ kkt, t, atol=1e-9) and np.allclose(Cf @ kkt, Cf @ r.delta, atol=1e-9)
    err = float(np.max(np.abs(kkt - r.delta)))
    assert err < 1e-8, (name, err)
    print(f"   {name}: |delta_code - delta_KKT|_max = {err:.1e}")
print("derive_prescribed_field: all identities hold")
