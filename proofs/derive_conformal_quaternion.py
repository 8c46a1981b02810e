r"""Close-to-conformal deformations of volumes (seed part 3 §2.4): the quaternion identities used by dhlb.conformal.

Quaternions are 4-tuples (w, x, y, z) of sympy expressions with the Hamilton product written out
here (nothing is imported from dhlb for the derivations; the last section compares the code).

1. H ≅ C² with the right complex structure: ``q = z₁ + j z₂``, ``z₁ = w + x i``, ``z₂ = y − z i``.
   Right multiplication by i is ``(z₁, z₂) ↦ (i z₁, i z₂)``; left multiplication by ``p = α + j β``
   is the C-linear map ``[[α, −β̄], [β, ᾱ]]`` (unitary, det = |p|²).  ``|q|² = |z₁|² + |z₂|²``.
2. For imaginary a, b: ``a b = −a·b + a × b``; ``exp(v) = cos|v| + sin|v| v/|v|`` is a unit
   quaternion and ``t ↦ exp(t v) p`` solves ``ψ' = v ψ`` (so the edge transport for a constant
   edge value g of grad u is ``η = exp(−½ g × e)``, ψ_j = η ψ_i).
3. Integrability (seed §2.4): if ``dψ(X) = −½ (g × X) ψ`` with ``g = grad u``, then the 1-form
   ``e^u ψ̄ X ψ`` is closed (symbolic in ψ, g, Hess u, X, Y).  The seed's sign is right.
4. Curvature of ``∇_X ψ = dψ(X) + A(X) ψ``, ``A(X) = ½ g × X``:
   ``F(X, Y) = ½ ((H X) × Y − (H Y) × X) + ½ g (g · (X × Y))``  (H = Hess u), and F ≡ 0 for the
   Möbius factor ``u = log(R²/|x − a|²)``.
5. Möbius map: ``f(x) = S_n(a + R² r/|r|²)`` (``r = x − a``, S_n the reflection in the plane ⊥ n)
   has ``df(X) = e^u φ̄ X φ`` with the unit quaternion ``φ = r̂ n`` (r̂ = r/|r|), and φ is parallel:
   ``dφ(X) = −½ (grad u × X) φ``.
6. Discrete holonomy: on the triangle ``x_i = c + h a``, ``x_j = c + h b``, ``x_k = c + h d`` with the
   transports ``η = exp(−½ g(midpoint) × e)``, the holonomy ``η_ki η_jk η_ij`` (i → j → k → i)
   equals ``1 − ½ F_c(x_j − x_i, x_k − x_i) + O(h³)`` (series in h, symbolic g, H, third
   derivatives): the discrete connection reproduces the curvature to second order.
7. Point charges: ``u = Σ q/|x − a|`` has ``grad u = −Σ q (x − a)/|x − a|³``.
8. The least-squares map: ``∂/∂f Σ_e w_e |f_j − f_i − E_e|² = 2 (L f − D₀ᵀ W E)`` with
   ``L = D₀ᵀ W D₀`` (D₀ the edge–vertex incidence, −1 at the tail, +1 at the head).

Finally the closed forms are compared with dhlb.conformal.quaternion and dhlb.conformal.factors.
"""

from __future__ import annotations

import sys
from pathlib import Path

import sympy as sp

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from proofs._derive_util import qmul  # noqa: E402


def qconj(q):
    return (q[0], -q[1], -q[2], -q[3])


def im(v):
    return (sp.Integer(0), v[0], v[1], v[2])


def vec(q):
    return sp.Matrix(q[1:])


def zero(expr_list):
    return all(sp.simplify(e) == 0 for e in expr_list)


def check(name, cond):
    assert cond, name
    print(f"  ok  {name}")


