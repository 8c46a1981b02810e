r"""The moment functions of the fast local matrices: ``exp[0^α, z_c^β(, z_d^γ)]`` at imaginary nodes.

Used by :mod:`dhlb.fem.kernels_closed` (which states the reduction of the local matrices to these
functions).  Nodes are ``z_c = -iA_c`` for real ``A_c`` (the curvatures ``Ω_abc``).

* ``ρ = max |A_c| <= 4``: the Taylor series ``Σ_q h_q(nodes) / (q + N)!`` with exact
  coefficients (real parts: even q, imaginary parts: odd q); the degree is chosen per element
  from its ρ (rounded up to a power of 2^(1/4)) so that the tail is below 1e-17 of the leading
  term, and the products are padded to a fixed column multiple: an element's value does not depend
  on the batch it is computed in.  Low degree: one
  matrix product with the monomials ``A1^j A2^k``; high degree (ρ >~ 0.4): the six families of
  complete homogeneous sums ``h_q^{(β,γ)}`` by their recurrences in q, then small products.
* ``ρ > 4``: the recurrence ``z F(α, β, γ) = F(α-1, β, γ) - F(α, β-1, γ)`` upwards from
  ``F(α, 0, γ) = exp[0^α, z_d^γ]`` and ``F(0, β, γ) = e^{z_c} exp[0^β, (z_d - z_c)^γ]`` (1-D
  functions: Taylor for ``|A| <= 4``, the 1-D recurrence beyond), dividing by the larger node.
  Its rounding error grows like ``N!/ρ^N``; at ``ρ = 4`` it is about 1e-14 for ``N <= 7`` (3e-14
  at ``ρ = 3``, hence the Taylor radius 4, where the series needs degree 30).

Relative accuracy against 40-digit mpmath: below 1e-14 for every real A
(``tests/test_fem_fast_local.py``).
"""

from __future__ import annotations

import itertools
from functools import cache
from math import comb, factorial

import numpy as np

__all__ = ["PAT3", "moments_3d", "phi_2d"]

_R = 4.0            # Taylor radius (1-D and 2-D); recurrence beyond
_TINY = 0.25        # rows with ρ <= _TINY get their own (short) series
_TAIL = 1e-17       # relative truncation error of the series
_H_MIN_DEGREE = 12  # above: complete homogeneous sums, below: monomials

# --------------------------------------------------------------------------- series tables


def _compositions(q: int, k: int):
    if k == 1:
        yield (q,)
        return
    for j in range(q + 1):
        for rest in _compositions(q - j, k - 1):
            yield (j,) + rest


def _f_poly(a: int, mus: tuple, qmax: int, weight=1.0, shift: int = 0) -> dict:
    """``weight A_1^shift exp[0^a, (-iA_1)^{μ_1}, ...]`` as {exponents: coefficient} up to degree qmax.

    ``h_q`` of the nodes is ``Σ_{|k| = q} Π C(k_c + μ_c - 1, μ_c - 1) (-iA_c)^{k_c}``.
    """
    out = {}
    for q in range(qmax + 1):
        for ks in _compositions(q, len(mus)):
            c = weight * (-1j) ** q / factorial(q + a + sum(mus) - 1)
            for mu, k in zip(mus, ks):
                c *= comb(k + mu - 1, mu - 1)
            out[(ks[0] + shift,) + ks[1:]] = c
    return out


def _add(p: dict, q: dict) -> dict:
    out = dict(p)
    for k, c in q.items():
        out[k] = out.get(k, 0) + c
    return out


def _degree(profiles: tuple, r: float) -> int:
    """Smallest Q: the terms of degree > Q sum to at most _TAIL times the lowest-order term (|A| <= r).

    ``profiles``: :func:`_profiles` of the polynomials.
    """
    best = 1
    for d0, per in profiles:
        rel = per * r ** np.arange(per.size)
        tail = np.cumsum(rel[::-1])[::-1]              # tail[j] = Σ_{deg >= d0 + j}
        ok = np.nonzero(tail <= _TAIL)[0]
        assert ok.size and rel[-1] < 1e-30, "series table too short for this radius"
        best = max(best, d0 + int(ok[0]) - 1)
    return best


