"""Seed part 3, Lemma 8 and Theorem 16 (the n-dimensional cotangent formula), n = 2 and 3.

c^ij = ∫_σ <dx_i, dx_j> = vol(σ) <∇x_i, ∇x_j> (the P1 stiffness from barycentric gradients) equals

    -cot(α_ij) vol(σ∖{i,j}) / (n(n-1))   (i ≠ j),        vol(σ∖{i}) / (n h_i)   (i = j),

α_ij the interior dihedral angle between the facets σ∖{i} and σ∖{j}, h_i the height over σ∖{i}.
Lemma 8: ∇x_i = -N_i / h_i (N_i the outward unit normal of σ∖{i}).

Symbolic proof with a general simplex placed so that everything is rational:
  n = 2: p_k = 0, p_i = (a, 0), p_j = (b, c), a, c > 0   (angle at k between the edges to i, j);
  n = 3: p_k = 0, p_l = (d, 0, 0), p_i = (a1, a2, 0), p_j = (b1, b2, b3), d, a2, b3 > 0
         (dihedral angle along the edge kl; σ∖{i,j} = kl).
The proof of Theorem 16 uses "n! vol σ = (n-2)! h_i h_j sin α vol(σ∖{i,j})"; that is misprinted:
the true relation is n(n-1) vol(σ) sin α = h_i h_j vol(σ∖{i,j}) (sin α on the other side), which is
what the formula needs; both are tested.
"""

import sympy as sp
from _common import check


def gradients(pts):
    """Barycentric gradients of the simplex with vertex rows pts (n+1, n)."""
    n = pts.cols
    e = sp.Matrix.vstack(*[pts[k, :] - pts[0, :] for k in range(1, n + 1)])      # rows e_k
    inv = e.inv()                                                                 # λ_k = (E^{-T}(p - p_0))_k
    grads = [inv[:, k - 1] for k in range(1, n + 1)]
    return [-sum(grads, sp.zeros(n, 1))] + grads, sp.Abs(e.det()) / sp.factorial(n)


def main() -> None:
    print("Lemma 8 and Theorem 16 (cotangent formula)")
    a, c = sp.symbols("a c", positive=True)
    b = sp.Symbol("b", real=True)
    # n = 2, local order (i, j, k) = (0, 1, 2)
    pts = sp.Matrix([[a, 0], [b, c], [0, 0]])
    g, vol = gradients(pts)
    cot_k = b / c                                  # angle at p_k between (a, 0) and (b, c)
    check(sp.simplify(vol * (g[0].T * g[1])[0] + cot_k / 2) == 0, "n = 2: c^ij = -cot(α_k)/2")
    edge = lambda u, v: (pts[u, :] - pts[v, :]).norm()
    for i, (j, k) in ((0, (1, 2)), (1, (0, 2)), (2, (0, 1))):
        h = 2 * vol / edge(j, k)
        assert sp.simplify(vol * (g[i].T * g[i])[0] - edge(j, k) / (2 * h)) == 0, i
    check(True, "n = 2: c^ii = vol(σ∖i)/(2 h_i) for every vertex")

    # n = 3, local order (i, j, k, l) = (0, 1, 2, 3)
    d, a2, b3 = sp.symbols("d a2 b3", positive=True)
    a1, b1, b2 = sp.symbols("a1 b1 b2", real=True)
    pts = sp.Matrix([[a1, a2, 0], [b1, b2, b3], [0, 0, 0], [d, 0, 0]])
    g, vol = gradients(pts)
    cot_kl = b2 / b3                               # half-planes through the x-axis towards p_i, p_j
    check(sp.simplify(vol * (g[0].T * g[1])[0] + cot_kl * d / 6) == 0,
          "n = 3: c^ij = -cot(α_ij) |kl| / 6 (dihedral angle along the opposite edge)")

    def face_data(i):
        f = [v for v in range(4) if v != i]
        u, v = pts[f[1], :] - pts[f[0], :], pts[f[2], :] - pts[f[0], :]
        nrm = u.cross(v)
        area2 = (nrm * nrm.T)[0] / 4                              # squared facet area
        # outward unit normal: pointing away from p_i
        sign = sp.sign(sp.simplify((nrm * (pts[f[0], :] - pts[i, :]).T)[0]))
        return area2, sign * nrm.T / sp.sqrt(4 * area2)

    for i in range(4):
        area2, unit = face_data(i)
        h = 3 * vol / sp.sqrt(area2)
        assert sp.simplify(vol * (g[i].T * g[i])[0] - area2 / (9 * vol)) == 0          # = vol(σ∖i)/(3 h_i)
        assert sp.simplify(g[i] + unit / h) == sp.zeros(3, 1)                          # Lemma 8
    check(True, "n = 3: c^ii = vol(σ∖i)/(3 h_i) and ∇x_i = -N_i/h_i for every vertex")

    # the relation in the proof: n(n-1) vol sin α = h_i h_j vol(σ∖{i,j})  (n = 3, pair (0, 1))
    sin_a = b3 / sp.sqrt(b2**2 + b3**2)
    h0 = 3 * vol / sp.sqrt(face_data(0)[0])
    h1 = 3 * vol / sp.sqrt(face_data(1)[0])
    true_rel = sp.simplify(6 * vol * sin_a - h0 * h1 * d)
    printed = sp.simplify(6 * vol - h0 * h1 * sin_a * d)
    check(true_rel == 0 and printed != 0,
          "proof of Thm 16: n(n-1) vol σ sin α = h_i h_j vol(σ∖ij) holds; "
          "printed n! vol σ = (n-2)! h_i h_j sin α vol(σ∖ij) does not")


if __name__ == "__main__":
    main()