def part1():
    print("1. H = C^2 (right complex structure), left multiplication in SU(2)")
    w, x, y, z, a0, a1, a2, a3 = sp.symbols("w x y z a0 a1 a2 a3", real=True)
    q = (w, x, y, z)
    p = (a0, a1, a2, a3)
    I = sp.I

    def c2(q):
        return sp.Matrix([q[0] + I * q[1], q[2] - I * q[3]])

    check("q i  <->  i (z1, z2)", zero(list(c2(qmul(q, (0, 1, 0, 0))) - I * c2(q))))
    al, be = a0 + I * a1, a2 - I * a3
    U = sp.Matrix([[al, -sp.conjugate(be)], [be, sp.conjugate(al)]])
    check("p q  <->  [[a, -conj b], [b, conj a]] (z1, z2)", zero(list(sp.expand(U * c2(q) - c2(qmul(p, q))))))
    check("U^H U = |p|^2 I", zero(list(sp.expand(U.H * U - (a0**2 + a1**2 + a2**2 + a3**2) * sp.eye(2)))))
    check("det U = |p|^2", sp.simplify(U.det() - (a0**2 + a1**2 + a2**2 + a3**2)) == 0)
    zz = c2(q)
    check("|q|^2 = |z1|^2 + |z2|^2", sp.simplify(sp.expand((zz.H * zz)[0]) - (w**2 + x**2 + y**2 + z**2)) == 0)


def part2():
    print("2. products of imaginary quaternions, exponential, transport ODE")
    a = sp.Matrix(sp.symbols("a1:4", real=True))
    b = sp.Matrix(sp.symbols("b1:4", real=True))
    ab = qmul(im(a), im(b))
    check("a b = -a.b + a x b", sp.simplify(ab[0] + a.dot(b)) == 0 and zero(list(vec(ab) - a.cross(b))))
    ba = qmul(im(b), im(a))
    check("a b - b a = 2 a x b", zero([ab[k] - ba[k] - (0 if k == 0 else 2 * a.cross(b)[k - 1]) for k in range(4)]))
    t = sp.symbols("t", real=True)
    s = sp.sqrt(a.dot(a))
    E = (sp.cos(t * s),) + tuple(sp.sin(t * s) * a[k] / s for k in range(3))
    p = sp.symbols("p0:4", real=True)
    lhs = [sp.diff(c, t) for c in qmul(E, p)]
    rhs = qmul(im(a), qmul(E, p))
    check("d/dt exp(t v) p = v exp(t v) p", zero([lhs[k] - rhs[k] for k in range(4)]))
    check("|exp(v)| = 1", sp.simplify(sum(c**2 for c in E) - 1) == 0)


def _symbols_field():
    X = sp.Matrix(sp.symbols("X1:4", real=True))
    Y = sp.Matrix(sp.symbols("Y1:4", real=True))
    g = sp.Matrix(sp.symbols("g1:4", real=True))
    hs = sp.symbols("h11 h12 h13 h22 h23 h33", real=True)
    H = sp.Matrix([[hs[0], hs[1], hs[2]], [hs[1], hs[3], hs[4]], [hs[2], hs[4], hs[5]]])
    return X, Y, g, H


def part3():
    print("3. integrability of e^u psi-bar X psi when d psi(X) = -1/2 (grad u x X) psi")
    X, Y, g, _ = _symbols_field()
    psi = sp.symbols("s0:4", real=True)

    def dpsi(V):
        return qmul(im(-g.cross(V) / 2), psi)

    # omega(Y) = psi-bar Y psi (Y constant); d(e^u omega)(X, Y) = e^u (du(X) w(Y) - du(Y) w(X) + X w(Y) - Y w(X))
    def omega(V):
        return qmul(qconj(psi), qmul(im(V), psi))

    def d_omega(V, W):  # derivative of omega(W) in direction V
        dp = dpsi(V)
        return [a + b for a, b in zip(qmul(qconj(dp), qmul(im(W), psi)), qmul(qconj(psi), qmul(im(W), dp)))]

    terms = [g.dot(X) * omega(Y)[k] - g.dot(Y) * omega(X)[k] + d_omega(X, Y)[k] - d_omega(Y, X)[k]
             for k in range(4)]
    check("d(e^u psi-bar dx psi) = 0", zero([sp.expand(t) for t in terms]))
    # the opposite sign of the connection is not integrable
    def dpsi_wrong(V):
        return qmul(im(g.cross(V) / 2), psi)
    def d_omega_wrong(V, W):
        dp = dpsi_wrong(V)
        return [a + b for a, b in zip(qmul(qconj(dp), qmul(im(W), psi)), qmul(qconj(psi), qmul(im(W), dp)))]
    wrong = [g.dot(X) * omega(Y)[k] - g.dot(Y) * omega(X)[k] + d_omega_wrong(X, Y)[k] - d_omega_wrong(Y, X)[k]
             for k in range(4)]
    check("... and with +1/2 (grad u x X) it is not", not zero([sp.expand(t) for t in wrong]))