def _profiles(polys: tuple) -> tuple:
    """Per polynomial: its lowest degree d0 and the sums of |coefficients| per degree from d0, relative to d0's."""
    out = []
    for p in polys:
        degrees = np.fromiter((sum(k) for k in p), np.int64, len(p))
        per = np.bincount(degrees, weights=np.abs(np.fromiter(p.values(), np.complex128, len(p))))
        d0 = int(np.nonzero(per)[0][0])
        out.append((d0, per[d0:] / per[d0]))
    return tuple(out)


@cache
def _even_odd_1d(key: tuple, q: int) -> np.ndarray:
    """``(2F, q+1)`` for the 1-D polynomials of ``key``: real parts in powers of A², imag parts / A."""
    polys = _polys_1d(key)
    out = np.zeros((2 * len(polys), q + 1))
    for f, p in enumerate(polys):
        for (k,), c in p.items():
            if k // 2 <= q:
                out[f + (k % 2) * len(polys), k // 2] = c.real if k % 2 == 0 else c.imag
    return out


@cache
def _polys_1d(key: tuple) -> tuple:
    """key: tuple of functions, each a tuple of terms (weight, shift, α, β)."""
    out = []
    for terms in key:
        p = {}
        for wgt, shift, a, b in terms:
            p = _add(p, _f_poly(a, (b,), 50, wgt, shift))
        out.append(p)
    return tuple(out)


@cache
def _degree_1d(key: tuple, r: float) -> int:
    return _degree(_profiles_1d(key), r) // 2 + 1


@cache
def _profiles_1d(key: tuple) -> tuple:
    return _profiles(_polys_1d(key))


def _per_degree(rho: np.ndarray, degree, fn, rows: int):
    """``fn(idx, q)`` for each group of elements whose series degree ``q = degree(r)`` is the same.

    ``r`` is the radius ``rho`` of the element rounded up to a power of 2^(1/4) (a bounded set of
    cached degrees). Every element gets the degree of its *own* radius, not that of the batch it is
    computed in, and its columns are computed by :func:`_padded` products: so the value of an element
    does not depend on which other elements are computed with it (a rank of an MPI run assembles a part
    of the mesh and must get the serial assembly's values bit for bit). Returns the real and imaginary
    parts ``(rows, len(rho))``.
    """
    keys = np.ceil(4 * np.log2(np.maximum(rho, 1e-12))).astype(np.int64)
    uk, inv = np.unique(keys, return_inverse=True)
    q_of = np.array([degree(float(2.0 ** (k / 4))) for k in uk], np.int64)
    deg = q_of[inv]
    if q_of.min(initial=0) == q_of.max(initial=0):
        return fn(slice(None), int(q_of.max(initial=1)))
    order = np.argsort(deg, kind="stable")
    sd = deg[order]
    cuts = np.r_[0, np.nonzero(sd[1:] != sd[:-1])[0] + 1, sd.size]
    re, im = np.empty((rows, rho.size)), np.empty((rows, rho.size))
    for a, b in itertools.pairwise(cuts):
        idx = order[a:b]
        re[:, idx], im[:, idx] = fn(idx, int(sd[a]))
    return re, im


_BLOCK = 64  # column count multiple of every product (see _padded)


def _padded(*arrays: np.ndarray) -> tuple:
    """The arrays with zeros appended to a length that is a multiple of :data:`_BLOCK`.

    A BLAS product ``C @ B`` computes the last ``K mod 8`` (or 16, …) columns of ``B`` by another
    kernel than the others, which rounds differently (OpenBLAS: in the last bit): with a column count
    that is a multiple of 64 every column takes the same path, so a column's result does not depend on
    its position or on the number of columns.
    """
    K = arrays[0].size
    pad = -K % _BLOCK
    if not pad:
        return arrays
    return tuple(np.concatenate([a, np.zeros(pad, a.dtype)]) for a in arrays)


def _series_1d(key: tuple, A: np.ndarray):
    """Real and imaginary parts ``(F, len(A))`` of the 1-D functions of ``key`` at ``A``, |A| <= _R."""
    return _per_degree(np.abs(A), lambda r: _degree_1d(key, r), lambda idx, q: _series_1d_at(key, A[idx], q),
                       len(key))


def _series_1d_at(key: tuple, A: np.ndarray, q: int):
    K = A.size
    (A,) = _padded(A)
    pw = np.empty((q + 1, A.size))
    pw[0] = 1.0
    a2 = A * A
    for k in range(1, q + 1):
        np.multiply(pw[k - 1], a2, out=pw[k])
    y = _even_odd_1d(key, q) @ pw
    nf = len(key)
    return y[:nf, :K], (y[nf:] * A)[:, :K]


# 3-D: the ten weighted moments (weight, α, β, γ) = weight · exp[0^α, z_c^β, z_d^γ].
PAT3 = ((6.0, 2, 1, 1), (6.0, 4, 1, 1), (6.0, 3, 2, 1), (6.0, 3, 1, 2), (24.0, 6, 1, 1),
        (12.0, 5, 2, 1), (12.0, 5, 1, 2), (12.0, 4, 3, 1), (12.0, 4, 1, 3), (6.0, 4, 2, 2))


@cache
def _polys_3d() -> tuple:
    return tuple(_f_poly(a, (b, c), 45, w) for w, a, b, c in PAT3)


@cache
def _matrix_3d(q: int):
    """Monomials ``(j, k)`` of even / odd degree <= q and the (10, ·) real coefficient matrices."""
    even = [(j, d - j) for d in range(0, q + 1, 2) for j in range(d + 1)]
    odd = [(j, d - j) for d in range(1, q + 1, 2) for j in range(d + 1)]
    ce = np.array([[p[k].real for k in even] for p in _polys_3d()])
    co = np.array([[p[k].imag for k in odd] for p in _polys_3d()])
    return even, odd, ce, co


@cache
def _degree_3d(r: float) -> int:
    return _degree(_profiles_3d(), r)


@cache
def _profiles_3d() -> tuple:
    return _profiles(_polys_3d())


# families (β, γ) of the complete homogeneous sums h_q^{(β,γ)}(A1, A2) =
# Σ_{j+k=q} C(j+β-1, β-1) C(k+γ-1, γ-1) A1^j A2^k; the moment (w, α, β, γ) is
# w Σ_q (-i)^q h_q^{(β,γ)} / (q + N)!.  Built by h^{(1,1)}_q = A1 h^{(1,1)}_{q-1} + A2^q and
# h^{(β+1,γ)}_q = h^{(β,γ)}_q + A1 h^{(β+1,γ)}_{q-1} (A2 for γ + 1): cheaper than the monomials at high degree.
_FAMS = ((1, 1), (2, 1), (1, 2), (3, 1), (2, 2), (1, 3))
_PARENT = (1, 1, 2)           # parents of (3, 1), (2, 2), (1, 3) among _FAMS


@cache
def _family_matrices(q: int) -> tuple:
    """Per family: (pattern indices, (2·n_pat, q+1) real / imaginary coefficient rows)."""
    out = []
    for fam in _FAMS:
        pats = [f for f, (_, _, b, c) in enumerate(PAT3) if (b, c) == fam]
        cm = np.zeros((2 * len(pats), q + 1))
        for i, f in enumerate(pats):
            w, a, b, c = PAT3[f]
            for k in range(q + 1):
                v = w / factorial(k + a + b + c - 1) * (-1) ** (k // 2)
                cm[i + (k % 2) * len(pats), k] = v if k % 2 == 0 else -v
        out.append((pats, cm))
    return tuple(out)


def _series_3d_h(A1: np.ndarray, A2: np.ndarray, q: int):
    K = A1.size
    h = np.empty((6, q + 1, K))
    h[:, 0] = 1.0
    yp = np.ones(K)
    x2, x3 = np.stack([A1, A2]), np.stack([A1, A2, A2])
    for k in range(1, q + 1):
        yp *= A2
        np.multiply(A1, h[0, k - 1], out=h[0, k])
        h[0, k] += yp
        np.multiply(x2, h[1:3, k - 1], out=h[1:3, k])
        h[1:3, k] += h[0, k]
        np.multiply(x3, h[3:6, k - 1], out=h[3:6, k])
        h[3:6, k] += h[_PARENT, k]
    re, im = np.empty((10, K)), np.empty((10, K))
    for fam, (pats, cm) in enumerate(_family_matrices(q)):
        y = cm @ h[fam]
        re[pats], im[pats] = y[: len(pats)], y[len(pats):]
    return re, im


def _series_3d(A1: np.ndarray, A2: np.ndarray, pats: tuple):
    rho = np.maximum(np.abs(A1), np.abs(A2))
    return _per_degree(rho, _degree_3d, lambda idx, q: _series_3d_at(A1[idx], A2[idx], pats, q), len(pats))


def _series_3d_at(A1: np.ndarray, A2: np.ndarray, pats: tuple, deg: int):
    K = A1.size
    A1, A2 = _padded(A1, A2)
    if deg > _H_MIN_DEGREE:
        re, im = np.empty((10, A1.size)), np.empty((10, A1.size))
        for s in range(0, A1.size, 4096):   # chunks of a multiple of _BLOCK columns
            re[:, s: s + 4096], im[:, s: s + 4096] = _series_3d_h(A1[s: s + 4096], A2[s: s + 4096], deg)
        return re[list(pats), :K], im[list(pats), :K]
    even, odd, ce, co = _matrix_3d(deg)
    ce, co = ce[list(pats)], co[list(pats)]
    q = max(sum(k) for k in even + odd)
    bufs = (np.empty((len(even), A1.size)), np.empty((len(odd), A1.size)))
    bufs[0][0] = 1.0
    start, prev = [1, 0], bufs[0][0:1]
    for d in range(1, q + 1):                # degree d rows (j, d - j), j = 0..d: A2 · degree d-1, then A1^d
        buf, s0 = bufs[d % 2], start[d % 2]
        cur = buf[s0: s0 + d + 1]
        np.multiply(prev, A2, out=cur[:d])
        np.multiply(prev[d - 1], A1, out=cur[d])
        start[d % 2] += d + 1
        prev = cur
    return (ce @ bufs[0])[:, :K], (co @ bufs[1])[:, :K]


# --------------------------------------------------------------------------- large phases


def _e_table(A: np.ndarray, need: tuple) -> dict:
    """``exp[0^α, (-iA)^β]`` for every ``(α, β)`` in ``need``, accurate for every real A."""
    out = {k: np.empty(A.shape, dtype=complex) for k in need}
    small = np.abs(A) <= _R
    if small.any():
        re, im = _series_1d(tuple(((1.0, 0, a, b),) for a, b in need), A[small])
        for f, key in enumerate(need):
            out[key][small] = re[f] + 1j * im[f]
    if not small.all():
        t = _recurrence(-1j * A[~small], max(a for a, _ in need), max(b for _, b in need))
        for key in need:
            out[key][~small] = t[key]
    return out


def _recurrence(z: np.ndarray, amax: int, bmax: int) -> dict:
    """``exp[0^α, z^β]`` by ``z F(α, β) = F(α-1, β) - F(α, β-1)`` (stable for |z| > _R)."""
    t, ez, iz = {}, np.exp(z), 1.0 / z
    for b in range(1, bmax + 1):
        t[0, b] = ez / factorial(b - 1)
    for a in range(1, amax + 1):
        t[a, 0] = 1.0 / factorial(a - 1)
        for b in range(1, bmax + 1):
            t[a, b] = (t[a - 1, b] - t[a, b - 1]) * iz
    return t


_NEED_Y = tuple((a, g) for a in range(1, 7) for g in range(1, 4) if a + g <= 7)
_NEED_D = tuple((b, g) for b in range(1, 4) for g in range(1, 4) if b + g <= 4)


def _large_3d(A1: np.ndarray, A2: np.ndarray, pats: tuple):
    """The ten weighted moments for pairs with max(|A1|, |A2|) > _R (recurrence in the larger node)."""
    swap = np.abs(A2) > np.abs(A1)
    U, V = np.where(swap, A2, A1), np.where(swap, A1, A2)
    z = -1j * U
    ez, iz = np.exp(z), 1.0 / z
    ey = _e_table(V, _NEED_Y)                                  # F(α, 0, γ) = exp[0^α, y^γ]
    ed = _e_table(V - U, _NEED_D)                              # exp[0^β, (y - z)^γ]
    t = {}
    for a in range(1, 7):
        t[a, 0, 0] = 1.0 / factorial(a - 1)
        for g in range(1, 4):
            if (a, g) in ey:
                t[a, 0, g] = ey[a, g]
    for b in range(1, 4):
        t[0, b, 0] = ez / factorial(b - 1)
        for g in range(1, 4):
            if (b, g) in ed:
                t[0, b, g] = ez * ed[b, g]
    for a in range(1, 7):
        for b in range(1, 4):
            for g in range(4):
                if a + b + g <= 8 and b + g <= 4:
                    t[a, b, g] = (t[a - 1, b, g] - t[a, b - 1, g]) * iz
    re, im = np.empty((len(pats), U.size)), np.empty((len(pats), U.size))
    for i, f in enumerate(pats):
        w, a, b, g = PAT3[f]
        v = w * np.where(swap, t[a, g, b], t[a, b, g])
        re[i], im[i] = v.real, v.imag
    return re, im


def moments_3d(A1: np.ndarray, A2: np.ndarray, pats: tuple = tuple(range(10))):
    """Real and imaginary parts (len(pats), K) of the weighted moments ``PAT3[f]``, ``f`` in ``pats``."""
    rho = np.maximum(np.abs(A1), np.abs(A2))
    if rho.max(initial=0.0) <= _TINY:
        return _series_3d(A1, A2, pats)
    re, im = np.empty((len(pats), A1.size)), np.empty((len(pats), A1.size))
    classes = (rho <= _TINY, (rho > _TINY) & (rho <= _R), rho > _R)
    for c, mask in enumerate(classes):
        idx = np.nonzero(mask)[0]
        if idx.size:
            fn = _large_3d if c == 2 else _series_3d
            re[:, idx], im[:, idx] = fn(A1[idx], A2[idx], pats)
    return re, im


# 2-D: φ_k(w), w = Ω_abc: φ0 = Θ_ab(a, b) (mass), and A[b, a]/(r vol) = G_ab φ1 + (G_ac + G_bc) φ2
# + (G_aa + G_bb) φ3 + G_cc φ4.  Terms (weight, power of w, α, β) of weight w^s exp[0^α, (-iw)^β].
_PHI = (((2.0, 0, 4, 1),), ((2.0, 0, 2, 1), (-4.0, 2, 4, 3)), ((4.0, 2, 5, 2), (-2j, 1, 4, 1)),
        ((2j, 1, 3, 2),), ((-8.0, 2, 6, 1),))


def phi_2d(w: np.ndarray, funcs: tuple = (0, 1, 2, 3, 4)):
    """Real and imaginary parts (len(funcs), m) of φ_f at w for f in ``funcs``."""
    key = tuple(_PHI[f] for f in funcs)
    small = np.abs(w) <= _R
    if small.all():
        return _series_1d(key, w)
    re, im = np.empty((len(key), w.size)), np.empty((len(key), w.size))
    if small.any():
        re[:, small], im[:, small] = _series_1d(key, w[small])
    wb = w[~small]
    e = _e_table(wb, ((4, 1), (2, 1), (4, 3), (5, 2), (3, 2), (6, 1)))
    for f, terms in enumerate(key):
        v = sum(wgt * wb ** s * e[a, b] for wgt, s, a, b in terms)
        re[f, ~small], im[f, ~small] = v.real, v.imag
    return re, im


