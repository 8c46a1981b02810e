"""Part 1, Appendix B (discrete Poincaré–Hopf for n-direction fields): the index sum is n·χ, not 2n·χ.

On an n-smooth closed triangle mesh Ω_t = n σ_t with σ_t = Σ_{v ∈ t} s_v α_v^t - π, and since the
rescaled angles around each vertex sum to 2π,

    Σ_t σ_t = 2π|V| - π|F| = 2π(|V| - |E| + |F|) = 2πχ      (closed surface: 2|E| = 3|F|),

so Σ_t Ω_t = 2πnχ (printed correctly) and Σ_t index_t = (1/2π) Σ_t (dω + Ω)_t = nχ.  The printed
theorem says "2nχ".  This script proves the counting identity symbolically and checks it on the
icosahedron and an icosphere with random n-direction fields built exactly as in part 1
(Eq. 6.1-6.3, 6.9): the face indices are integers summing to nχ = 2n.
"""

import numpy as np
import sympy as sp
from _common import check


def icosahedron():
    t = (1 + 5 ** 0.5) / 2
    v = np.array([[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t],
                  [0, -1, -t], [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]], float)
    f = np.array([[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4],
                  [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8],
                  [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]])
    return v / np.linalg.norm(v, axis=1)[:, None], f


def subdivide(v, f):
    mid, verts, faces = {}, list(v), []

    def midpoint(a, b):
        key = (min(a, b), max(a, b))
        if key not in mid:
            p = verts[a] + verts[b]
            verts.append(p / np.linalg.norm(p))
            mid[key] = len(verts) - 1
        return mid[key]

    for a, b, c in f:
        ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
        faces += [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
    return np.array(verts), np.array(faces)


def index_sum(v, f, n, rng):
    nv = len(v)
    angle = {}                                   # angle[(i, j, k)] at i in face (i, j, k)
    nxt = {}
    for tri in f:
        for a, b, c in ((tri[0], tri[1], tri[2]), (tri[1], tri[2], tri[0]), (tri[2], tri[0], tri[1])):
            u, w = v[b] - v[a], v[c] - v[a]
            angle[a, b, c] = np.arccos(np.clip(u @ w / np.linalg.norm(u) / np.linalg.norm(w), -1, 1))
            nxt[a, b] = c
    total = np.zeros(nv)
    for (a, _b, _c), ang in angle.items():
        total[a] += ang
    s = 2 * np.pi / total                        # Eq. 6.1
    theta = {}                                   # rescaled angle of edge direction p_j - p_i at i
    for i in range(nv):
        start = next(b for (a, b) in nxt if a == i)
        j, acc = start, 0.0
        while True:
            theta[i, j] = acc
            k = nxt[i, j]
            acc += s[i] * angle[i, j, k]
            j = k
            if j == start:
                break
    rho = {}
    for (i, j) in theta:
        # at j the direction p_j - p_i is the edge j->i turned by π
        rho[i, j] = n * ((theta[j, i] + np.pi) - theta[i, j])   # Eq. 6.2
    r = {e: np.exp(1j * val) for e, val in rho.items()}
    u = np.exp(1j * rng.uniform(0, 2 * np.pi, nv))              # random n-direction field
    indices, ok_curv = [], True
    for i, j, k in f:
        om = np.angle(r[i, j] * r[j, k] * r[k, i])               # Eq. 6.3
        sigma = s[i] * angle[i, j, k] + s[j] * angle[j, k, i] + s[k] * angle[k, i, j] - np.pi
        ok_curv &= abs(om - n * sigma) < 1e-9 if abs(n * sigma) < np.pi else True
        rot = sum(np.angle(u[b] / (r[a, b] * u[a])) for a, b in ((i, j), (j, k), (k, i)))
        indices.append((rot + om) / (2 * np.pi))                 # Eq. 6.9
    indices = np.array(indices)
    assert ok_curv
    assert np.allclose(indices, np.round(indices), atol=1e-9)
    return int(np.round(indices).sum()), len(v) - len({tuple(sorted(e)) for e in rho}) + len(f)


def main() -> None:
    print("Appendix B: discrete Poincaré–Hopf")
    V, E, F = sp.symbols("V E F", positive=True)
    sum_sigma = 2 * sp.pi * V - sp.pi * F                      # Σ_v 2π - π per face
    check(sp.simplify((sum_sigma - 2 * sp.pi * (V - E + F)).subs(E, sp.Rational(3, 2) * F)) == 0,
          "Σ_t σ_t = 2π|V| - π|F| = 2πχ when 2|E| = 3|F|, hence Σ_t Ω_t = 2πnχ and Σ index = nχ")
    rng = np.random.default_rng(1)
    v, f = icosahedron()
    for name, (vv, ff), ns in (("icosahedron", (v, f), (1, 2, 3, 4)), ("icosphere", subdivide(v, f), (1, 2, 4, 6))):
        for n in ns:
            for _ in range(3):
                total, chi = index_sum(vv, ff, n, rng)
                assert total == n * chi != 2 * n * chi, (name, n, total)
        check(True, f"{name} (χ = {chi}): index sums of random n-direction fields = nχ for n = {ns} (printed 2nχ)")


if __name__ == "__main__":
    main()