def curvature(g, H, X, Y):
    return ((H * X).cross(Y) - (H * Y).cross(X)) / 2 + g * g.dot(X.cross(Y)) / 2


def part4():
    print("4. curvature F = dA + [A, A]; flat for u = log(R^2/|x-a|^2)")
    X, Y, _, _ = _symbols_field()
    xs = sp.Matrix(sp.symbols("x1:4", real=True))
    # F(X,Y) from the definition, for a concrete generic quadratic+cubic u (exact polynomial)
    c = sp.symbols("c0:20", real=True)
    mons = [m for m in sp.itermonomials(list(xs), 3) if m != 1][:19]
    u = sum(ci * m for ci, m in zip(c, mons))
    gx = sp.Matrix([sp.diff(u, v) for v in xs])

    def A(V):
        return im(gx.cross(V) / 2)

    def dA(V, W):  # directional derivative of A(W) along V
        return im(sp.Matrix([sum(sp.diff(comp, xs[m]) * V[m] for m in range(3)) for comp in gx]).cross(W) / 2)

    F_def = [dA(X, Y)[k] - dA(Y, X)[k] + qmul(A(X), A(Y))[k] - qmul(A(Y), A(X))[k] for k in range(4)]
    Hx = sp.hessian(u, list(xs))
    F_closed = im(curvature(gx, Hx, X, Y))
    check("F(X,Y) = 1/2((HX)xY - (HY)xX) + 1/2 g (g.(X x Y))", zero([sp.expand(F_def[k] - F_closed[k])
                                                                     for k in range(4)]))
    a = sp.Matrix(sp.symbols("a1:4", real=True))
    R = sp.symbols("R", positive=True)
    r = xs - a
    um = sp.log(R**2 / r.dot(r))
    gm = sp.Matrix([sp.diff(um, v) for v in xs])
    Hm = sp.hessian(um, list(xs))
    check("grad log(R^2/|r|^2) = -2 r/|r|^2", zero(list(gm + 2 * r / r.dot(r))))
    check("F = 0 for the Moebius factor", zero(list(sp.simplify(curvature(gm, Hm, X, Y)))))
    return gm


def part5():
    print("5. Moebius map f = S_n o inversion: df(X) = e^u phi-bar X phi, phi = r-hat n parallel")
    # f depends on x only through r = x - a (a shifts f by a constant), so differentiate in r.
    r = sp.Matrix(sp.symbols("r1:4", real=True))
    n = sp.Matrix(sp.symbols("n1:4", real=True))
    R = sp.symbols("R", positive=True)
    X = sp.Matrix(sp.symbols("X1:4", real=True))
    rr, nn = r.dot(r), n.dot(n)
    inv = R**2 * r / rr
    f = inv - 2 * n * n.dot(inv) / nn  # reflection in the plane normal to n
    df = f.jacobian(r) * X
    # phi = (r/|r|)(n/|n|): phi-bar X phi = (r n)-bar X (r n) / (rr nn), no square roots
    rn = qmul(im(r), im(n))
    target = [c / (rr * nn) for c in qmul(qconj(rn), qmul(im(X), rn))]
    eu = R**2 / rr
    check("df(X) = e^u phi-bar X phi", zero([sp.cancel(sp.together(df[k] - eu * target[k + 1])) for k in range(3)])
          and sp.expand(target[0]) == 0)
    check("|phi|^2 = |r|^2 |n|^2 / (rr nn) = 1", sp.expand(sum(c**2 for c in rn) - rr * nn) == 0)
    # d phi(X) = -1/2 (g x X) phi with g = -2 r/rr, multiplied by |r|^3 |n| (n constant):
    #   d(r/|r|)(X) |r|^3 = X rr - r (r.X)   and   -1/2 (g x X) phi |r|^3 |n| = (r x X) r n
    lhs = qmul(im(X * rr - r * r.dot(X)), im(n))
    rhs = qmul(im(r.cross(X)), qmul(im(r), im(n)))
    check("d phi(X) = -1/2 (grad u x X) phi", zero([sp.expand(lhs[k] - rhs[k]) for k in range(4)]))
    J = f.jacobian(r)
    check("det df = e^{3u} > 0 (orientation preserving)", sp.cancel(sp.together(J.det() - eu**3)) == 0)


def _qexp_series(v, h, order):
    """The exponential of an imaginary quaternion v (components polynomials in h with v = O(h)), up to h^order."""
    out = (sp.Integer(1), 0, 0, 0)
    term = (sp.Integer(1), 0, 0, 0)
    for k in range(1, order + 1):
        term = tuple(sp.expand(c / k) for c in qmul(term, im(v)))
        out = tuple(sp.expand(o + t) for o, t in zip(out, term))
    return tuple(sp.series(c, h, 0, order + 1).removeO() for c in out)


def part6():
    print("6. triangle holonomy of eta = exp(-1/2 g(mid) x e) = 1 - 1/2 F(x_j - x_i, x_k - x_i) + O(h^3)")
    h = sp.symbols("h", positive=True)
    g0 = sp.Matrix(sp.symbols("g1:4", real=True))
    hs = sp.symbols("h11 h12 h13 h22 h23 h33", real=True)
    H = sp.Matrix([[hs[0], hs[1], hs[2]], [hs[1], hs[3], hs[4]], [hs[2], hs[4], hs[5]]])
    # a generic third-derivative tensor enters g at O(h^2): take it as free symbols T[i](d, d)
    T = [sp.Matrix(3, 3, lambda r, s, i=i: sp.Symbol(f"t{i}{min(r, s)}{max(r, s)}", real=True)) for i in range(3)]

    def grad(d):  # grad u at c + d, to second order
        return g0 + H * d + sp.Matrix([(d.T * T[i] * d)[0] / 2 for i in range(3)])

    pa = sp.Matrix([sp.Rational(1, 3), sp.Rational(-1, 5), sp.Rational(2, 7)])
    pb = sp.Matrix([sp.Rational(3, 4), sp.Rational(1, 6), sp.Rational(-1, 2)])
    pd = sp.Matrix([sp.Rational(-1, 8), sp.Rational(5, 6), sp.Rational(1, 3)])
    P = [h * pa, h * pb, h * pd]

    def eta(i, j):
        e = P[j] - P[i]
        return _qexp_series(-grad((P[i] + P[j]) / 2).cross(e) / 2, h, 2)

    hol = qmul(eta(2, 0), qmul(eta(1, 2), eta(0, 1)))
    hol = [sp.expand(sp.series(c, h, 0, 3).removeO()) for c in hol]
    F = curvature(g0, H, P[1] - P[0], P[2] - P[0])
    expected = (sp.Integer(1),) + tuple(-F[k] / 2 for k in range(3))
    check("holonomy = 1 - 1/2 F(x_j - x_i, x_k - x_i) + O(h^3)", zero([sp.expand(hol[k] - expected[k])
                                                                        for k in range(4)]))
    check("(and not 1 + 1/2 F)", not zero([sp.expand(hol[k] - (2 if k == 0 else 0) + expected[k])
                                           for k in range(1, 4)]))


def part7():
    print("7. point charges: grad sum q/|x - a| = -sum q (x - a)/|x - a|^3")
    xs = sp.Matrix(sp.symbols("x1:4", real=True))
    a = sp.Matrix(sp.symbols("a1:4", real=True))
    q = sp.symbols("q", real=True)
    r = xs - a
    u = q / sp.sqrt(r.dot(r))
    grad = sp.Matrix([sp.diff(u, v) for v in xs])
    check("grad q/|r| = -q r/|r|^3", zero(list(grad + q * r / r.dot(r) ** sp.Rational(3, 2))))
    hess = sp.hessian(u, list(xs))
    closed = q * (3 * r * r.T / r.dot(r) ** sp.Rational(5, 2) - sp.eye(3) / r.dot(r) ** sp.Rational(3, 2))
    check("Hess q/|r| = q (3 r r^T/|r|^5 - I/|r|^3)", zero(list(hess - closed)))


def part8():
    print("8. normal equations of the least-squares map")
    f = sp.symbols("f0:4", real=True)
    edges = [(0, 1), (1, 2), (0, 2), (2, 3), (1, 3)]
    w = sp.symbols("w0:5", real=True)
    E = sp.symbols("E0:5", real=True)
    energy = sum(wi * (f[j] - f[i] - Ei) ** 2 for wi, (i, j), Ei in zip(w, edges, E))
    D0 = sp.zeros(5, 4)
    for e, (i, j) in enumerate(edges):
        D0[e, i], D0[e, j] = -1, 1
    W = sp.diag(*w)
    grad = sp.Matrix([sp.diff(energy, v) for v in f])
    check("grad = 2 (D0^T W D0 f - D0^T W E)", zero(list(sp.expand(grad - 2 * (D0.T * W * D0 * sp.Matrix(f)
                                                                                - D0.T * W * sp.Matrix(E))))))


def compare_with_code():
    print("9. dhlb.conformal against the closed forms (random data)")
    import numpy as np

    from dhlb.conformal.factors import mobius_factor, point_charge_factor
    from dhlb.conformal.quaternion import qexp, su2_matrix, to_c2
    from dhlb.conformal.quaternion import qmul as cmul

    rng = np.random.default_rng(1)
    p, q = rng.standard_normal((2, 50, 4))
    err = 0.0
    for k in range(50):
        ref = [float(v) for v in qmul(tuple(sp.Float(t) for t in p[k]), tuple(sp.Float(t) for t in q[k]))]
        err = max(err, float(np.abs(cmul(p[k], q[k]) - ref).max()))
    check(f"qmul = Hamilton product (max err {err:.1e})", err < 1e-13)
    err = float(np.abs(np.einsum("kab,kb->ka", su2_matrix(p), to_c2(q)) - to_c2(cmul(p, q))).max())
    check(f"su2_matrix(p) to_c2(q) = to_c2(p q) (max err {err:.1e})", err < 1e-13)
    v = rng.standard_normal((50, 3))
    ex = qexp(np.c_[np.zeros(50), v])
    t = np.linalg.norm(v, axis=1)
    err = float(np.abs(ex - np.c_[np.cos(t), np.sin(t)[:, None] * v / t[:, None]]).max())
    check(f"qexp of imaginary = cos|v| + sin|v| v/|v| (max err {err:.1e})", err < 1e-14)
    x = rng.standard_normal((20, 3)) + 5
    a, R = np.array([0.3, -0.2, 0.1]), 1.7
    m = mobius_factor(a, R)
    r = x - a
    err = max(float(np.abs(m(x) - np.log(R**2 / (r**2).sum(1))).max()),
              float(np.abs(m.gradient(x) + 2 * r / (r**2).sum(1)[:, None]).max()))
    check(f"mobius_factor value and gradient (max err {err:.1e})", err < 1e-13)
    pc = point_charge_factor([[0.3, -0.2, 0.1, 2.0], [1.0, 1.0, 0.0, -0.5]])
    ref = sum(qq / np.linalg.norm(x - c, axis=1) for c, qq in [((0.3, -0.2, 0.1), 2.0), ((1.0, 1.0, 0.0), -0.5)])
    refg = sum(-qq * (x - c) / np.linalg.norm(x - c, axis=1)[:, None] ** 3
               for c, qq in [(np.array((0.3, -0.2, 0.1)), 2.0), (np.array((1.0, 1.0, 0.0)), -0.5)])
    err = max(float(np.abs(pc(x) - ref).max()), float(np.abs(pc.gradient(x) - refg).max()))
    check(f"point_charge_factor value and gradient (max err {err:.1e})", err < 1e-13)


if __name__ == "__main__":
    part1()
    part2()
    part3()
    part4()
    part5()
    part6()
    part7()
    part8()
    compare_with_code()
    print("derive_conformal_quaternion: all identities hold")
